#pragma once
// Images and height fields: loading (stb), built-in procedural maps, PNG output. No GL here.
//
// Row order: every in-memory image in prismrelief stores its *bottom* row first (row 0 is
// v = 0), matching the contract's UV origin (bottom-left) and glTexImage2D. Files store the top
// row first, so loaders flip and writers flip back.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

namespace pr {

// Limits on what inputs may claim (pre-checked before decoding, so absurd headers fail early).
struct ImageLimits {
    int max_dimension = 16384;          // width and height, each
    std::int64_t max_pixels = 1 << 26;  // 64 Mpixel
};

// Scalar height field h in [0,1]: the first channel of the image, full precision (16-bit input
// keeps 16 bits). Repeat wrap; texel centres at ((i+0.5)/w, (j+0.5)/h).
struct HeightField {
    int width = 0;
    int height = 0;
    int bits = 8;                // 8 or 16: precision of the source, chooses R8 or R16 on the GPU
    std::string name;            // file path or "builtin:NAME", for messages and cache keys
    std::vector<float> texels;   // width*height, bottom row first

    float at(int x, int y) const; // wrapped texel fetch
    // Bilinear sample at uv (UV origin bottom-left, repeat wrap, texel centres at (i+0.5)/n):
    // the exact function the reference geometry and the GPU's level-0 bilinear fetch share.
    float sample(glm::vec2 uv) const;
    float min_value() const;
    float max_value() const;
};

// RGBA8 straight-alpha image, bottom row first.
struct RgbaImage {
    int width = 0;
    int height = 0;
    std::vector<std::uint8_t> pixels; // width*height*4

    glm::u8vec4 at(int x, int y) const { const auto* p = &pixels[4 * (std::size_t(y) * width + x)]; return {p[0], p[1], p[2], p[3]}; }
};

// `spec` is a file (PNG, JPEG, BMP, TGA, binary PNM, HDR, GIF, PSD, PIC; 8 or 16 bit; first channel) or "builtin:NAME" (see
// builtin_height_names()). Throws pr::Error naming the file on any problem (missing, not an
// image, truncated, 0x0, too large).
// Throws pr::Error(subject, …) when a w x h image is empty or exceeds `limits` (every image read
// checks its header's size with it before decoding).
void check_image_dimensions(const std::string& subject, std::int64_t w, std::int64_t h, const ImageLimits& limits = {});

// Removes empty IDAT chunks from PNG bytes (stb_image 2.27 has undefined behaviour on them; see
// image.cpp). Other bytes, and non-PNG input, are left as they are. Every PNG read goes through it.
void drop_empty_png_idat(std::vector<std::uint8_t>& bytes);

HeightField load_height(const std::string& spec, const ImageLimits& limits = {});

// Colour texture: a file (any stb format; grey, grey+alpha, RGB, RGBA, paletted) or "builtin:NAME"
// (see builtin_color_names()). Throws pr::Error naming the file.
RgbaImage load_color(const std::string& spec, const ImageLimits& limits = {});

// Names accepted after "builtin:" (e.g. "bumps", "bricks", "noise", ...), each tileable.
std::vector<std::string> builtin_height_names();
std::vector<std::string> builtin_color_names();
// For a "builtin:NAME[@N|@WxH]" map: its name and size checked as load_height (`color` false) or
// load_color would check them, without making the map (a scene file's map that a flag
// replaces); throws pr::Error naming `spec`. Nothing for a file name.
void check_builtin_name(const std::string& spec, bool color, const ImageLimits& limits);

// Whether stb can encode a width x height RGBA PNG: it filters the rows into one buffer whose size,
// (4 width + 1) height bytes, it keeps in an int (past 2 GiB it wrapped, and the buffer it
// allocated was too small for the rows written into it), and so the compressed stream's, which
// may be 9/8 of it.
bool png_encodable(int width, int height);
// Encodes `image` (bottom row first) as PNG, top row first as files store it; refuses an image
// png_encodable() says no to.
std::vector<std::uint8_t> encode_png(const RgbaImage& image);
// The same, for the file `path`: a failure is reported under that name (a staged write).
std::vector<std::uint8_t> encode_png_for(const std::filesystem::path& path, const RgbaImage& image);
// Encodes and writes atomically (temporary file + rename). Throws pr::Error naming `path`.
void write_png(const std::filesystem::path& path, const RgbaImage& image);
// Reads a PNG written by write_png (or any 8-bit image) back as RGBA, bottom row first.
RgbaImage read_rgba(const std::filesystem::path& path);

} // namespace pr
