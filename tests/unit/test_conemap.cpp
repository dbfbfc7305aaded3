// Cone maps (maps/conemap): the pruned generator against brute force, conservativeness at texel
// centres, the relaxed property, rounding, PNG and cache round trips.
#include "core/error.hpp"
#include "maps/conemap.hpp"
#include "temp_dir.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <functional>
#include <limits>
#include <random>
#include <stdexcept>

using namespace pr;
namespace fs = std::filesystem;

namespace {

HeightField make(int w, int h, const std::function<float(int, int)>& f)
{
    HeightField hf;
    hf.width = w;
    hf.height = h;
    hf.bits = 16;
    hf.name = "test";
    hf.texels.resize(std::size_t(w) * std::size_t(h));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) hf.texels[std::size_t(y) * std::size_t(w) + std::size_t(x)] = f(x, y);
    return hf;
}

float q16(double v) { return float(std::round(std::clamp(v, 0.0, 1.0) * 65535.0) / 65535.0); }
// A height as an rg8 cone PNG's R channel holds it (write_cone_png rounds h * 255 in float).
float q8(float v) { return float(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)) / 255.0f; }

// The heights a map of `format` is built from and stores: rg8 keeps 8 bits, rg16 all 16.
HeightField stored_heights(const HeightField& f, ConeFormat format)
{
    HeightField s = f;
    if (format == ConeFormat::Rg8)
        for (float& t : s.texels) t = q8(t);
    return s;
}

HeightField random_map(int w, int h, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(0, 65535);
    return make(w, h, [&](int, int) { return float(d(rng)) / 65535.0f; });
}

// A smooth random map (sum of a few waves): long slopes, like real height maps.
HeightField smooth_map(int w, int h, unsigned seed)
{
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    double a[4], px[4], py[4];
    for (int i = 0; i < 4; ++i) a[i] = u(rng), px[i] = u(rng) * 6.28, py[i] = u(rng) * 6.28;
    return make(w, h, [&](int x, int y) {
        double s = 0;
        for (int i = 0; i < 4; ++i)
            s += a[i] * std::sin(6.2831853 * (i + 1) * x / w + px[i]) * std::cos(6.2831853 * (4 - i) * y / h + py[i]);
        return q16(0.5 + 0.2 * s);
    });
}

int wrapi(int i, int n) { return ((i % n) + n) % n; }
int signed_offset(int d, int n)
{
    d = wrapi(d, n);
    return 2 * d > n ? d - n : d;
}

double uv_distance(const HeightField& f, int dx, int dy)
{
    return std::sqrt(double(dx * dx) / (double(f.width) * f.width) + double(dy * dy) / (double(f.height) * f.height));
}

float texel(const HeightField& f, int x, int y) { return f.texels[std::size_t(y) * std::size_t(f.width) + std::size_t(x)]; }

// h_q - h_p as the map stores heights: whole 16-bit steps (an 8-bit step is 257 of them), exactly.
// (The difference of the float texels is off by up to 6e-8, 0.4 % of a one-step rise: the
// generator and these checks used it, and a map 1.1e-6 above the exact ratio passed them.)
double stored_rise(const HeightField& f, int qx, int qy, int px, int py)
{
    return double(std::int64_t(cone_height_steps(texel(f, qx, qy), ConeFormat::Rg16)) -
                  std::int64_t(cone_height_steps(texel(f, px, py), ConeFormat::Rg16))) /
           65535.0;
}

// O(n^2): every pair of texels.
std::vector<int> brute_force(const HeightField& f, ConeKind kind, ConeFormat format)
{
    std::vector<int> ks;
    for (int py = 0; py < f.height; ++py)
        for (int px = 0; px < f.width; ++px) {
            double c = 1.0;
            for (int qy = 0; qy < f.height; ++qy)
                for (int qx = 0; qx < f.width; ++qx) {
                    const int dx = signed_offset(qx - px, f.width), dy = signed_offset(qy - py, f.height);
                    const double dh = stored_rise(f, qx, qy, px, py);
                    if (!(dh > 0)) continue;
                    const double cone = uv_distance(f, dx, dy) / dh;
                    int budget = std::numeric_limits<int>::max();
                    const double v = kind == ConeKind::Cone
                                         ? cone
                                         : relaxed_constraint(f, px, py, dx, dy, std::numeric_limits<double>::infinity(),
                                                              budget, cone);
                    c = std::min(c, v);
                }
            ks.push_back(cone_ratio_steps(c, format));
        }
    return ks;
}

int steps_of(const ConeMap& m, std::size_t i, ConeFormat format)
{
    return int(std::lround(double(m.ratios[i]) * cone_format_steps(format)));
}

// No texel q with h_q > h_p lies strictly inside p's cone (stored, rounded ratio).
void expect_conservative(const HeightField& f, const ConeMap& m)
{
    int bad = 0;
    for (int py = 0; py < f.height; ++py)
        for (int px = 0; px < f.width; ++px) {
            const double r = m.ratios[std::size_t(py) * std::size_t(f.width) + std::size_t(px)];
            for (int qy = 0; qy < f.height; ++qy)
                for (int qx = 0; qx < f.width; ++qx) {
                    const double dh = stored_rise(f, qx, qy, px, py);
                    if (dh > 0 && uv_distance(f, signed_offset(qx - px, f.width), signed_offset(qy - py, f.height)) < r * r * dh)
                        ++bad;
                }
        }
    EXPECT_EQ(bad, 0) << f.name;
}

struct Case {
    std::string name;
    HeightField field;
};

std::vector<Case> cases()
{
    std::vector<Case> c;
    c.push_back({"random32", random_map(32, 32, 1)});
    c.push_back({"random48x24", random_map(48, 24, 2)});
    c.push_back({"smooth40x56", smooth_map(40, 56, 3)});
    c.push_back({"spike", make(33, 33, [](int x, int y) { return x == 7 && y == 20 ? 1.0f : 0.0f; })});
    c.push_back({"step", make(32, 32, [](int x, int) { return x < 16 ? 0.25f : 0.75f; })});
    c.push_back({"ramp", make(64, 8, [](int x, int) { return q16(x / 63.0); })});
    c.push_back({"steep_ramp", make(32, 32, [](int x, int y) { return q16(((x + y) % 8) / 7.0); })});
    c.push_back({"constant", make(32, 32, [](int, int) { return 0.5f; })});
    c.push_back({"boxes", make(36, 36, [](int x, int y) {
                     return (x % 12 > 3 && x % 12 < 9 && y % 12 > 2) ? 0.2f + 0.05f * float((x / 12 + 3 * (y / 12)) % 9) : 0.1f;
                 })});
    for (auto& k : c) k.field.name = k.name;
    return c;
}

// Looks `f` up in the cache at `dir` expecting a miss (a rebuild); returns what was said.
std::string rebuild_said(const HeightField& f, const fs::path& dir)
{
    ::testing::internal::CaptureStderr();
    EXPECT_FALSE(cached_cone_map(f, ConeKind::Cone, dir).from_cache);
    return ::testing::internal::GetCapturedStderr();
}

} // namespace

