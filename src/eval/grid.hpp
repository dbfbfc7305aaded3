#pragma once
// The comparison figure of `compare`: a silhouette-difference tile and a labelled grid of tiles,
// with a small built-in bitmap font so no font file or library is needed. CPU only.
//
// Row order: like every RgbaImage here, inputs and outputs store the bottom row first, so "above"
// means higher row indices. The grid is opaque (alpha 255 everywhere): it is a figure for people,
// not a render, so the contract's alpha = coverage rule does not apply to it.
#include "core/image.hpp"

#include <string>
#include <string_view>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace pr {

// Colours of silhouette_diff_tile, public so a caller can write a legend that matches.
inline constexpr glm::u8vec4 kDiffOnlyTechnique{255, 0, 255, 255}; // magenta: extra coverage
inline constexpr glm::u8vec4 kDiffOnlyReference{0, 200, 255, 255};  // cyan: missing coverage
inline constexpr glm::u8vec4 kDiffNeither{40, 40, 40, 255};         // dark grey background
// Pixels both cover show the technique's luminance mapped into [kDiffBothLow, kDiffBothHigh]:
// the shape stays recognisable but never reaches the saturated colours or the background.
inline constexpr int kDiffBothLow = 96;
inline constexpr int kDiffBothHigh = 224;

// Opaque tile the size of the inputs: only in the technique -> kDiffOnlyTechnique, only in the
// reference -> kDiffOnlyReference, in both -> grey from the technique's luminance, in neither ->
// kDiffNeither. Coverage as in metrics (alpha >= 128). Different sizes throw pr::Error.
RgbaImage silhouette_diff_tile(const RgbaImage& technique, const RgbaImage& reference);

struct Tile {
    std::string label; // lines separated by '\n', a line too wide broken after a ':' where it can;
                       // the strips fit the most lines, each line cut to fit
    RgbaImage image;
};

// How compose_grid places things; exposed so tests (and callers that annotate the figure) need
// not repeat the arithmetic.
struct GridLayout {
    int columns = 0;      // min(requested, tile count)
    int rows = 0;
    int cell_width = 0;   // the widest tile
    int cell_height = 0;  // the tallest tile
    int scale = 1;        // font scale: 2 when cells are at least 256 px wide
    int strip_height = 0; // label strip above each tile
    int margin = 0;       // around and between cells
    int width = 0;
    int height = 0;
};
GridLayout plan_grid(const std::vector<Tile>& tiles, int columns);

// Lower-left corner, in the grid image (bottom row first), of tile `index`'s image. Its label
// strip spans rows [y + h, y + h + strip_height) right above it (h = the tile's height) and
// columns [x, x + cell_width); smaller tiles sit at the top-left of their cell.
glm::ivec2 tile_origin(const GridLayout& layout, int index, const Tile& tile);

// Tiles in row-major order, `columns` per row, first tile at the top left, each under a white
// strip with its label in black. Tiles are composited over a grey checker (or, when
// `background_colour_hint` is given and not empty, over the flat RGB of its pixel (0,0)) so what a
// tile leaves transparent shows as background. Label lines too long for the cell are broken after
// a ':' where they can, else cut at the last whole character that fits. Throws
// pr::Error("grid", ...) on no tiles or columns < 1.
RgbaImage compose_grid(const std::vector<Tile>& tiles, int columns,
                       const RgbaImage* background_colour_hint = nullptr);

// ---- the bitmap font (also usable for legends) ----
// Glyphs are 5x9 cells (7 rows above the baseline, 2 for descenders), advanced by 6 pixels, all
// times `scale`. Printable ASCII has glyphs; any other byte draws as '?'.
inline constexpr int kGlyphWidth = 5;
inline constexpr int kGlyphRows = 9;
inline constexpr int kGlyphAdvance = 6;
int text_width(std::string_view text, int scale);
// Draws `text` with its cell's top-left corner at column x, row y_top (bottom-row-first storage:
// y_top is the highest row the text may touch; glyphs extend down to y_top - 9*scale + 1).
// Pixels outside the image are skipped.
void draw_text(RgbaImage& image, int x, int y_top, std::string_view text, int scale,
               glm::u8vec4 colour);

} // namespace pr
