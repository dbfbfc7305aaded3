// The comparison figure (eval/grid): silhouette-difference colours, grid layout, labels drawn
// upright above their tiles in bottom-row-first storage, and the built-in font.
#include "core/error.hpp"
#include "eval/grid.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace {

pr::RgbaImage solid(int w, int h, glm::u8vec4 c)
{
    pr::RgbaImage img;
    img.width = w;
    img.height = h;
    img.pixels.resize(4 * std::size_t(w) * h);
    for (std::size_t i = 0; i < img.pixels.size(); i += 4)
        for (int k = 0; k < 4; ++k) img.pixels[i + k] = c[k];
    return img;
}

void set(pr::RgbaImage& img, int x, int y, glm::u8vec4 c)
{
    for (int k = 0; k < 4; ++k) img.pixels[4 * (std::size_t(y) * img.width + x) + k] = c[k];
}

glm::u8vec4 grey(int v)
{
    const auto g = static_cast<std::uint8_t>(v);
    return {g, g, g, 255};
}

bool dark(glm::u8vec4 c) { return c.r < 64 && c.g < 64 && c.b < 64; }

// Dark pixels per row over rows [y0, y1) and columns [x0, x1), indexed from y0.
std::vector<int> dark_per_row(const pr::RgbaImage& img, int x0, int x1, int y0, int y1)
{
    std::vector<int> counts;
    for (int y = y0; y < y1; ++y) {
        int n = 0;
        for (int x = x0; x < x1; ++x) n += dark(img.at(x, y)) ? 1 : 0;
        counts.push_back(n);
    }
    return counts;
}

TEST(GridDiff, ColoursBySilhouette)
{
    // Row 0: both, only technique, only reference; row 1: neither, both (black), both (white).
    pr::RgbaImage t = solid(3, 2, {0, 0, 0, 0});
    pr::RgbaImage r = solid(3, 2, {0, 0, 0, 0});
    set(t, 0, 0, {255, 255, 255, 255});
    set(r, 0, 0, {0, 0, 0, 255});
    set(t, 1, 0, {10, 20, 30, 200});
    set(r, 2, 0, {10, 20, 30, 128});
    set(t, 1, 1, {0, 0, 0, 255});
    set(r, 1, 1, {9, 9, 9, 255});
    set(t, 2, 1, {255, 255, 255, 255});
    set(r, 2, 1, {255, 255, 255, 255});
    const pr::RgbaImage d = pr::silhouette_diff_tile(t, r);
    ASSERT_EQ(d.width, 3);
    ASSERT_EQ(d.height, 2);
    // Both covered: grey from the *technique's* luminance (white here, though the reference is
    // black), scaled into [kDiffBothLow, kDiffBothHigh].
    EXPECT_EQ(d.at(0, 0), grey(pr::kDiffBothHigh));
    EXPECT_EQ(d.at(1, 0), pr::kDiffOnlyTechnique);
    EXPECT_EQ(d.at(2, 0), pr::kDiffOnlyReference);
    EXPECT_EQ(d.at(0, 1), pr::kDiffNeither);
    EXPECT_EQ(d.at(1, 1), grey(pr::kDiffBothLow));
    EXPECT_EQ(d.at(2, 1), grey(pr::kDiffBothHigh));
    // The four classes are told apart at a glance.
    const std::set<std::vector<int>> distinct = {
        {pr::kDiffOnlyTechnique.r, pr::kDiffOnlyTechnique.g, pr::kDiffOnlyTechnique.b},
        {pr::kDiffOnlyReference.r, pr::kDiffOnlyReference.g, pr::kDiffOnlyReference.b},
        {pr::kDiffNeither.r, pr::kDiffNeither.g, pr::kDiffNeither.b}};
    EXPECT_EQ(distinct.size(), 3u);
    EXPECT_GT(pr::kDiffBothLow, pr::kDiffNeither.r);
}

TEST(GridDiff, SizeMismatchThrows)
{
    EXPECT_THROW(pr::silhouette_diff_tile(solid(3, 2, {}), solid(2, 3, {})), pr::Error);
}