TEST(ConeMap, NamesParseAndReject)
{
    EXPECT_EQ(parse_cone_kind("cone"), ConeKind::Cone);
    EXPECT_EQ(parse_cone_kind("relaxed"), ConeKind::Relaxed);
    EXPECT_EQ(cone_kind_name(ConeKind::Relaxed), "relaxed");
    EXPECT_EQ(parse_cone_format("rg8"), ConeFormat::Rg8);
    EXPECT_EQ(cone_format_name(ConeFormat::Rg16), "rg16");
    try {
        parse_cone_kind("wide");
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.subject(), "--kind");
    }
    EXPECT_THROW(parse_cone_format("rg32"), Error);
}

TEST(ConeMap, RoundingIsDown)
{
    // sqrt(0.25) = 0.5 = 127.5/255: down to 127 (rg8); exact steps stay (up to the 1e-6 margin).
    EXPECT_EQ(cone_ratio_steps(0.25, ConeFormat::Rg8), 127);
    EXPECT_EQ(cone_ratio_steps(1.0, ConeFormat::Rg8), 255);
    EXPECT_EQ(cone_ratio_steps(7.0, ConeFormat::Rg16), 65535);
    EXPECT_EQ(cone_ratio_steps(0.0, ConeFormat::Rg16), 0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 10000; ++i) {
        const double c = u(rng);
        for (ConeFormat f : {ConeFormat::Rg8, ConeFormat::Rg16}) {
            const int k = cone_ratio_steps(c, f);
            const float r = cone_steps_to_ratio(k, f);
            EXPECT_LE(double(r) * r, c);                       // down
            EXPECT_GT(double(k + 1) / cone_format_steps(f), std::sqrt(c) * (1 - 1e-6)); // by < 1 step
            EXPECT_LE(double(r), double(k) / cone_format_steps(f));
        }
    }
}

// The table that whole maps convert through holds every step's ratio, as cone_steps_to_ratio.
TEST(ConeMap, RatioTableHoldsEveryStep)
{
    for (ConeFormat f : {ConeFormat::Rg8, ConeFormat::Rg16}) {
        const std::vector<float>& table = cone_ratio_table(f);
        ASSERT_EQ(table.size(), std::size_t(cone_format_steps(f)) + 1);
        for (int k = 0; k <= cone_format_steps(f); ++k) ASSERT_EQ(table[std::size_t(k)], cone_steps_to_ratio(k, f)) << k;
        EXPECT_EQ(&table, &cone_ratio_table(f)); // built once
    }
}

TEST(ConeMap, ConeEqualsBruteForceAndIsConservative)
{
    for (const Case& c : cases())
        for (ConeFormat format : {ConeFormat::Rg8, ConeFormat::Rg16}) {
            ConeBuildOptions o;
            o.format = format;
            o.threads = 2;
            const ConeMap m = build_cone_map_cpu(c.field, ConeKind::Cone, o);
            ASSERT_EQ(m.width, c.field.width);
            const HeightField stored = stored_heights(c.field, format); // the map's own heights
            ASSERT_EQ(m.heights, stored.texels);
            const std::vector<int> expected = brute_force(stored, ConeKind::Cone, format);
            int differ = 0;
            for (std::size_t i = 0; i < expected.size(); ++i) differ += steps_of(m, i, format) != expected[i];
            EXPECT_EQ(differ, 0) << c.name << " " << cone_format_name(format);
            expect_conservative(stored, m);
        }
}

// The seeds (ConeSeeds) of every fourth texel of every fourth row, where every search starts: the
// texel whose constraint sets that texel's cone (the brute force's steps), none where the cone is
// capped (no constraint under 1: nothing higher, or nothing near enough); and for relaxed maps
// the same of relaxed constraints and relaxed cones (exact: no march budget). Sizes that are not
// multiples of the spacing; the coarse seeds (every sixteenth texel) searched from nothing, the
// others from them.
TEST(ConeMap, SeedsAreTheTexelsThatSetTheirCones)
{
    for (const HeightField& f : {random_map(37, 30, 31), smooth_map(70, 22, 32)}) {
        ConeBuildOptions o;
        o.node_budget = 0;
        o.relaxed_budget = 0;
        const ConeSeeds seeds = cone_seeds_cpu(f, build_max_pyramid(f), ConeKind::Relaxed, o);
        ASSERT_EQ(seeds.width, (f.width + 3) / 4);
        ASSERT_EQ(seeds.height, (f.height + 3) / 4);
        ASSERT_EQ(seeds.texels.size(), std::size_t(seeds.width * seeds.height));
        ASSERT_EQ(seeds.relaxed.size(), seeds.texels.size());
        EXPECT_EQ(cone_seeds_cpu(f, build_max_pyramid(f), ConeKind::Cone, o).texels, seeds.texels);
        EXPECT_TRUE(cone_seeds_cpu(f, build_max_pyramid(f), ConeKind::Cone, o).relaxed.empty());
        for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
            const std::vector<int> expected = brute_force(f, kind, ConeFormat::Rg16);
            const std::vector<std::uint32_t>& grid = kind == ConeKind::Cone ? seeds.texels : seeds.relaxed;
            const std::string what = kind == ConeKind::Cone ? "cone " : "relaxed ";
            int none = 0, found = 0;
            for (int sy = 0; sy < seeds.height; ++sy)
                for (int sx = 0; sx < seeds.width; ++sx) {
                    const int px = 4 * sx, py = 4 * sy;
                    const std::uint32_t t = grid[std::size_t(sy * seeds.width + sx)];
                    if (t == kNoConeSeed) {
                        EXPECT_EQ(expected[std::size_t(py * f.width + px)], 65535) << what << px << "," << py;
                        ++none;
                        continue;
                    }
                    ASSERT_LT(t, f.texels.size());
                    const int qx = int(t) % f.width, qy = int(t) / f.width;
                    const double rise = stored_rise(f, qx, qy, px, py);
                    ASSERT_GT(rise, 0.0) << what << px << "," << py;
                    const int dx = signed_offset(qx - px, f.width), dy = signed_offset(qy - py, f.height);
                    double c = uv_distance(f, dx, dy) / rise;
                    int budget = std::numeric_limits<int>::max();
                    if (kind == ConeKind::Relaxed)
                        c = relaxed_constraint(f, px, py, dx, dy, std::numeric_limits<double>::infinity(), budget, c);
                    EXPECT_EQ(cone_ratio_steps(c, ConeFormat::Rg16), expected[std::size_t(py * f.width + px)])
                        << what << px << "," << py;
                    ++found;
                }
            EXPECT_GT(found, seeds.width * seeds.height / 2) << what;
            EXPECT_GE(none, 1) << what; // (both maps have capped cones among their seed texels)
        }
    }
}

