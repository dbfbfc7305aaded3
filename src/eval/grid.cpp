#include "eval/grid.hpp"

#include "core/error.hpp"
#include "eval/metrics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <fmt/format.h>

namespace pr {
namespace {

// ---- font ----
// One string per printable ASCII character (0x20..0x7E, in order), drawn as rows of five
// '.'/'#' from the top down, separated by spaces: 7 rows above the baseline and, for descenders,
// up to 2 more. Kept as pictures rather than hex so a glyph can be read and fixed in place.
constexpr std::array<std::string_view, 95> kGlyphArt = {
    "..... ..... ..... ..... ..... ..... .....",             // space
    "..#.. ..#.. ..#.. ..#.. ..#.. ..... ..#..",             // !
    ".#.#. .#.#. ..... ..... ..... ..... .....",             // "
    ".#.#. .#.#. ##### .#.#. ##### .#.#. .#.#.",             // #
    "..#.. .#### #.#.. .###. ..#.# ####. ..#..",             // $
    "##... ##..# ...#. ..#.. .#... #..## ...##",             // %
    ".##.. #..#. #.#.. .#... #.#.# #..#. .##.#",             // &
    "..#.. ..#.. ..... ..... ..... ..... .....",             // '
    "...#. ..#.. .#... .#... .#... ..#.. ...#.",             // (
    ".#... ..#.. ...#. ...#. ...#. ..#.. .#...",             // )
    "..... ..#.. #.#.# .###. #.#.# ..#.. .....",             // *
    "..... ..#.. ..#.. ##### ..#.. ..#.. .....",             // +
    "..... ..... ..... ..... ..... .##.. .##.. ..#.. .#...", // ,
    "..... ..... ..... ##### ..... ..... .....",             // -
    "..... ..... ..... ..... ..... .##.. .##..",             // .
    "..... ....# ...#. ..#.. .#... #.... .....",             // /
    ".###. #...# #..## #.#.# ##..# #...# .###.",             // 0
    "..#.. .##.. ..#.. ..#.. ..#.. ..#.. .###.",             // 1
    ".###. #...# ....# ...#. ..#.. .#... #####",             // 2
    "##### ...#. ..#.. ...#. ....# #...# .###.",             // 3
    "...#. ..##. .#.#. #..#. ##### ...#. ...#.",             // 4
    "##### #.... ####. ....# ....# #...# .###.",             // 5
    "..##. .#... #.... ####. #...# #...# .###.",             // 6
    "##### ....# ...#. ..#.. .#... .#... .#...",             // 7
    ".###. #...# #...# .###. #...# #...# .###.",             // 8
    ".###. #...# #...# .#### ....# ...#. .##..",             // 9
    "..... .##.. .##.. ..... .##.. .##.. .....",             // :
    "..... .##.. .##.. ..... .##.. .##.. ..#.. .#...",       // ;
    "...#. ..#.. .#... #.... .#... ..#.. ...#.",             // <
    "..... ..... ##### ..... ##### ..... .....",             // =
    ".#... ..#.. ...#. ....# ...#. ..#.. .#...",             // >
    ".###. #...# ....# ...#. ..#.. ..... ..#..",             // ?
    ".###. #...# ....# .##.# #.#.# #.#.# .###.",             // @
    ".###. #...# #...# ##### #...# #...# #...#",             // A
    "####. #...# #...# ####. #...# #...# ####.",             // B
    ".###. #...# #.... #.... #.... #...# .###.",             // C
    "###.. #..#. #...# #...# #...# #..#. ###..",             // D
    "##### #.... #.... ####. #.... #.... #####",             // E
    "##### #.... #.... ####. #.... #.... #....",             // F
    ".###. #...# #.... #.### #...# #...# .####",             // G
    "#...# #...# #...# ##### #...# #...# #...#",             // H
    ".###. ..#.. ..#.. ..#.. ..#.. ..#.. .###.",             // I
    "..### ...#. ...#. ...#. ...#. #..#. .##..",             // J
    "#...# #..#. #.#.. ##... #.#.. #..#. #...#",             // K
    "#.... #.... #.... #.... #.... #.... #####",             // L
    "#...# ##.## #.#.# #.#.# #...# #...# #...#",             // M
    "#...# #...# ##..# #.#.# #..## #...# #...#",             // N
    ".###. #...# #...# #...# #...# #...# .###.",             // O
    "####. #...# #...# ####. #.... #.... #....",             // P
    ".###. #...# #...# #...# #.#.# #..#. .##.#",             // Q
    "####. #...# #...# ####. #.#.. #..#. #...#",             // R
    ".#### #.... #.... .###. ....# ....# ####.",             // S
    "##### ..#.. ..#.. ..#.. ..#.. ..#.. ..#..",             // T
    "#...# #...# #...# #...# #...# #...# .###.",             // U
    "#...# #...# #...# #...# #...# .#.#. ..#..",             // V
    "#...# #...# #...# #.#.# #.#.# #.#.# .#.#.",             // W
    "#...# #...# .#.#. ..#.. .#.#. #...# #...#",             // X
    "#...# #...# .#.#. ..#.. ..#.. ..#.. ..#..",             // Y
    "##### ....# ...#. ..#.. .#... #.... #####",             // Z
    ".###. .#... .#... .#... .#... .#... .###.",             // [
    "..... #.... .#... ..#.. ...#. ....# .....",             // backslash
    ".###. ...#. ...#. ...#. ...#. ...#. .###.",             // ]
    "..#.. .#.#. #...# ..... ..... ..... .....",             // ^
    "..... ..... ..... ..... ..... ..... #####",             // _
    ".#... ..#.. ..... ..... ..... ..... .....",             // `
    "..... ..... .###. ....# .#### #...# .####",             // a
    "#.... #.... #.##. ##..# #...# #...# ####.",             // b
    "..... ..... .###. #.... #.... #...# .###.",             // c
    "....# ....# .##.# #..## #...# #...# .####",             // d
    "..... ..... .###. #...# ##### #.... .###.",             // e
    "..##. .#..# .#... ###.. .#... .#... .#...",             // f
    "..... ..... .#### #...# #...# .#### ....# #...# .###.", // g
    "#.... #.... #.##. ##..# #...# #...# #...#",             // h
    "..#.. ..... .##.. ..#.. ..#.. ..#.. .###.",             // i
    "...#. ..... ..##. ...#. ...#. ...#. ...#. #..#. .##..", // j
    "#.... #.... #..#. #.#.. ##... #.#.. #..#.",             // k
    ".##.. ..#.. ..#.. ..#.. ..#.. ..#.. .###.",             // l
    "..... ..... ##.#. #.#.# #.#.# #.#.# #.#.#",             // m
    "..... ..... #.##. ##..# #...# #...# #...#",             // n
    "..... ..... .###. #...# #...# #...# .###.",             // o
    "..... ..... ####. #...# #...# ####. #.... #.... #....", // p
    "..... ..... .#### #...# #...# .#### ....# ....# ....#", // q
    "..... ..... #.##. ##..# #.... #.... #....",             // r
    "..... ..... .###. #.... .###. ....# ####.",             // s
    ".#... .#... ###.. .#... .#... .#..# ..##.",             // t
    "..... ..... #...# #...# #...# #..## .##.#",             // u
    "..... ..... #...# #...# #...# .#.#. ..#..",             // v
    "..... ..... #...# #...# #.#.# #.#.# .#.#.",             // w
    "..... ..... #...# .#.#. ..#.. .#.#. #...#",             // x
    "..... ..... #...# #...# #...# .#### ....# #...# .###.", // y
    "..... ..... ##### ...#. ..#.. .#... #####",             // z
    "...#. ..#.. ..#.. .#... ..#.. ..#.. ...#.",             // {
    "..#.. ..#.. ..#.. ..#.. ..#.. ..#.. ..#..",             // |
    ".#... ..#.. ..#.. ...#. ..#.. ..#.. .#...",             // }
    "..... ..... .#... #.#.# ...#. ..... .....",             // ~
};

// 7 to 9 rows of exactly five '.' or '#', single spaces between: checked at compile time, so a
// mistyped glyph fails the build instead of drawing garbage.
constexpr bool well_formed(std::string_view art)
{
    int rows = 0;
    std::size_t i = 0;
    for (;;) {
        if (i + kGlyphWidth > art.size()) return false;
        for (int k = 0; k < kGlyphWidth; ++k)
            if (art[i + k] != '.' && art[i + k] != '#') return false;
        ++rows;
        i += kGlyphWidth;
        if (i == art.size()) break;
        if (art[i] != ' ') return false;
        ++i;
    }
    return rows >= 7 && rows <= kGlyphRows;
}
static_assert(std::all_of(kGlyphArt.begin(), kGlyphArt.end(), well_formed),
              "every glyph must be 7 to 9 rows of five '.' or '#'");

// Row bits, top row first; bit 4 is the leftmost column.
using GlyphBits = std::array<std::uint8_t, kGlyphRows>;

constexpr std::array<GlyphBits, 95> build_font()
{
    std::array<GlyphBits, 95> font{};
    for (std::size_t g = 0; g < kGlyphArt.size(); ++g) {
        const std::string_view art = kGlyphArt[g];
        for (std::size_t row = 0; row * (kGlyphWidth + 1) < art.size(); ++row) {
            std::uint8_t bits = 0;
            for (int k = 0; k < kGlyphWidth; ++k)
                if (art[row * (kGlyphWidth + 1) + k] == '#')
                    bits = static_cast<std::uint8_t>(bits | (1u << (kGlyphWidth - 1 - k)));
            font[g][row] = bits;
        }
    }
    return font;
}
constexpr std::array<GlyphBits, 95> kFont = build_font();

const GlyphBits& glyph(char ch)
{
    const auto code = static_cast<unsigned char>(ch);
    return kFont[(code >= 0x20 && code <= 0x7E) ? code - 0x20 : '?' - 0x20];
}

// ---- drawing helpers ----
// Grid colours: a light page, white label strips with black text, and a mid-grey checker under
// the tiles so that what they leave transparent reads as "nothing" rather than as white.
constexpr glm::u8vec4 kPage{232, 232, 232, 255};
constexpr glm::u8vec4 kStrip{255, 255, 255, 255};
constexpr glm::u8vec4 kText{0, 0, 0, 255};
constexpr glm::u8vec4 kCheckerLight{170, 170, 170, 255};
constexpr glm::u8vec4 kCheckerDark{128, 128, 128, 255};
constexpr int kCheckerSquare = 8; // pixels, times the font scale

void put(RgbaImage& image, int x, int y, glm::u8vec4 c)
{
    if (x < 0 || y < 0 || x >= image.width || y >= image.height) return;
    std::uint8_t* p = &image.pixels[4 * (std::size_t(y) * image.width + x)];
    p[0] = c.r;
    p[1] = c.g;
    p[2] = c.b;
    p[3] = c.a;
}

void fill(RgbaImage& image, int x0, int y0, int w, int h, glm::u8vec4 c)
{
    for (int y = y0; y < y0 + h; ++y)
        for (int x = x0; x < x0 + w; ++x) put(image, x, y, c);
}

void check_image(const RgbaImage& image, const char* subject)
{
    if (image.width < 0 || image.height < 0 ||
        image.pixels.size() != 4 * std::size_t(image.width) * std::size_t(image.height))
        throw Error(subject, fmt::format("an image is {}x{} but holds {} bytes", image.width,
                                         image.height, image.pixels.size()));
}

std::uint8_t blend(int src, int dst, int alpha)
{
    // Straight alpha "over", rounded to nearest.
    return static_cast<std::uint8_t>((src * alpha + dst * (255 - alpha) + 127) / 255);
}

} // namespace

RgbaImage silhouette_diff_tile(const RgbaImage& technique, const RgbaImage& reference)
{
    check_image(technique, "compare");
    check_image(reference, "compare");
    if (technique.width != reference.width || technique.height != reference.height)
        throw Error("compare",
                    fmt::format("the technique image is {}x{} but the reference is {}x{}",
                                technique.width, technique.height, reference.width,
                                reference.height));
    RgbaImage out;
    out.width = technique.width;
    out.height = technique.height;
    out.pixels.resize(technique.pixels.size());
    for (std::size_t i = 0; i < technique.pixels.size(); i += 4) {
        const std::uint8_t* t = &technique.pixels[i];
        const bool in_t = covers(t[3]);
        const bool in_r = covers(reference.pixels[i + 3]);
        glm::u8vec4 c = kDiffNeither;
        if (in_t && in_r) {
            // Rec. 709 weights on the stored (sRGB) values: a display aid, not a measurement.
            const double luma = 0.2126 * t[0] + 0.7152 * t[1] + 0.0722 * t[2];
            const auto g = static_cast<std::uint8_t>(
                std::lround(kDiffBothLow + luma * (kDiffBothHigh - kDiffBothLow) / 255.0));
            c = {g, g, g, 255};
        } else if (in_t) {
            c = kDiffOnlyTechnique;
        } else if (in_r) {
            c = kDiffOnlyReference;
        }
        out.pixels[i] = c.r;
        out.pixels[i + 1] = c.g;
        out.pixels[i + 2] = c.b;
        out.pixels[i + 3] = c.a;
    }
    return out;
}

namespace {

// The lines a label is drawn in within `inner` pixels at `scale`: its own ('\n'), each one that
// does not fit broken after a ':' where it can ("prism:relaxed-cone:exact" over two lines, not
// cut to "prism:relaxed-c", which "prism:relaxed-cone" is cut to as well: two techniques of a
// grid read the same; found by an exploratory session). A piece still too wide is cut by
// compose_grid.
std::vector<std::string_view> label_lines(std::string_view label, int inner, int scale)
{
    std::vector<std::string_view> lines;
    for (;;) {
        const std::size_t end = label.find('\n');
        std::string_view line = label.substr(0, end);
        while (text_width(line, scale) > inner) {
            // The longest head that ends with ':' and fits; none: the first head that ends with
            // ':', cut at the edge on a line of its own (a line with no break left goes as it
            // is). Where "relaxed-cone:" did not fit (tiles under about 80 pixels) the rest of
            // the line went on it, cut: four prism variants all read "prism:" over
            // "relaxed-cone" (found by an exploratory session, thirty-third).
            std::size_t cut = std::string_view::npos;
            for (std::size_t i = line.find(':'); i != std::string_view::npos && i + 1 < line.size(); i = line.find(':', i + 1))
                if (text_width(line.substr(0, i + 1), scale) <= inner) cut = i + 1;
            if (const std::size_t first = line.find(':');
                cut == std::string_view::npos && first != std::string_view::npos && first + 1 < line.size())
                cut = first + 1;
            if (cut == std::string_view::npos) break;
            lines.push_back(line.substr(0, cut));
            line.remove_prefix(cut);
        }
        lines.push_back(line);
        if (end == std::string_view::npos) return lines;
        label.remove_prefix(end + 1);
    }
}

} // namespace

GridLayout plan_grid(const std::vector<Tile>& tiles, int columns)
{
    if (tiles.empty()) throw Error("grid", "no tiles to lay out");
    if (columns < 1) throw Error("grid", fmt::format("{} columns: need at least 1", columns));
    GridLayout l;
    const int n = static_cast<int>(tiles.size());
    l.columns = std::min(columns, n); // empty columns would only widen the figure
    l.rows = (n + l.columns - 1) / l.columns;
    for (const Tile& t : tiles) {
        l.cell_width = std::max(l.cell_width, t.image.width);
        l.cell_height = std::max(l.cell_height, t.image.height);
    }
    // One scale for the whole figure so every strip has the same height.
    l.scale = l.cell_width >= 256 ? 2 : 1;
    // Lines of the longest label (label_lines), one pixel row apart; 2 rows of padding above the
    // text, 1 below.
    int lines = 1;
    for (const Tile& t : tiles)
        lines = std::max(lines, static_cast<int>(label_lines(t.label, l.cell_width - 4 * l.scale, l.scale).size()));
    l.strip_height = (lines * (kGlyphRows + 1) + 2) * l.scale;
    l.margin = 4 * l.scale;
    l.width = l.columns * l.cell_width + (l.columns + 1) * l.margin;
    l.height = l.rows * (l.strip_height + l.cell_height) + (l.rows + 1) * l.margin;
    return l;
}

glm::ivec2 tile_origin(const GridLayout& l, int index, const Tile& tile)
{
    const int col = index % l.columns;
    const int row = index / l.columns; // 0 = top row of the figure
    const int x = l.margin + col * (l.cell_width + l.margin);
    // Measured from the top, as the figure is read, then turned into bottom-first rows.
    const int tile_top = l.margin + row * (l.strip_height + l.cell_height + l.margin) +
                         l.strip_height;
    return {x, l.height - tile_top - tile.image.height};
}

RgbaImage compose_grid(const std::vector<Tile>& tiles, int columns,
                       const RgbaImage* background_colour_hint)
{
    const GridLayout l = plan_grid(tiles, columns);
    for (const Tile& t : tiles) check_image(t.image, "grid");
    const bool flat = background_colour_hint && background_colour_hint->pixels.size() >= 4;
    const glm::u8vec4 flat_colour = flat ? background_colour_hint->at(0, 0) : glm::u8vec4{};

    RgbaImage out;
    out.width = l.width;
    out.height = l.height;
    out.pixels.resize(4 * std::size_t(l.width) * std::size_t(l.height));
    fill(out, 0, 0, l.width, l.height, kPage);

    for (std::size_t i = 0; i < tiles.size(); ++i) {
        const Tile& tile = tiles[i];
        const RgbaImage& img = tile.image;
        const glm::ivec2 o = tile_origin(l, static_cast<int>(i), tile);

        const int strip_y = o.y + img.height;
        fill(out, o.x, strip_y, l.cell_width, l.strip_height, kStrip);
        // Line by line from the top (label_lines), each cut at the last whole character that fits
        // the strip's inner width.
        const int inner = l.cell_width - 4 * l.scale;
        const std::vector<std::string_view> lines = label_lines(tile.label, inner, l.scale);
        for (std::size_t line = 0; line < lines.size(); ++line) {
            const std::string_view whole = lines[line];
            std::string_view text = whole;
            while (!text.empty() && text_width(text, l.scale) > inner) text.remove_suffix(1);
            // A number is not cut: "IoU 0.9942" cut to "IoU 0.9" read as a tenth lower (found by
            // an exploratory session); the line ends before it ("IoU").
            const auto in_number = [](char c) { return (c >= '0' && c <= '9') || c == '.' || c == '-'; };
            if (text.size() < whole.size() && !text.empty() && in_number(text.back()) && in_number(whole[text.size()])) {
                while (!text.empty() && in_number(text.back())) text.remove_suffix(1);
                while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
            }
            draw_text(out, o.x + 2 * l.scale,
                      strip_y + l.strip_height - 1 - 2 * l.scale - int(line) * (kGlyphRows + 1) * l.scale, text,
                      l.scale, kText);
        }

        const int square = kCheckerSquare * l.scale;
        for (int y = 0; y < img.height; ++y) {
            for (int x = 0; x < img.width; ++x) {
                glm::u8vec4 bg = flat_colour;
                if (!flat) bg = ((x / square + y / square) % 2) ? kCheckerDark : kCheckerLight;
                const glm::u8vec4 s = img.at(x, y);
                put(out, o.x + x, o.y + y,
                    {blend(s.r, bg.r, s.a), blend(s.g, bg.g, s.a), blend(s.b, bg.b, s.a), 255});
            }
        }
    }
    return out;
}

int text_width(std::string_view text, int scale)
{
    if (text.empty()) return 0;
    // No gap after the last glyph.
    return (static_cast<int>(text.size()) * kGlyphAdvance - (kGlyphAdvance - kGlyphWidth)) * scale;
}

void draw_text(RgbaImage& image, int x, int y_top, std::string_view text, int scale,
               glm::u8vec4 colour)
{
    for (std::size_t n = 0; n < text.size(); ++n) {
        const GlyphBits& bits = glyph(text[n]);
        const int gx = x + static_cast<int>(n) * kGlyphAdvance * scale;
        for (int row = 0; row < kGlyphRows; ++row) {
            for (int col = 0; col < kGlyphWidth; ++col) {
                if (!(bits[row] & (1u << (kGlyphWidth - 1 - col)))) continue;
                // Glyph rows run top-down; storage rows bottom-up, hence the minus.
                for (int sy = 0; sy < scale; ++sy)
                    for (int sx = 0; sx < scale; ++sx)
                        put(image, gx + col * scale + sx, y_top - row * scale - sy, colour);
            }
        }
    }
}

} // namespace pr
