// Cone maps as PNG files (docs/cone-maps.md, "File layout"): an RGB PNG, R = height, G = ratio
// (the integer step k of k / 255 or k / 65535, so the file holds exactly the rounded-down
// ratio), B = 0; 8 bits per channel for rg8, 16 bits for rg16. Top row first, as files store it.
//
// stb_image_write writes only 8-bit PNG, so the chunks are written here; the compressed stream
// comes from stb's zlib compressor (stbi_zlib_compress, compiled into pr_core by core/image.cpp),
// so no other library is linked. Reading uses stb_image (also in pr_core).
#include "maps/conemap.hpp"

#include "core/atomic_file.hpp"
#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpedantic"
#include <stb/stb_image.h> // declarations only; the implementation lives in core/image.cpp
#pragma GCC diagnostic pop

// Defined (with C linkage) by stb_image_write's implementation in core/image.cpp; its result is
// malloc'ed (stb's default STBIW_MALLOC).
extern "C" unsigned char* stbi_zlib_compress(unsigned char* data, int data_len, int* out_len, int quality);

namespace pr {
namespace {

std::uint32_t crc32(const std::uint8_t* p, std::size_t n, std::uint32_t crc = 0)
{
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    crc = ~crc;
    for (std::size_t i = 0; i < n; ++i) crc = table[(crc ^ p[i]) & 0xFF] ^ (crc >> 8);
    return ~crc;
}

void put32(std::vector<std::uint8_t>& out, std::uint32_t v)
{
    for (int s = 24; s >= 0; s -= 8) out.push_back(std::uint8_t(v >> s));
}

void chunk(std::vector<std::uint8_t>& out, const char type[4], const std::vector<std::uint8_t>& data)
{
    put32(out, std::uint32_t(data.size()));
    const std::size_t start = out.size();
    out.insert(out.end(), type, type + 4);
    out.insert(out.end(), data.begin(), data.end());
    put32(out, crc32(out.data() + start, out.size() - start));
}

int paeth(int a, int b, int c)
{
    const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
    return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
}

std::vector<std::uint8_t> encode(const ConeMap& map, ConeFormat format)
{
    const int bytes_per_sample = format == ConeFormat::Rg8 ? 1 : 2;
    const int bpp = 3 * bytes_per_sample; // bytes per pixel
    const std::size_t stride = std::size_t(map.width) * std::size_t(bpp);
    // Raw rows, top row first.
    std::vector<std::uint8_t> raw(stride * std::size_t(map.height));
    for (int y = 0; y < map.height; ++y) {
        std::uint8_t* row = raw.data() + std::size_t(map.height - 1 - y) * stride;
        for (int x = 0; x < map.width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(map.width) + std::size_t(x);
            const std::uint32_t h = cone_height_steps(map.heights[i], format);
            const std::uint32_t v[3] = {h, cone_ratio_to_steps(map.ratios[i], format), 0};
            for (int c = 0; c < 3; ++c) {
                if (bytes_per_sample == 1) {
                    row[x * bpp + c] = std::uint8_t(v[c]);
                } else {
                    row[x * bpp + 2 * c] = std::uint8_t(v[c] >> 8);
                    row[x * bpp + 2 * c + 1] = std::uint8_t(v[c]);
                }
            }
        }
    }
    // Filter each row with the PNG filter of least absolute sum (the usual heuristic).
    std::vector<std::uint8_t> filtered((stride + 1) * std::size_t(map.height));
    std::vector<std::uint8_t> candidate(stride);
    for (int y = 0; y < map.height; ++y) {
        const std::uint8_t* cur = raw.data() + std::size_t(y) * stride;
        const std::uint8_t* up = y > 0 ? cur - stride : nullptr;
        std::uint8_t* dst = filtered.data() + std::size_t(y) * (stride + 1);
        long best_sum = -1;
        for (int type = 0; type < 5; ++type) {
            long sum = 0;
            for (std::size_t i = 0; i < stride; ++i) {
                const int a = i >= std::size_t(bpp) ? cur[i - std::size_t(bpp)] : 0;
                const int b = up ? up[i] : 0;
                const int c = (up && i >= std::size_t(bpp)) ? up[i - std::size_t(bpp)] : 0;
                int pred = 0;
                if (type == 1) pred = a;
                else if (type == 2) pred = b;
                else if (type == 3) pred = (a + b) / 2;
                else if (type == 4) pred = paeth(a, b, c);
                candidate[i] = std::uint8_t(cur[i] - pred);
                sum += std::abs(int(std::int8_t(candidate[i])));
            }
            if (best_sum < 0 || sum < best_sum) {
                best_sum = sum;
                dst[0] = std::uint8_t(type);
                std::copy(candidate.begin(), candidate.end(), dst + 1);
            }
        }
    }
    if (filtered.size() > std::size_t(1) << 30) throw Error("PNG", "cone map too large to encode");
    int zlen = 0;
    std::unique_ptr<unsigned char, decltype(&std::free)> z(
        stbi_zlib_compress(filtered.data(), int(filtered.size()), &zlen, 8), &std::free);
    if (!z) throw Error("PNG", "compression failed");

    std::vector<std::uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    std::vector<std::uint8_t> ihdr;
    put32(ihdr, std::uint32_t(map.width));
    put32(ihdr, std::uint32_t(map.height));
    ihdr.push_back(std::uint8_t(8 * bytes_per_sample)); // bit depth
    ihdr.push_back(2);                                  // colour type: RGB
    ihdr.push_back(0);                                  // deflate
    ihdr.push_back(0);                                  // adaptive filtering
    ihdr.push_back(0);                                  // no interlace
    chunk(out, "IHDR", ihdr);
    chunk(out, "IDAT", std::vector<std::uint8_t>(z.get(), z.get() + zlen));
    chunk(out, "IEND", {});
    return out;
}

} // namespace

std::vector<std::uint8_t> encode_cone_png(const std::filesystem::path& path, const ConeMap& map, ConeFormat format)
{
    const std::size_t n = std::size_t(std::max(map.width, 0)) * std::size_t(std::max(map.height, 0));
    if (map.width < 1 || map.height < 1 || map.heights.size() != n || map.ratios.size() != n)
        throw Error(path.string(), "cannot write an empty or inconsistent cone map");
    try {
        return encode(map, format);
    } catch (const Error& e) {
        throw Error(path.string(), e.problem());
    }
}

void write_cone_png(const std::filesystem::path& path, const ConeMap& map, ConeFormat format)
{
    write_file_atomic(path, encode_cone_png(path, map, format));
}

ConeMap read_cone_png(const std::filesystem::path& path, ConeKind kind)
{
    const std::string name = path.string();
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(name, "cannot open");
    std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    static const std::uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    if (bytes.size() < 33 || std::memcmp(bytes.data(), signature, 8) != 0)
        throw Error(name, "not a PNG file (a cone map is an RGB PNG: R height, G ratio)");
    if (bytes.size() > std::size_t(1) << 30) throw Error(name, "file too large");
    drop_empty_png_idat(bytes);
    const int len = int(bytes.size());
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(bytes.data(), len, &w, &h, &comp))
        throw Error(name, std::string("not a readable PNG (") + stbi_failure_reason() + ")");
    check_image_dimensions(name, w, h);
    if (comp != 3 && comp != 4)
        throw Error(name, "a cone map has RGB channels (R height, G ratio); this file has " + std::to_string(comp));
    const bool wide = stbi_is_16_bit_from_memory(bytes.data(), len) != 0;
    const ConeFormat format = wide ? ConeFormat::Rg16 : ConeFormat::Rg8;
    const int steps = cone_format_steps(format);
    ConeMap map;
    map.width = w;
    map.height = h;
    map.kind = kind;
    map.heights.resize(std::size_t(w) * std::size_t(h));
    map.ratios.resize(map.heights.size());
    int n = 0;
    const std::vector<float>& ratio_of = cone_ratio_table(format);
    const auto fill = [&](auto* data) {
        if (!data) throw Error(name, std::string("truncated or corrupt PNG (") + stbi_failure_reason() + ")");
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x) {
                const auto* px = data + (std::size_t(h - 1 - y) * std::size_t(w) + std::size_t(x)) * 3;
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                map.heights[i] = float(px[0]) / float(steps);
                map.ratios[i] = ratio_of[px[1]]; // px[1] <= steps: 8 bits for rg8, 16 for rg16
            }
        stbi_image_free(data);
    };
    if (wide) fill(stbi_load_16_from_memory(bytes.data(), len, &w, &h, &n, 3));
    else fill(stbi_load_from_memory(bytes.data(), len, &w, &h, &n, 3));
    return map;
}

} // namespace pr