// The seed passes' shares of the seeds' progress, which both generators report by: in their
// order (cone seeds, then relaxed ones; coarse, then the others), each starting where the one
// before ended, together the whole, a relaxed search counting as four cone ones.
TEST(ConeMap, SeedPassesShareTheSeedsProgressInOrder)
{
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
        double end = 0.0;
        for (bool relaxed : {false, true}) {
            if (relaxed && kind == ConeKind::Cone) break;
            for (bool coarse : {true, false}) {
                const auto [from, share] = cone_seed_pass_progress(kind, relaxed, coarse);
                EXPECT_DOUBLE_EQ(from, end) << relaxed << coarse;
                EXPECT_GT(share, 0.0);
                end = from + share;
            }
        }
        EXPECT_DOUBLE_EQ(end, 1.0);
    }
    EXPECT_DOUBLE_EQ(cone_seed_pass_progress(ConeKind::Cone, false, true).second, 1.0 / 16.0);
    EXPECT_DOUBLE_EQ(cone_seed_pass_progress(ConeKind::Relaxed, true, false).second, 4.0 * 15.0 / 16.0 / 5.0);
    const ConeSeeds grid = cone_seed_grid(random_map(9, 5, 1), ConeKind::Relaxed);
    EXPECT_EQ(grid.width, 3);
    EXPECT_EQ(grid.height, 2);
    EXPECT_EQ(grid.texels, std::vector<std::uint32_t>(6, kNoConeSeed));
    EXPECT_EQ(grid.relaxed, grid.texels);
    EXPECT_TRUE(cone_seed_grid(random_map(9, 5, 1), ConeKind::Cone).relaxed.empty());
}

// An rg8 map stores 8-bit heights (R), and a marcher or any reader of the PNG sees only those: its
// ratios must be conservative against them, not against the field's 16 bits, which 8-bit rounding
// can reorder or bring closer (1139 of 4096 texels of builtin:noise@64 had a higher stored texel
// inside their cone when G came from the 16-bit heights). Checked by brute force against the R
// channel read back from the PNG; 8-bit fields keep their heights bit for bit.
TEST(ConeMap, Rg8MapsAreConservativeAgainstTheirStoredHeights)
{
    prtest::TempDir dir;
    ConeBuildOptions o;
    o.format = ConeFormat::Rg8;
    const HeightField fine[] = {smooth_map(40, 32, 21), random_map(32, 32, 22)};
    for (const HeightField& f : fine) {
        const ConeMap m = build_cone_map_cpu(f, ConeKind::Cone, o);
        const fs::path png = dir.path() / "rg8.png";
        write_cone_png(png, m, ConeFormat::Rg8);
        const ConeMap back = read_cone_png(png, ConeKind::Cone);
        EXPECT_EQ(back.heights, m.heights); // the map holds exactly what its R channel stores
        EXPECT_EQ(back.ratios, m.ratios);
        HeightField stored = f;
        stored.texels = back.heights;
        expect_conservative(stored, back);
        const std::vector<int> expected = brute_force(stored, ConeKind::Cone, ConeFormat::Rg8);
        int differ = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) differ += steps_of(m, i, ConeFormat::Rg8) != expected[i];
        EXPECT_EQ(differ, 0); // and as wide as the stored heights allow
        // Relaxed maps are built from the stored heights too.
        EXPECT_EQ(build_cone_map_cpu(f, ConeKind::Relaxed, o).heights, back.heights);
        // The cache serves the same map (its stored heights are the rounded ones).
        const ConeCacheResult first = cached_cone_map(f, ConeKind::Cone, dir.path(), o);
        const ConeCacheResult second = cached_cone_map(f, ConeKind::Cone, dir.path(), o);
        EXPECT_FALSE(first.from_cache);
        EXPECT_TRUE(second.from_cache);
        EXPECT_EQ(second.map.heights, m.heights);
        EXPECT_EQ(second.map.ratios, m.ratios);
    }
    // 8-bit heights are stored as they are: rg8 and rg16 maps carry the field's own texels.
    std::mt19937 rng(23);
    std::uniform_int_distribution<int> d(0, 255);
    const HeightField coarse = make(24, 20, [&](int, int) { return float(d(rng)) / 255.0f; });
    EXPECT_EQ(build_cone_map_cpu(coarse, ConeKind::Cone, o).heights, coarse.texels);
    EXPECT_EQ(build_cone_map_cpu(coarse, ConeKind::Cone, {}).heights, coarse.texels);
    EXPECT_EQ(build_cone_map_cpu(fine[0], ConeKind::Cone, {}).heights, fine[0].texels); // rg16
}

TEST(ConeMap, KnownValues)
{
    // A spike of height 1 on a flat 0 map: c = distance to the spike; the spike itself: 1 (cap).
    const HeightField f = make(32, 32, [](int x, int y) { return x == 0 && y == 0 ? 1.0f : 0.0f; });
    const ConeMap m = build_cone_map_cpu(f, ConeKind::Cone, {});
    EXPECT_EQ(m.ratios[0], cone_steps_to_ratio(65535, ConeFormat::Rg16));
    // Texel (3, 0): distance 3/32 (and (31, 0) wraps to distance 1/32).
    EXPECT_EQ(m.ratios[3], cone_steps_to_ratio(cone_ratio_steps(3.0 / 32.0, ConeFormat::Rg16), ConeFormat::Rg16));
    EXPECT_EQ(m.ratios[31], cone_steps_to_ratio(cone_ratio_steps(1.0 / 32.0, ConeFormat::Rg16), ConeFormat::Rg16));
    // A constant map: every cone is the cap.
    const ConeMap c = build_cone_map_cpu(make(16, 8, [](int, int) { return 0.3f; }), ConeKind::Relaxed, {});
    for (float r : c.ratios) EXPECT_EQ(r, 1.0f);
}

TEST(ConeMap, RelaxedEqualsBruteForceAndIsWider)
{
    for (const Case& c : cases()) {
        if (c.field.width * c.field.height > 1300) continue; // brute-force marching is O(n^2 * march)
        ConeBuildOptions o;
        o.threads = 2;
        o.relaxed_budget = 0; // exact
        const ConeMap relaxed = build_cone_map_cpu(c.field, ConeKind::Relaxed, o);
        const ConeMap cone = build_cone_map_cpu(c.field, ConeKind::Cone, o);
        const std::vector<int> expected = brute_force(c.field, ConeKind::Relaxed, ConeFormat::Rg16);
        int differ = 0, narrower = 0;
        for (std::size_t i = 0; i < expected.size(); ++i) {
            differ += steps_of(relaxed, i, ConeFormat::Rg16) != expected[i];
            narrower += relaxed.ratios[i] < cone.ratios[i];
        }
        EXPECT_EQ(differ, 0) << c.name;
        EXPECT_EQ(narrower, 0) << c.name;
    }
}