TEST(Grid, SizeFollowsTilesAndColumns)
{
    const std::vector<pr::Tile> tiles(5, pr::Tile{"x", solid(10, 8, {255, 0, 0, 255})});
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    EXPECT_EQ(l.columns, 2);
    EXPECT_EQ(l.rows, 3);
    EXPECT_EQ(l.cell_width, 10);
    EXPECT_EQ(l.cell_height, 8);
    EXPECT_EQ(l.scale, 1);
    EXPECT_GT(l.margin, 0);
    EXPECT_GE(l.strip_height, pr::kGlyphRows);
    EXPECT_EQ(l.width, 2 * 10 + 3 * l.margin);
    EXPECT_EQ(l.height, 3 * (l.strip_height + 8) + 4 * l.margin);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    EXPECT_EQ(g.width, l.width);
    EXPECT_EQ(g.height, l.height);
    ASSERT_EQ(g.pixels.size(), 4 * std::size_t(g.width) * g.height);
    for (std::size_t i = 3; i < g.pixels.size(); i += 4) ASSERT_EQ(g.pixels[i], 255) << i;

    // More columns than tiles: no empty columns.
    const pr::GridLayout wide = pr::plan_grid(tiles, 8);
    EXPECT_EQ(wide.columns, 5);
    EXPECT_EQ(wide.rows, 1);
}

TEST(Grid, BadArgumentsThrow)
{
    EXPECT_THROW(pr::compose_grid({}, 2), pr::Error);
    const std::vector<pr::Tile> one{{"a", solid(4, 4, {})}};
    EXPECT_THROW(pr::compose_grid(one, 0), pr::Error);
}

