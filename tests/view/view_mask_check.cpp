// Compares the viewer's screenshots with render's PNGs by coverage (alpha >= 128, contract).
//   view_mask_check same A.png B.png MAX_DIFF
//       the masks differ in at most MAX_DIFF pixels
//   view_mask_check split SPLIT.png LEFT.png RIGHT.png DIVIDER MAX_DIFF MIN_EXTRA
//       columns left of round(DIVIDER * width) match LEFT's mask, the rest RIGHT's (at most MAX_DIFF
//       pixels differ), and the right half holds at least MIN_EXTRA pixels that RIGHT covers and
//       LEFT does not (the split view shows where the two silhouettes differ)
//   view_mask_check divider SHOT.png COLUMN
//       column COLUMN of a --screenshot-ui is white from top to bottom (the split view's divider
//       line), and no other column is
//   view_mask_check rgb A.png B.png MIN_CHANGED
//       same masks, and at least MIN_CHANGED pixels whose colour differs (overlays)
//   view_mask_check binary A.png
//       alpha is coverage: every pixel 0 or 255, and some covered
//   view_mask_check equal A.png B.png MAX_DIFF
//       at most MAX_DIFF pixels differ in any channel (colour or alpha)
//   view_mask_check scaled VIEW.png LEFT.png RIGHT.png DIVIDER MAX_DIFF
//       VIEW is LEFT and RIGHT (render's images at the renderer's size, --render-scale) scaled
//       up with nearest filtering, one scale for the whole image: view pixel X shows renderer
//       column floor((X + 0.5) * w / W) (rows likewise), of LEFT left of column
//       round(DIVIDER * w), of RIGHT from it on. At most MAX_DIFF pixels differ in any channel.
// Exit 0 when the check holds; prints the counts either way.
#include "core/image.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

namespace {

bool covered(const pr::RgbaImage& img, int x, int y) { return img.at(x, y).a >= 128; }

bool same_size(const pr::RgbaImage& a, const pr::RgbaImage& b)
{
    if (a.width == b.width && a.height == b.height) return true;
    std::printf("size differs: %dx%d against %dx%d\n", a.width, a.height, b.width, b.height);
    return false;
}

} // namespace