// The relaxed property, by brute-force ray casting (GPU Gems 3, ch. 18): for every texel p and
// every texel q, the viewing ray from p's column at the top (height 1) through q's surface point,
// marched on past q, leaves the surface (E) outside p's relaxed cone or not above h_p: a ray that
// enters the cone from above crosses the surface into the solid at most once inside it. With the
// default march budget and a small one that binds on most texels.
TEST(ConeMap, RelaxedRaysLeaveTheSurfaceOutsideTheCone)
{
    for (const Case& c : cases())
    for (int budget : {ConeBuildOptions{}.relaxed_budget, 8}) {
        if (c.field.width * c.field.height > 1300) continue;
        const HeightField& f = c.field;
        ConeBuildOptions o;
        o.relaxed_budget = budget;
        const ConeMap m = build_cone_map_cpu(f, ConeKind::Relaxed, o);
        int inside = 0;
        for (int py = 0; py < f.height; ++py)
            for (int px = 0; px < f.width; ++px) {
                const double r = m.ratios[std::size_t(py) * std::size_t(f.width) + std::size_t(px)];
                // Walk the ray by hand (independent of the generator's bookkeeping).
                for (int qy = 0; qy < f.height; ++qy)
                    for (int qx = 0; qx < f.width; ++qx) {
                        const int dx = signed_offset(qx - px, f.width), dy = signed_offset(qy - py, f.height);
                        const double hp = texel(f, px, py), hq = texel(f, qx, qy);
                        if (!(hq > hp)) continue;
                        const double len = std::hypot(double(dx), double(dy));
                        for (int k = 1; k < 4 * (f.width + f.height); ++k) {
                            const double lambda = 1.0 + k / len;
                            const double z = 1.0 - lambda * (1.0 - hq);
                            if (z <= hp) break;
                            const double x = px + lambda * dx, y = py + lambda * dy;
                            const double x0 = std::floor(x), y0 = std::floor(y), fx = x - x0, fy = y - y0;
                            const auto h = [&](int i, int j) { return double(texel(f, wrapi(i, f.width), wrapi(j, f.height))); };
                            const int ix = int(x0), iy = int(y0);
                            const double a = h(ix, iy) + (h(ix + 1, iy) - h(ix, iy)) * fx;
                            const double b = h(ix, iy + 1) + (h(ix + 1, iy + 1) - h(ix, iy + 1)) * fx;
                            if (a + (b - a) * fy < z) { // E: the ray is above the surface again
                                const double dist = lambda * uv_distance(f, dx, dy);
                                inside += dist < r * r * (z - hp) * (1 - 1e-9);
                                break;
                            }
                        }
                    }
            }
        EXPECT_EQ(inside, 0) << c.name << " budget " << budget;
    }
}

// A wall 4 texels thick (height 1 on 0): the ray from a floor texel's column top through the
// wall's near texel runs along the wall's top and is out of it one texel past the far side, but
// rays a hair under it come out before that. So a relaxed cone in front of the wall reaches at
// most its last texel, not the step out (which let the prism's relaxed-cone marcher cross a thin
// wall's top in one step: Prism.ConeMarchersMeetAThinWallsFaceUnderItsTop).
TEST(ConeMap, RelaxedConesInFrontOfAThinWallStopAtItsLastTexel)
{
    const HeightField f = make(64, 8, [](int x, int) { return x >= 32 && x < 36 ? 1.0f : 0.0f; });
    const ConeMap m = build_cone_map_cpu(f, ConeKind::Relaxed, {});
    int past = 0;
    for (int py = 0; py < f.height; ++py)
        for (int px = 0; px < 32; ++px) {
            const double r = m.ratios[std::size_t(py) * std::size_t(f.width) + std::size_t(px)];
            const double last = std::min(35 - px, px + 64 - 32) / 64.0; // to the right, or wrapped left
            past += r * r > last * (1.0 + 1e-9);
        }
    EXPECT_EQ(past, 0);
}

// A ridge a texel thin and lower than the range: a ray coming in low, a hair under its top, goes
// in and out of it within a texel, so no relaxed cone in front of it may reach past it. (Only the
// ray from height 1 was followed, which falls through such a ridge to the floor and set no
// constraint: the cones next to a ridge 0.3 high were 15 times the cone's, and a relaxed march
// seen low over the plane stepped over the ridge's top; found by an exploratory session,
// thirtieth.)
TEST(ConeMap, RelaxedConesInFrontOfALowRidgeStopPastIt)
{
    const float top = 0.3f;
    const HeightField f = make(64, 8, [&](int x, int) { return x == 32 ? top : 0.0f; });
    const ConeMap m = build_cone_map_cpu(f, ConeKind::Relaxed, {});
    int past = 0;
    for (int py = 0; py < f.height; ++py)
        for (int px = 0; px < 32; ++px) {
            const double r = m.ratios[std::size_t(py) * std::size_t(f.width) + std::size_t(px)];
            const double beyond = std::min(33 - px, px + 33) / 64.0; // a texel past it, either way round
            past += r * r > beyond / double(top) * (1.0 + 1e-9);
        }
    EXPECT_EQ(past, 0);
}

// A march budget gives a narrower relaxed cone where the search needs more, never narrower than
// the cone, and still a valid relaxed cone (checked by the ray test above with the default budget).
TEST(ConeMap, RelaxedBudgetLiesBetweenConeAndExact)
{
    const HeightField f = smooth_map(48, 40, 12);
    ConeBuildOptions exact, tight;
    exact.relaxed_budget = 0;
    tight.relaxed_budget = 16;
    const ConeMap e = build_cone_map_cpu(f, ConeKind::Relaxed, exact);
    const ConeMap t = build_cone_map_cpu(f, ConeKind::Relaxed, tight);
    const ConeMap c = build_cone_map_cpu(f, ConeKind::Cone, {});
    int narrower = 0;
    for (std::size_t i = 0; i < c.ratios.size(); ++i) {
        EXPECT_LE(t.ratios[i], e.ratios[i]);
        EXPECT_GE(t.ratios[i], c.ratios[i]);
        narrower += t.ratios[i] < e.ratios[i];
    }
    EXPECT_GT(narrower, 0); // the budget did bind somewhere
}