TEST(Grid, DifferentSizesPadToTheLargest)
{
    const std::vector<pr::Tile> tiles{{"a", solid(10, 8, {255, 0, 0, 255})},
                                      {"b", solid(20, 4, {0, 0, 255, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    EXPECT_EQ(l.cell_width, 20);
    EXPECT_EQ(l.cell_height, 8);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    // Each tile's corners land where tile_origin says, the first cell's padding stays page.
    for (int i = 0; i < 2; ++i) {
        const pr::RgbaImage& img = tiles[i].image;
        const glm::ivec2 o = pr::tile_origin(l, i, tiles[i]);
        EXPECT_EQ(g.at(o.x, o.y), img.at(0, 0));
        EXPECT_EQ(g.at(o.x + img.width - 1, o.y + img.height - 1),
                  img.at(img.width - 1, img.height - 1));
    }
    const glm::ivec2 o0 = pr::tile_origin(l, 0, tiles[0]);
    EXPECT_NE(g.at(o0.x + 15, o0.y), glm::u8vec4(255, 0, 0, 255));
}

TEST(Grid, TilesKeepTheirRowOrderAndSitInReadingOrder)
{
    // Tile rows are stored bottom first, like the grid: the tile's row 0 must stay the lowest.
    pr::RgbaImage img = solid(6, 4, {0, 255, 0, 255});
    set(img, 0, 0, {255, 0, 0, 255});
    const std::vector<pr::Tile> tiles{{"first", img}, {"second", img}, {"third", img}};
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    const glm::ivec2 a = pr::tile_origin(l, 0, tiles[0]);
    const glm::ivec2 b = pr::tile_origin(l, 1, tiles[1]);
    const glm::ivec2 c = pr::tile_origin(l, 2, tiles[2]);
    EXPECT_EQ(g.at(a.x, a.y), glm::u8vec4(255, 0, 0, 255));
    EXPECT_EQ(g.at(a.x, a.y + 3), glm::u8vec4(0, 255, 0, 255));
    // The first tile is at the top left: the third, in the second row, sits lower.
    EXPECT_EQ(a.y, b.y);
    EXPECT_LT(a.x, b.x);
    EXPECT_EQ(c.x, a.x);
    EXPECT_LT(c.y, a.y);
}

TEST(Grid, TransparentPixelsShowTheBackground)
{
    const std::vector<pr::Tile> tiles{{"t", solid(32, 32, {255, 0, 0, 0})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 1);
    const glm::ivec2 o = pr::tile_origin(l, 0, tiles[0]);
    const pr::RgbaImage g = pr::compose_grid(tiles, 1);
    std::set<int> greys;
    for (int y = 0; y < 32; ++y) {
        for (int x = 0; x < 32; ++x) {
            const glm::u8vec4 p = g.at(o.x + x, o.y + y);
            ASSERT_EQ(p.r, p.g); // the tile's red never shows
            ASSERT_EQ(p.g, p.b);
            greys.insert(p.r);
        }
    }
    EXPECT_EQ(greys.size(), 2u); // a checker of two greys

    const pr::RgbaImage hint = solid(1, 1, {10, 200, 30, 255});
    const pr::RgbaImage flat = pr::compose_grid(tiles, 1, &hint);
    EXPECT_EQ(flat.at(o.x + 5, o.y + 20), glm::u8vec4(10, 200, 30, 255));

    // Half-transparent red over the flat colour: the straight-alpha blend.
    const std::vector<pr::Tile> half{{"h", solid(4, 4, {255, 0, 0, 128})}};
    const glm::ivec2 oh = pr::tile_origin(pr::plan_grid(half, 1), 0, half[0]);
    const pr::RgbaImage blended = pr::compose_grid(half, 1, &hint);
    EXPECT_EQ(blended.at(oh.x, oh.y), glm::u8vec4(133, 100, 15, 255));
}

TEST(Grid, LabelIsDrawnUprightInTheStripAboveTheTile)
{
    const std::vector<pr::Tile> tiles{{"T", solid(40, 20, {255, 255, 255, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 1);
    const glm::ivec2 o = pr::tile_origin(l, 0, tiles[0]);
    const pr::RgbaImage g = pr::compose_grid(tiles, 1);

    // Nothing dark inside the (white) tile, nor below it.
    for (int n : dark_per_row(g, 0, g.width, 0, o.y + 20)) EXPECT_EQ(n, 0);
    // The strip holds text: rows above the tile (higher indices).
    const int strip_y = o.y + 20;
    ASSERT_LE(strip_y + l.strip_height, g.height);
    const std::vector<int> rows =
        dark_per_row(g, o.x, o.x + l.cell_width, strip_y, strip_y + l.strip_height);
    int lowest = -1;
    int highest = -1;
    for (int i = 0; i < int(rows.size()); ++i) {
        if (rows[i] == 0) continue;
        if (lowest < 0) lowest = i;
        highest = i;
    }
    ASSERT_GE(highest, 0) << "no text drawn";
    // Upright "T": the bar (5 pixels) is the highest dark row, the stem (1 pixel) the lowest.
    EXPECT_EQ(rows[highest], 5);
    EXPECT_EQ(rows[lowest], 1);
    EXPECT_EQ(highest - lowest, 6);
    // The strip itself is white around the text.
    EXPECT_EQ(g.at(o.x + l.cell_width - 1, strip_y), glm::u8vec4(255, 255, 255, 255));

    // Without a label the strip stays blank: the dark pixels above were the text.
    const std::vector<pr::Tile> unlabelled{{"", tiles[0].image}};
    const pr::RgbaImage blank = pr::compose_grid(unlabelled, 1);
    for (int n : dark_per_row(blank, 0, blank.width, 0, blank.height)) EXPECT_EQ(n, 0);
}

TEST(Grid, WideTilesGetDoubleSizeText)
{
    const std::vector<pr::Tile> tiles{{"T", solid(256, 8, {255, 255, 255, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 1);
    EXPECT_EQ(l.scale, 2);
    const glm::ivec2 o = pr::tile_origin(l, 0, tiles[0]);
    const pr::RgbaImage g = pr::compose_grid(tiles, 1);
    const std::vector<int> rows =
        dark_per_row(g, o.x, o.x + l.cell_width, o.y + 8, o.y + 8 + l.strip_height);
    int highest = -1;
    int dark_rows = 0;
    for (int i = 0; i < int(rows.size()); ++i) {
        if (rows[i] > 0) {
            highest = i;
            ++dark_rows;
        }
    }
    ASSERT_GE(highest, 1);
    EXPECT_EQ(rows[highest], 10);     // the bar, twice as wide
    EXPECT_EQ(rows[highest - 1], 10); // and twice as tall
    EXPECT_EQ(dark_rows, 14);
}

TEST(Grid, LongLabelsStayInsideTheirCell)
{
    const std::string label(100, 'W');
    const std::vector<pr::Tile> tiles{{label, solid(30, 10, {255, 255, 255, 255})},
                                      {"", solid(30, 10, {255, 255, 255, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    const glm::ivec2 first = pr::tile_origin(l, 0, tiles[0]);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    int inside = 0;
    for (int y = 0; y < g.height; ++y) {
        for (int x = 0; x < g.width; ++x) {
            if (!dark(g.at(x, y))) continue;
            EXPECT_LT(x, first.x + l.cell_width) << "text spilled at x=" << x;
            ++inside;
        }
    }
    EXPECT_GT(inside, 0);
}

TEST(GridFont, EveryPrintableCharacterHasItsOwnGlyph)
{
    // Bitmaps as strings: GCC 12 -O3 misreads std::set<std::vector<uint8_t>> comparisons
    // (a false -Wstringop-overread).
    std::set<std::string> seen;
    for (char ch = 0x20; ch <= 0x7E; ++ch) {
        pr::RgbaImage img = solid(pr::kGlyphWidth, pr::kGlyphRows, {255, 255, 255, 255});
        pr::draw_text(img, 0, pr::kGlyphRows - 1, std::string(1, ch), 1, {0, 0, 0, 255});
        int drawn = 0;
        for (std::size_t i = 0; i < img.pixels.size(); i += 4) drawn += img.pixels[i] == 0;
        if (ch == ' ')
            EXPECT_EQ(drawn, 0);
        else
            EXPECT_GT(drawn, 0) << "no glyph for '" << ch << "'";
        const std::string bitmap(img.pixels.begin(), img.pixels.end());
        EXPECT_TRUE(seen.insert(bitmap).second) << "'" << ch << "' looks like another glyph";
    }
    EXPECT_EQ(pr::text_width("", 1), 0);
    EXPECT_EQ(pr::text_width("ab", 1), pr::kGlyphAdvance + pr::kGlyphWidth);
    EXPECT_EQ(pr::text_width("ab", 2), 2 * (pr::kGlyphAdvance + pr::kGlyphWidth));
}

TEST(GridFont, UnknownBytesDrawAsQuestionMarkAndClipAtTheEdges)
{
    pr::RgbaImage a = solid(8, 12, {255, 255, 255, 255});
    pr::RgbaImage b = a;
    pr::draw_text(a, 1, 10, "\xc3", 1, {0, 0, 0, 255});
    pr::draw_text(b, 1, 10, "?", 1, {0, 0, 0, 255});
    EXPECT_EQ(a.pixels, b.pixels);
    // Partly or wholly outside the image: no crash, nothing written out of bounds.
    pr::draw_text(a, -3, 2, "Wg", 2, {0, 0, 0, 255});
    pr::draw_text(a, 100, 100, "x", 1, {0, 0, 0, 255});
    SUCCEED();
}

} // namespace

// A label of two lines ("name\nIoU …" in compare's grid) gets a strip two lines high for every
// tile, and each line is drawn (and cut to fit) on its own: two upright T's, one above the other.
TEST(Grid, LabelsOfTwoLinesStackTheirLines)
{
    const std::vector<pr::Tile> tiles{{"T\nT", solid(40, 20, {255, 255, 255, 255})},
                                      {"T", solid(40, 20, {255, 255, 255, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    const pr::GridLayout one = pr::plan_grid({tiles[1]}, 1);
    EXPECT_EQ(l.strip_height, one.strip_height + (pr::kGlyphRows + 1) * l.scale);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    for (int k = 0; k < 2; ++k) {
        const glm::ivec2 o = pr::tile_origin(l, k, tiles[k]);
        const std::vector<int> rows = dark_per_row(g, o.x, o.x + l.cell_width, o.y + 20, o.y + 20 + l.strip_height);
        int bars = 0, stems = 0;
        for (int n : rows) {
            bars += n == 5;
            stems += n == 1;
        }
        EXPECT_EQ(bars, k == 0 ? 2 : 1) << "tile " << k;
        EXPECT_EQ(stems, k == 0 ? 12 : 6) << "tile " << k;
    }
    // A line too long for the strip is cut, and the next line still drawn in full.
    const std::vector<pr::Tile> cut{{"TTTTTTTTTTTT\nT", solid(40, 20, {255, 255, 255, 255})}};
    const pr::GridLayout lc = pr::plan_grid(cut, 1);
    const pr::RgbaImage gc = pr::compose_grid(cut, 1);
    const glm::ivec2 oc = pr::tile_origin(lc, 0, cut[0]);
    const std::vector<int> rows = dark_per_row(gc, oc.x, oc.x + lc.cell_width, oc.y + 20, oc.y + 20 + lc.strip_height);
    int widest = 0, bars_of_one = 0;
    for (int n : rows) {
        widest = std::max(widest, n);
        bars_of_one += n == 5;
    }
    EXPECT_EQ(widest, 6 * 5) << "six T's fit 40 px less the padding";
    EXPECT_EQ(bars_of_one, 1) << "the second line's one T";
    // A number is not cut: "T 11111" is seven characters where six fit, and the line ends before
    // the number ("IoU 0.9942" read "IoU 0.9" in a narrow tile), as a label of "T" alone.
    const auto strip = [](const std::string& label) {
        const std::vector<pr::Tile> t{{label, solid(40, 20, {255, 255, 255, 255})}};
        return pr::compose_grid(t, 1).pixels;
    };
    EXPECT_EQ(strip("T 11111"), strip("T"));
    EXPECT_NE(strip("T 1111"), strip("T")) << "six characters fit whole";
}

// A label line too wide for its cell is broken after a ':' where it can, and the strips grow to
// fit: cut at the cell's edge, "prism:relaxed-cone" and "prism:relaxed-cone:exact" both read
// "prism:relaxed-c" in a grid of 96-pixel tiles (found by an exploratory session).
TEST(Grid, LongLabelsBreakAfterAColon)
{
    const std::vector<pr::Tile> tiles{{"prism:relaxed-cone\nIoU 0.9999", solid(96, 8, {255, 0, 0, 255})},
                                      {"prism:relaxed-cone:exact\nIoU 0.9999", solid(96, 8, {255, 0, 0, 255})}};
    const pr::GridLayout l = pr::plan_grid(tiles, 2);
    // "prism:" / "relaxed-cone:" / "exact" / "IoU 0.9999": four lines of 9 rows, a row apart.
    EXPECT_EQ(l.strip_height, 4 * (pr::kGlyphRows + 1) + 2);
    const pr::RgbaImage g = pr::compose_grid(tiles, 2);
    // The two strips differ (the grid's rows are bottom first; the strip lies over its tile).
    const auto strip = [&](int index) {
        const glm::ivec2 o = pr::tile_origin(l, index, tiles[std::size_t(index)]);
        std::vector<std::uint8_t> rows;
        for (int y = o.y + 8; y < o.y + 8 + l.strip_height; ++y)
            for (int x = o.x; x < o.x + l.cell_width; ++x)
                for (int c = 0; c < 4; ++c) rows.push_back(g.pixels[4 * (std::size_t(y) * std::size_t(g.width) + std::size_t(x)) + std::size_t(c)]);
        return rows;
    };
    EXPECT_NE(strip(0), strip(1));
    // A label that fits keeps its one line.
    EXPECT_EQ(pr::plan_grid({{"relief", solid(96, 8, {})}}, 1).strip_height, pr::kGlyphRows + 1 + 2);
    // Where even a part does not fit ("relaxed-cone:" in a 64-pixel tile), it is cut on a line of
    // its own and the rest still breaks: "prism:" / "relaxed-co" / "walk:full" / "IoU 1" (the
    // rest went on the cut line, three lines, and the four variants of relaxed-cone read alike).
    const std::vector<pr::Tile> narrow{{"prism:relaxed-cone:walk:full\nIoU 1", solid(64, 8, {})},
                                       {"prism:relaxed-cone:exact\nIoU 1", solid(64, 8, {})}};
    EXPECT_EQ(pr::plan_grid(narrow, 2).strip_height, 4 * (pr::kGlyphRows + 1) + 2);
}