int main(int argc, char** argv)
{
    try {
        const std::string mode = argc > 1 ? argv[1] : "";
        if (mode == "same" && argc == 5) {
            const auto a = pr::read_rgba(argv[2]), b = pr::read_rgba(argv[3]);
            if (!same_size(a, b)) return 1;
            long diff = 0, cov = 0;
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x) {
                    diff += covered(a, x, y) != covered(b, x, y);
                    cov += covered(a, x, y);
                }
            std::printf("same: %ld pixels covered, %ld differ (max %s)\n", cov, diff, argv[4]);
            return cov > 0 && diff <= std::atol(argv[4]) ? 0 : 1;
        }
        if (mode == "equal" && argc == 5) {
            const auto a = pr::read_rgba(argv[2]), b = pr::read_rgba(argv[3]);
            if (!same_size(a, b)) return 1;
            long diff = 0;
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x) {
                    const auto p = a.at(x, y), q = b.at(x, y);
                    diff += p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a;
                }
            std::printf("equal: %ld pixels differ (max %s)\n", diff, argv[4]);
            return diff <= std::atol(argv[4]) ? 0 : 1;
        }
        if (mode == "scaled" && argc == 7) {
            const auto v = pr::read_rgba(argv[2]), l = pr::read_rgba(argv[3]), r = pr::read_rgba(argv[4]);
            if (!same_size(l, r)) return 1;
            const int d = static_cast<int>(std::lround(std::atof(argv[5]) * l.width));
            // Pixel centres, in whole numbers: floor((2X + 1) * w / 2W). (read_rgba's rows are
            // bottom first, as GL's.)
            const auto source = [](int x, int from, int to) { return int((2LL * x + 1) * to / (2LL * from)); };
            long diff = 0, left_diff = 0;
            for (int y = 0; y < v.height; ++y)
                for (int x = 0; x < v.width; ++x) {
                    const int sx = source(x, v.width, l.width), sy = source(y, v.height, l.height);
                    const auto p = v.at(x, y), q = (sx < d ? l : r).at(sx, sy);
                    const bool differs = p.r != q.r || p.g != q.g || p.b != q.b || p.a != q.a;
                    diff += differs;
                    left_diff += differs && sx < d;
                }
            std::printf("scaled %dx%d from %dx%d, split at renderer column %d: %ld pixels differ (%ld left of "
                        "the split; max %s)\n",
                        v.width, v.height, l.width, l.height, d, diff, left_diff, argv[6]);
            return diff <= std::atol(argv[6]) ? 0 : 1;
        }
        if (mode == "binary" && argc == 3) {
            const auto a = pr::read_rgba(argv[2]);
            long partial = 0, cov = 0;
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x) {
                    partial += a.at(x, y).a != 0 && a.at(x, y).a != 255;
                    cov += a.at(x, y).a == 255;
                }
            std::printf("binary: %ld pixels covered, %ld with partial alpha (max 0)\n", cov, partial);
            return cov > 0 && partial == 0 ? 0 : 1;
        }
        if (mode == "split" && argc == 8) {
            const auto s = pr::read_rgba(argv[2]), l = pr::read_rgba(argv[3]), r = pr::read_rgba(argv[4]);
            if (!same_size(s, l) || !same_size(s, r)) return 1;
            const int x0 = static_cast<int>(std::lround(std::atof(argv[5]) * s.width));
            long diff = 0, extra = 0;
            for (int y = 0; y < s.height; ++y)
                for (int x = 0; x < s.width; ++x) {
                    const pr::RgbaImage& expect = x < x0 ? l : r;
                    diff += covered(s, x, y) != covered(expect, x, y);
                    if (x >= x0) extra += covered(s, x, y) && covered(r, x, y) && !covered(l, x, y);
                }
            std::printf("split at column %d: %ld pixels differ from the halves (max %s), right half covers "
                        "%ld pixels the left technique does not (min %s)\n",
                        x0, diff, argv[6], extra, argv[7]);
            return diff <= std::atol(argv[6]) && extra >= std::atol(argv[7]) ? 0 : 1;
        }
        if (mode == "divider" && argc == 4) {
            const auto a = pr::read_rgba(argv[2]);
            const int want = std::atoi(argv[3]);
            std::string white;
            bool found = false, others = false;
            for (int x = 0; x < a.width; ++x) {
                bool all = true;
                for (int y = 0; y < a.height && all; ++y) {
                    const auto p = a.at(x, y);
                    all = p.r == 255 && p.g == 255 && p.b == 255;
                }
                if (!all) continue;
                white += (white.empty() ? "" : " ") + std::to_string(x);
                (x == want ? found : others) = true;
            }
            std::printf("divider: white columns %s (expected %d alone)\n", white.empty() ? "none" : white.c_str(), want);
            return found && !others ? 0 : 1;
        }
        if (mode == "rgb" && argc == 5) {
            const auto a = pr::read_rgba(argv[2]), b = pr::read_rgba(argv[3]);
            if (!same_size(a, b)) return 1;
            long diff = 0, changed = 0;
            for (int y = 0; y < a.height; ++y)
                for (int x = 0; x < a.width; ++x) {
                    diff += covered(a, x, y) != covered(b, x, y);
                    const auto p = a.at(x, y), q = b.at(x, y);
                    changed += p.r != q.r || p.g != q.g || p.b != q.b;
                }
            std::printf("rgb: masks differ in %ld pixels (max 0), colour in %ld (min %s)\n", diff, changed, argv[4]);
            return diff == 0 && changed >= std::atol(argv[4]) ? 0 : 1;
        }
        std::fprintf(stderr, "usage: view_mask_check same|equal|scaled|split|divider|rgb|binary … (see the source)\n");
        return 2;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "view_mask_check: %s\n", e.what());
        return 1;
    }
}