// A node budget (pathological maps: a long ramp) gives a narrower cone where the search runs out,
// never a wider one: still conservative against brute force. Depth first alone
// (best_first_budget 0, as the GPU searches), and with a best-first part that runs out too.
TEST(ConeMap, NodeBudgetStaysConservative)
{
    const HeightField f = make(64, 48, [](int x, int y) { return q16((x + 0.3 * y) / 80.0); });
    ConeBuildOptions exact, depth_first, both;
    exact.node_budget = 0;
    exact.relaxed_budget = 0;
    depth_first.node_budget = 24;
    depth_first.best_first_budget = 0;
    both.node_budget = 24;
    both.best_first_budget = 24;
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
        const ConeMap e = build_cone_map_cpu(f, kind, exact);
        const ConeMap d = build_cone_map_cpu(f, kind, depth_first);
        const ConeMap b = build_cone_map_cpu(f, kind, both);
        int narrower = 0, wider_than_depth_first = 0;
        for (std::size_t i = 0; i < e.ratios.size(); ++i) {
            EXPECT_LE(d.ratios[i], e.ratios[i]);
            EXPECT_LE(b.ratios[i], e.ratios[i]) << cone_kind_name(kind) << " texel " << i;
            EXPECT_GE(b.ratios[i], d.ratios[i]); // going on best first never narrows
            narrower += d.ratios[i] < e.ratios[i];
            wider_than_depth_first += b.ratios[i] > d.ratios[i];
        }
        EXPECT_GT(narrower, 0) << cone_kind_name(kind); // the budget did bind
        EXPECT_GT(wider_than_depth_first, 0) << cone_kind_name(kind);
        if (kind == ConeKind::Cone) {
            expect_conservative(f, d);
            expect_conservative(f, b);
        }
    }
    // The default budget does not bind on the test maps: the exact result (brute-force tested).
    for (const Case& c : cases()) {
        const ConeMap d = build_cone_map_cpu(c.field, ConeKind::Cone, {});
        const ConeMap e = build_cone_map_cpu(c.field, ConeKind::Cone, exact);
        EXPECT_EQ(d.ratios, e.ratios) << c.name;
    }
}

// Where the depth-first search runs out of nodes it leaves the near siblings of the nodes it went
// down into, whose bounds are small; counted by those, the cones of a ramp or a hill came out
// far too narrow (on a 512² ramp a sixth of the texels stored less than half their ratio, on a
// hill a third). Best first from there, the default budget proves the exact ratio on both here,
// with a node budget that binds as 1024 does at 512².
TEST(ConeMap, BestFirstFinishesWhereTheNodesRunOut)
{
    const HeightField ramp = make(64, 48, [](int x, int y) { return q16((x + 0.3 * y) / 80.0); });
    const HeightField hill = make(64, 64, [](int x, int y) {
        return q16(std::max(0.0, 1.0 - 2.0 * std::hypot((x + 0.5) / 64.0 - 0.5, (y + 0.5) / 64.0 - 0.5)));
    });
    for (const HeightField* f : {&ramp, &hill}) {
        ConeBuildOptions exact, depth_first, both;
        exact.node_budget = 0;
        depth_first.node_budget = both.node_budget = 24;
        depth_first.best_first_budget = 0;
        const ConeMap e = build_cone_map_cpu(*f, ConeKind::Cone, exact);
        const ConeMap d = build_cone_map_cpu(*f, ConeKind::Cone, depth_first);
        int half = 0;
        for (std::size_t i = 0; i < e.ratios.size(); ++i) half += d.ratios[i] < 0.5f * e.ratios[i];
        std::printf("%s: %d of %zu texels under half their ratio depth first\n", f == &ramp ? "ramp" : "hill", half,
                    e.ratios.size());
        EXPECT_GT(half, int(e.ratios.size() / 50)) << (f == &ramp ? "ramp" : "hill");
        EXPECT_EQ(build_cone_map_cpu(*f, ConeKind::Cone, both).ratios, e.ratios) << (f == &ramp ? "ramp" : "hill");
    }
}

TEST(ConeMap, RelaxedIsWiderSomewhereOnBoxes)
{
    const Case c = cases()[8];
    const ConeMap relaxed = build_cone_map_cpu(c.field, ConeKind::Relaxed, {});
    const ConeMap cone = build_cone_map_cpu(c.field, ConeKind::Cone, {});
    double sr = 0, sc = 0;
    for (std::size_t i = 0; i < cone.ratios.size(); ++i) sr += relaxed.ratios[i], sc += cone.ratios[i];
    EXPECT_GT(sr, sc * 1.05);
}

// What the renderer uploads: bilinear filtering of the narrowed ratios, anywhere in a patch
// (wrapping at the borders), is never wider than the narrowest of the patch's four corners in the
// map, and each texel only narrows.
TEST(ConeMap, RatiosForBilinearAreNoWiderThanAPatchsCorners)
{
    const int w = 13, h = 9;
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> ratios(std::size_t(w) * h);
    for (float& r : ratios) r = u(rng) < 0.2f ? 1.0f : u(rng); // wide texels among narrow ones
    const std::vector<float> narrow = ratios_for_bilinear(ratios, w, h);
    ASSERT_EQ(narrow.size(), ratios.size());
    auto at = [w, h](const std::vector<float>& v, int x, int y) {
        return v[std::size_t((y % h + h) % h) * std::size_t(w) + std::size_t((x % w + w) % w)];
    };
    for (std::size_t i = 0; i < ratios.size(); ++i) EXPECT_LE(narrow[i], ratios[i]);
    int wider_than_corners_unnarrowed = 0;
    for (int y = -1; y < h; ++y)
        for (int x = -1; x < w; ++x) {
            const float corners = std::min({at(ratios, x, y), at(ratios, x + 1, y), at(ratios, x, y + 1), at(ratios, x + 1, y + 1)});
            for (float fy : {0.0f, 0.25f, 0.5f, 0.9f})
                for (float fx : {0.0f, 0.3f, 0.5f, 1.0f}) {
                    auto bilinear = [&](const std::vector<float>& v) {
                        const float a = at(v, x, y) + (at(v, x + 1, y) - at(v, x, y)) * fx;
                        const float b = at(v, x, y + 1) + (at(v, x + 1, y + 1) - at(v, x, y + 1)) * fx;
                        return a + (b - a) * fy;
                    };
                    EXPECT_LE(bilinear(narrow), corners + 1e-6f) << x << "," << y << " at " << fx << "," << fy;
                    wider_than_corners_unnarrowed += bilinear(ratios) > corners + 1e-6f;
                }
        }
    EXPECT_GT(wider_than_corners_unnarrowed, 100); // the map itself is (the test can fail)
    EXPECT_THROW(ratios_for_bilinear(ratios, w + 1, h), std::invalid_argument);
}

TEST(ConeMap, ThreadCountDoesNotChangeTheMap)
{
    // (Rows longer than a span, kConeSpan, with a part span at their end, and rows shorter.)
    for (const HeightField& f : {smooth_map(64, 48, 9), smooth_map(2 * kConeSpan + 37, 3, 4), smooth_map(5, 90, 2)})
        for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
            ConeBuildOptions one, two, three;
            one.threads = 1;
            two.threads = 2;
            three.threads = 3;
            int calls = 0;
            two.progress = [&](double) { ++calls; };
            const std::vector<float> ratios = build_cone_map_cpu(f, kind, one).ratios;
            EXPECT_EQ(ratios, build_cone_map_cpu(f, kind, two).ratios) << f.width << "x" << f.height;
            EXPECT_EQ(ratios, build_cone_map_cpu(f, kind, three).ratios) << f.width << "x" << f.height;
            EXPECT_GE(calls, 1);
        }
}

// The threads take spans of rows: a map of one long row has work for all of them (it ran on one
// thread when a row was the unit; found by an exploratory session, forty-sixth).
TEST(ConeMap, LongRowsAreSharedAmongThreads)
{
    EXPECT_EQ(cone_cpu_items(16384, 1), 16384 / kConeSpan);
    EXPECT_EQ(cone_cpu_items(kConeSpan + 1, 2), 4);
    EXPECT_EQ(cone_cpu_items(1, 1), 1);
    EXPECT_EQ(cone_cpu_items(512, 512), 512 * (512 / kConeSpan));
    ConeBuildOptions o;
    o.threads = 4;
    EXPECT_EQ(cone_cpu_threads(o, cone_cpu_items(16384, 1)), 4u);
    EXPECT_EQ(cone_cpu_threads(o, cone_cpu_items(kConeSpan, 1)), 1u);
}

// A cancelled build (the viewer's, when the scene changes or the window closes) stops and
// throws, with every thread, and leaves no cache entry; a flag that stays false changes nothing.
TEST(ConeMap, CancelledBuildThrowsAndCachesNothing)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(48, 40, 5);
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
        std::atomic<bool> cancel{true};
        for (int threads : {1, 2}) {
            ConeBuildOptions o;
            o.threads = threads;
            o.cancel = &cancel;
            EXPECT_THROW(build_cone_map_cpu(f, kind, o), ConeBuildCancelled) << threads;
        }
        ConeBuildOptions o;
        o.cancel = &cancel;
        EXPECT_THROW(cached_cone_map(f, kind, dir.path(), o), ConeBuildCancelled);
        EXPECT_FALSE(fs::exists(cone_cache_entry(f, kind, o, dir.path())));
        cancel = false;
        EXPECT_EQ(build_cone_map_cpu(f, kind, o).ratios, build_cone_map_cpu(f, kind).ratios);
        EXPECT_FALSE(cached_cone_map(f, kind, dir.path(), o).from_cache);
        EXPECT_TRUE(fs::exists(cone_cache_entry(f, kind, o, dir.path())));
    }
}

// The cache is bounded: after a write the least recently used entries (written or read longest
// ago) go until the rest fit; the entry just written and files that are not entries stay.
TEST(ConeMap, CacheDropsTheLeastRecentlyUsedEntriesBeyondItsBound)
{
    prtest::TempDir dir;
    using Clock = fs::file_time_type::clock;
    std::vector<HeightField> fields;
    std::vector<fs::path> entries;
    for (int i = 0; i < 3; ++i) {
        fields.push_back(smooth_map(32, 32, 3 + i));
        entries.push_back(cached_cone_map(fields.back(), ConeKind::Cone, dir.path()).entry);
        // Distinct times, oldest first (file times may be coarse).
        fs::last_write_time(entries.back(), Clock::now() - std::chrono::hours(3 - i));
    }
    const std::uintmax_t entry_bytes = fs::file_size(entries[0]);
    const fs::path foreign = dir.write("cone/notes.txt", std::string(3 * entry_bytes, 'x'));
    // Files that only look like entries (or their temporaries), older than every entry: neither
    // counted nor removed (a name that began "cone-" and ended ".bin" was taken for an entry).
    std::vector<fs::path> lookalikes;
    for (const char* name : {"cone/cone-my-backup.bin", "cone/relaxed-rg16-32x32-0123456789abcdeg.bin",
                             "cone/cone-rg16-032x32-0123456789abcdef.bin", "cone/cone-rg16-32x32-0123456789abcdef.bin.bak",
                             "cone/.cone-x.bin.tmp1", "cone/.cone-rg16-8x8-2.bin.tmp999"}) {
        lookalikes.push_back(dir.write(name, std::string(entry_bytes, 'y')));
        fs::last_write_time(lookalikes.back(), Clock::now() - std::chrono::hours(5));
    }
    EXPECT_EQ(trim_cone_cache(dir.path(), 3 * entry_bytes), 0u); // fits: nothing goes
    // Reading the oldest makes it the most recently used: the next trim takes the second one.
    EXPECT_TRUE(cached_cone_map(fields[0], ConeKind::Cone, dir.path()).from_cache);
    EXPECT_EQ(trim_cone_cache(dir.path(), 2 * entry_bytes), 1u);
    EXPECT_TRUE(fs::exists(entries[0]));
    EXPECT_FALSE(fs::exists(entries[1]));
    EXPECT_TRUE(fs::exists(entries[2]));
    EXPECT_TRUE(fs::exists(foreign));
    for (const fs::path& p : lookalikes) EXPECT_TRUE(fs::exists(p)) << p;
    // `keep` stays even when it alone is over the bound.
    EXPECT_EQ(trim_cone_cache(dir.path(), 1, entries[2]), 1u);
    EXPECT_TRUE(fs::exists(entries[2]));
    EXPECT_FALSE(fs::exists(entries[0]));

    // cached_cone_map trims after each write, to PRISMRELIEF_CACHE_MAX_MB (here: one MiB, the size
    // of two 256² entries and a half), and keeps what it wrote.
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "1", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::uint64_t(1) << 20);
    std::vector<fs::path> big;
    for (int i = 0; i < 4; ++i) {
        big.push_back(cached_cone_map(smooth_map(256, 256, 7 + i), ConeKind::Cone, dir.path()).entry);
        fs::last_write_time(big.back(), Clock::now() - std::chrono::minutes(10 - i));
        EXPECT_TRUE(fs::exists(big.back()));
    }
    std::uintmax_t total = 0;
    for (const auto& e : fs::directory_iterator(dir.path() / "cone"))
        if (e.path().extension() == ".bin") total += e.file_size();
    EXPECT_LE(total, std::uintmax_t(1) << 20);
    EXPECT_FALSE(fs::exists(big[0])); // the oldest went
    EXPECT_TRUE(fs::exists(foreign));
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "0", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::numeric_limits<std::uint64_t>::max()); // no bound
    // Past 2^43 MiB, or past 64 bits: no bound either (it fell back to the default).
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "8796093022209", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::numeric_limits<std::uint64_t>::max());
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "99999999999999999999", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::numeric_limits<std::uint64_t>::max());
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "8796093022208", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::uint64_t(8796093022208) << 20);
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "-5", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::uint64_t(2048) << 20); // warned, the default
    ASSERT_EQ(setenv("PRISMRELIEF_CACHE_MAX_MB", "lots", 1), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::uint64_t(2048) << 20); // warned, the default
    ASSERT_EQ(unsetenv("PRISMRELIEF_CACHE_MAX_MB"), 0);
    EXPECT_EQ(cone_cache_max_bytes(), std::uint64_t(2048) << 20);
}

// A stored ratio's step, as the PNG, the cache and conemap --json take it: every step of either
// format comes back from its float, and ratios outside [0, 1] are clamped.
TEST(ConeMap, RatioStepsComeBackFromTheirFloats)
{
    for (ConeFormat format : {ConeFormat::Rg8, ConeFormat::Rg16})
        for (int k = 0; k <= cone_format_steps(format); ++k)
            ASSERT_EQ(cone_ratio_to_steps(cone_steps_to_ratio(k, format), format), std::uint32_t(k)) << k;
    EXPECT_EQ(cone_ratio_to_steps(1.5f, ConeFormat::Rg8), 255u);
    EXPECT_EQ(cone_ratio_to_steps(-0.5f, ConeFormat::Rg16), 0u);
}

TEST(ConeMap, PngRoundTrip)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(24, 16, 4);
    for (ConeFormat format : {ConeFormat::Rg8, ConeFormat::Rg16}) {
        ConeBuildOptions o;
        o.format = format;
        const ConeMap m = build_cone_map_cpu(f, ConeKind::Cone, o);
        const fs::path p = dir.path() / ("c_" + cone_format_name(format) + ".png");
        write_cone_png(p, m, format);
        const ConeMap back = read_cone_png(p, ConeKind::Cone);
        ASSERT_EQ(back.width, 24);
        ASSERT_EQ(back.height, 16);
        EXPECT_EQ(back.ratios, m.ratios); // exact: the file stores the steps
        const double tol = format == ConeFormat::Rg8 ? 0.5 / 255 + 1e-6 : 0.5 / 65535 + 1e-7;
        for (std::size_t i = 0; i < m.heights.size(); ++i) ASSERT_NEAR(back.heights[i], m.heights[i], tol);
    }
}

TEST(ConeMap, PngReadRejectsBadFiles)
{
    prtest::TempDir dir;
    const fs::path text = dir.write("text.png", "not a png at all, no sir, not even close to one");
    try {
        read_cone_png(text, ConeKind::Cone);
        FAIL();
    } catch (const Error& e) {
        EXPECT_EQ(e.subject(), text.string());
    }
    EXPECT_THROW(read_cone_png(dir.path() / "missing.png", ConeKind::Cone), Error);
    // Truncated: a real cone PNG cut in half.
    const ConeMap m = build_cone_map_cpu(random_map(32, 32, 3), ConeKind::Cone, {});
    const fs::path whole = dir.path() / "whole.png";
    write_cone_png(whole, m, ConeFormat::Rg16);
    std::ifstream in(whole, std::ios::binary);
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    bytes.resize(bytes.size() / 2);
    EXPECT_THROW(read_cone_png(dir.write_bytes("half.png", bytes), ConeKind::Cone), Error);
}

// A FIFO or an empty folder where an entry goes is replaced by the entry, with a warning (written
// over, it stayed: every run rebuilt the map and warned); the cache's folders are made 0700 whatever the umask
// (under umask 000 anyone could write entries). Found by an exploratory session, thirty-fourth.
TEST(ConeMap, CacheReplacesSpecialFilesAndMakesPrivateFolders)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(16, 16, 3);
    const mode_t old_mask = ::umask(0);
    const ConeCacheResult first = cached_cone_map(f, ConeKind::Cone, dir.path() / "made" / "here");
    ::umask(old_mask);
    ASSERT_FALSE(first.entry.empty());
    for (const fs::path& folder : {dir.path() / "made", dir.path() / "made" / "here", first.entry.parent_path()})
        EXPECT_EQ(fs::status(folder).permissions() & fs::perms::all, fs::perms::owner_all) << folder;
    for (const bool fifo : {true, false}) {
        fs::remove(first.entry);
        if (fifo)
            ASSERT_EQ(::mkfifo(first.entry.c_str(), 0600), 0);
        else
            fs::create_directory(first.entry);
        ::testing::internal::CaptureStderr();
        EXPECT_FALSE(cached_cone_map(f, ConeKind::Cone, dir.path() / "made" / "here").from_cache);
        // Said, as any entry that is wrong (forty-first session: silent).
        EXPECT_NE(::testing::internal::GetCapturedStderr().find(
                      first.entry.string() + (fifo ? ": is not a regular file (a FIFO); rebuilding it" : ": is a folder; rebuilding it")),
                  std::string::npos)
            << fifo;
        EXPECT_TRUE(fs::is_regular_file(fs::symlink_status(first.entry))) << fifo;
        EXPECT_TRUE(cached_cone_map(f, ConeKind::Cone, dir.path() / "made" / "here").from_cache);
    }
}

TEST(ConeMap, CacheRoundTripAndCorruptEntryIsRebuilt)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(32, 32, 6);
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
        const ConeCacheResult first = cached_cone_map(f, kind, dir.path());
        EXPECT_FALSE(first.from_cache);
        ASSERT_TRUE(fs::exists(first.entry));
        const ConeCacheResult second = cached_cone_map(f, kind, dir.path());
        EXPECT_TRUE(second.from_cache);
        EXPECT_EQ(second.map.ratios, first.map.ratios);
        EXPECT_EQ(second.map.heights, first.map.heights);
        EXPECT_EQ(second.map.kind, kind);

        // Flip one payload byte: the checksum catches it, the entry is rebuilt and rewritten.
        {
            std::fstream io(first.entry, std::ios::in | std::ios::out | std::ios::binary);
            io.seekp(100);
            io.put(char(0x5A));
        }
        const ConeCacheResult third = cached_cone_map(f, kind, dir.path());
        EXPECT_FALSE(third.from_cache);
        EXPECT_EQ(third.map.ratios, first.map.ratios);
        EXPECT_TRUE(cached_cone_map(f, kind, dir.path()).from_cache);

        // Truncated entry: rebuilt too.
        fs::resize_file(first.entry, 20);
        EXPECT_FALSE(cached_cone_map(f, kind, dir.path()).from_cache);
        EXPECT_TRUE(cached_cone_map(f, kind, dir.path()).from_cache);
    }
    // Another format or another map: another entry.
    ConeBuildOptions rg8;
    rg8.format = ConeFormat::Rg8;
    EXPECT_FALSE(cached_cone_map(f, ConeKind::Cone, dir.path(), rg8).from_cache);
    HeightField g = f;
    g.texels[5] = 0.0f;
    EXPECT_FALSE(cached_cone_map(g, ConeKind::Cone, dir.path()).from_cache);
    // Other budgets (which change the map where they bind): another entry.
    for (int which = 0; which < 3; ++which) {
        ConeBuildOptions o;
        (which == 0 ? o.node_budget : which == 1 ? o.best_first_budget : o.relaxed_budget) = 24;
        EXPECT_FALSE(cached_cone_map(f, ConeKind::Relaxed, dir.path(), o).from_cache) << which;
        EXPECT_TRUE(cached_cone_map(f, ConeKind::Relaxed, dir.path(), o).from_cache) << which;
    }
}

// read_cached_cone_map (the viewer's read in the frame): the entry's map, or nothing, without a
// word and without building, where there is no cache, no entry or a wrong one.
TEST(ConeMap, ReadingTheCacheAloneNeverBuilds)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(32, 32, 6);
    EXPECT_FALSE(read_cached_cone_map(f, ConeKind::Relaxed, dir.path()).has_value()); // no entry
    EXPECT_FALSE(read_cached_cone_map(f, ConeKind::Relaxed, {}).has_value());         // no cache
    EXPECT_TRUE(fs::is_empty(dir.path()));
    const ConeCacheResult built = cached_cone_map(f, ConeKind::Relaxed, dir.path());
    const std::optional<ConeMap> read = read_cached_cone_map(f, ConeKind::Relaxed, dir.path());
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->ratios, built.map.ratios);
    EXPECT_EQ(read->heights, built.map.heights);
    EXPECT_FALSE(read_cached_cone_map(f, ConeKind::Cone, dir.path()).has_value()); // another kind's entry
    {
        std::fstream io(built.entry, std::ios::in | std::ios::out | std::ios::binary);
        io.seekp(100);
        io.put(char(0x5A));
    }
    const auto before = fs::last_write_time(built.entry);
    ::testing::internal::CaptureStderr();
    EXPECT_FALSE(read_cached_cone_map(f, ConeKind::Relaxed, dir.path()).has_value());
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(fs::last_write_time(built.entry), before); // neither rebuilt nor marked used
}

// An entry of the wrong length (cut short, or with bytes appended) is rebuilt, and the warning
// gives the length expected and the one found.
TEST(ConeMap, CacheEntryOfTheWrongSizeSaysSo)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(16, 12, 24);
    const fs::path entry = cached_cone_map(f, ConeKind::Cone, dir.path()).entry;
    const std::uintmax_t size = fs::file_size(entry);
    for (const std::uintmax_t wrong : {size + 7, size - 5}) {
        fs::resize_file(entry, wrong);
        const std::string said = rebuild_said(f, dir.path());
        EXPECT_NE(said.find("size is wrong (expected " + std::to_string(size) + " bytes, found " +
                            std::to_string(wrong) + ")"),
                  std::string::npos)
            << said;
        EXPECT_EQ(said.find("truncated"), std::string::npos) << said;
        EXPECT_EQ(fs::file_size(entry), size); // rewritten
    }
}

// An entry far larger than this map's (a 4 GiB sparse file in its place) was read whole into
// memory before its size was looked at; now no more than twice an entry's size is read.
TEST(ConeMap, HugeCacheEntryIsNotReadWhole)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(16, 12, 24);
    const fs::path entry = cached_cone_map(f, ConeKind::Cone, dir.path()).entry;
    const std::uintmax_t size = fs::file_size(entry);
    fs::resize_file(entry, std::uintmax_t(4) << 30);
    const std::string said = rebuild_said(f, dir.path());
    EXPECT_NE(said.find(entry.string() + ": is 4 GiB (4294967296 bytes), more than"), std::string::npos) << said;
    EXPECT_NE(said.find("not this map's entry; rebuilding it"), std::string::npos) << said;
    EXPECT_EQ(fs::file_size(entry), size); // rewritten
}

// A link in an entry's place was written through by the rebuild: the file it named (any file the
// user may write) became a cache entry. The link is replaced; its target keeps its content.
TEST(ConeMap, LinkInAnEntrysPlaceIsReplacedNotFollowed)
{
    prtest::TempDir dir;
    const HeightField f = smooth_map(16, 12, 24);
    const fs::path entry = cached_cone_map(f, ConeKind::Cone, dir.path()).entry;
    const fs::path precious = dir.write("precious.txt", "precious");
    fs::remove(entry);
    fs::create_symlink(precious, entry);
    rebuild_said(f, dir.path());
    EXPECT_EQ(fs::file_size(precious), 8u);
    EXPECT_FALSE(fs::is_symlink(entry));
    EXPECT_TRUE(cached_cone_map(f, ConeKind::Cone, dir.path()).from_cache);
}

TEST(ConeMap, UnwritableCacheOnlyWarns)
{
    prtest::TempDir dir;
    const fs::path blocker = dir.write("file", "a file where the cache folder should be");
    const HeightField f = random_map(16, 16, 8);
    ::testing::internal::CaptureStderr();
    const ConeCacheResult r = cached_cone_map(f, ConeKind::Cone, blocker / "cache");
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_FALSE(r.from_cache);
    EXPECT_EQ(r.map.ratios.size(), 256u);
    // Which part of the path is in the way ("File exists" said nothing of it).
    EXPECT_NE(said.find("cannot create it: " + blocker.string() + " is not a folder"), std::string::npos) << said;
    const fs::path dangling = dir.path() / "gone";
    fs::create_symlink(dir.path() / "missing", dangling);
    ::testing::internal::CaptureStderr();
    cached_cone_map(f, ConeKind::Cone, dangling);
    const std::string said_link = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said_link.find(dangling.string() + " is a symbolic link to " + (dir.path() / "missing").string() +
                             ", which does not exist"),
              std::string::npos)
        << said_link;
    // Two links naming each other: a loop, not a missing target.
    fs::create_symlink(dir.path() / "loop_b", dir.path() / "loop_a");
    fs::create_symlink(dir.path() / "loop_a", dir.path() / "loop_b");
    ::testing::internal::CaptureStderr();
    cached_cone_map(f, ConeKind::Cone, dir.path() / "loop_a");
    const std::string said_loop = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said_loop.find((dir.path() / "loop_a").string() + " is a symbolic link to " +
                             (dir.path() / "loop_b").string() + ", which leads back to itself (a loop of links)"),
              std::string::npos)
        << said_loop;
}

TEST(ConeMap, DefaultCacheDirFollowsXdg)
{
    const char* old = std::getenv("XDG_CACHE_HOME");
    const std::string saved = old ? old : "";
    ::setenv("XDG_CACHE_HOME", "/tmp/xdg-test", 1);
    EXPECT_EQ(default_cache_dir(), fs::path("/tmp/xdg-test/prismrelief"));
    ::setenv("XDG_CACHE_HOME", "relative/ignored", 1);
    EXPECT_NE(default_cache_dir(), fs::path("relative/ignored/prismrelief"));
    if (old) ::setenv("XDG_CACHE_HOME", saved.c_str(), 1);
    else ::unsetenv("XDG_CACHE_HOME");
}

// The rise from one texel to another is taken in the map's own height steps (R), not as the
// difference of the float texels, whose rounding (up to 6e-8 together) is 4e-3 of a one-step
// rise: texel 0 (63370) of this map stored G = 62670 where the exact floor(sqrt(c) * 65535) with
// c = (2/96) / (1493/65535) is 62669, and texel 2 (64863) lay inside its cone (found by an
// exploratory session, sixteenth session). CPU and GPU agree (test_conemap_gpu).
TEST(ConeMap, RatiosAreConservativeAgainstTheStoredSteps)
{
    const HeightField f = make(96, 1, [](int x, int) {
        return x == 0 ? 63370.0f / 65535.0f : x == 2 ? 64863.0f / 65535.0f : 0.0f;
    });
    const ConeMap m = build_cone_map_cpu(f, ConeKind::Cone, ConeBuildOptions{});
    const double c = (2.0 / 96.0) / (1493.0 / 65535.0);
    EXPECT_EQ(steps_of(m, 0, ConeFormat::Rg16), int(std::floor(std::sqrt(c) * 65535.0)));
    expect_conservative(f, m);
}
