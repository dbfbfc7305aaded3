#include "core/image.hpp"
#include "core/image_checks.hpp"

#include "core/atomic_file.hpp"
#include "core/builtin_maps.hpp"
#include "core/error.hpp"
#include "core/input_file.hpp"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string_view>

#include <fmt/format.h>

// stb is third-party code that does not build cleanly under -Wall -Wextra (GCC 12 flags its
// aggregate initializers; other compilers and versions find more); silence it here only.
// Failure strings stay on (the default) so errors can say why a file was rejected.
// Note: stb_image is not hardened against hostile input in every decoder. The header check
// against ImageLimits below bounds the image size a file may claim before anything is decoded;
// it does not make stb safe against crafted files.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wstringop-overflow"
#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO // we write through write_file_atomic, never stb's fopen
#include <stb_image.h>
#include <stb_image_write.h>
#pragma GCC diagnostic pop

namespace pr {
namespace {

// Apple's CgBI PNGs (Xcode's "optimized" form: BGRA, colour premultiplied by alpha, raw deflate):
// stb reads their data but leaves it as stored unless told, so a red map came out blue and a
// height read the blue channel (found by an exploratory session, fiftieth). Told once, before any
// decode; the flags act on CgBI files only.
const bool kCgbiConverted = [] {
    stbi_convert_iphone_png_to_rgb(1);
    stbi_set_unpremultiply_on_load(1);
    return true;
}();

struct StbiFree {
    void operator()(void* p) const { stbi_image_free(p); }
};
template <typename T>
using StbiPtr = std::unique_ptr<T, StbiFree>;

int wrap_index(std::int64_t i, int n)
{
    const std::int64_t r = i % n;
    return static_cast<int>(r < 0 ? r + n : r);
}

// How many bytes an image file within `limits` may take, so that a huge file is refused by its
// size and a pipe stops being read there, before the header can be checked. The largest pixel
// stb_image decodes is 8 bytes (16-bit RGBA PNG or PSD; 16-bit RGB PNM is 6, BMP/TGA/HDR/PIC at
// most 5 with their run-length codes); PNG's stored (uncompressed) deflate blocks and row filter
// bytes add well under 1 %, and a JPEG of pure RGB noise at quality 100 takes 4.1 bytes a pixel
// (stb_image_write, 512x512). The other 64 MiB is for what a file may carry besides pixels
// (EXIF, ICC profiles, text chunks).
// With the default 64 Mpixel that is 576 MiB; stb takes an int length, so never more than 2 GiB.
std::uint64_t max_image_file_bytes(const ImageLimits& limits)
{
    constexpr std::uint64_t kBytesPerPixel = 8, kExtra = std::uint64_t(64) << 20;
    const std::uint64_t pixels = std::uint64_t(std::max<std::int64_t>(limits.max_pixels, 1));
    const std::uint64_t stb_max = std::uint64_t(INT_MAX);
    if (pixels > (stb_max - kExtra) / kBytesPerPixel) return stb_max;
    return pixels * kBytesPerPixel + kExtra;
}

// The whole file (core/input_file: devices refused, a FIFO with no writer not waited on forever,
// pipes and regular files capped).
std::vector<std::uint8_t> read_file(const std::string& path, const ImageLimits& limits)
{
    std::vector<std::uint8_t> bytes = read_input_bytes(
        path, {max_image_file_bytes(limits), "an image",
               fmt::format("the most an image within the limit of {} pixels can take (8 bytes "
                           "a pixel, and 64 MiB)", limits.max_pixels)});
    if (bytes.empty()) throw Error(path, "is empty");
    return bytes;
}

// stb's failure reasons are terse codes ("outofdata", "bad png sig"); say what they mean.
// Reason codes stb leaves from another format's signature test, not the file's own decoder's
// (some decoders, a JPEG cut inside its tables, fail without one of their own).
bool another_decoders_code(const std::string& code)
{
    return code == "bad png sig" || code == "not GIF" || code == "no SOI";
}

// A code that can be shown: stb names an unknown critical PNG chunk by its type, whatever its
// bytes (four zeros made the reason empty).
bool showable_code(const std::string& code)
{
    return !code.empty() && std::all_of(code.begin(), code.end(), [](char ch) { return ch >= ' ' && ch <= '~'; });
}

std::string stb_reason()
{
    const char* raw = stbi_failure_reason();
    const std::string code = raw ? raw : "unknown error";
    if (code == "unknown image type")
        return "unknown format; readable formats: PNG, JPEG, BMP, TGA, GIF, PSD, HDR, PIC, binary PNM (P5, P6)";
    if (code == "outofdata" || code == "read past buffer" || code == "not enough pixels" ||
        code == "bad file" || code == "no IDAT")
        return "truncated or corrupt data: " + code;
    // Some decoders (JPEG cut inside its tables) fail without a reason of their own, leaving the
    // stale one of another format's signature test: the header was readable, the data was not.
    if (another_decoders_code(code)) return "truncated or corrupt data";
    // (A JPEG whose scan data ends, cut short or without its end marker: "corrupt or unsupported:
    // expected marker" until the fiftieth session; found by an exploratory session.)
    if (code == "expected marker")
        return "truncated or corrupt data: the JPEG's data ends where a marker should come: a file cut short, "
               "or damaged";
    if (code == "0-pixel image" || code == "0 width") return "the image has no pixels (0x0)";
    if (code == "too large") return "its header claims absurd dimensions";
    if (code == "outofmem") return "out of memory while decoding";
    // stb names an unknown critical PNG chunk by its type, whatever its bytes: four zeros made
    // the reason empty ("corrupt or unsupported: "). check_png leaves few such files to stb.
    if (!showable_code(code)) return "corrupt data";
    return "corrupt or unsupported: " + code;
}

[[noreturn]] void fail_decode(const std::string& subject)
{
    throw Error(subject, "not a supported image (" + stb_reason() + ")");
}

// A Softimage PIC file: its magic number, and "PICT" at byte 88.
bool is_pic(const std::vector<std::uint8_t>& b)
{
    return b.size() >= 92 && b[0] == 0x53 && b[1] == 0x80 && b[2] == 0xF6 && b[3] == 0x34 &&
           std::memcmp(&b[88], "PICT", 4) == 0;
}

// Dimensions straight from the header of the formats whose size sits at a fixed offset, so the
// limits apply even where stb's own check refuses first (its PNG header check rejects anything
// over 2^30 bytes and then reports only "unknown image type") and so 0x0 is named as such.
struct Sniffed {
    const char* format;
    std::optional<std::int64_t> width, height; // absent when the header is cut short
};

std::optional<Sniffed> sniff(const std::vector<std::uint8_t>& b)
{
    const auto be32 = [&b](std::size_t o) {
        return std::int64_t(std::uint32_t(b[o]) << 24 | std::uint32_t(b[o + 1]) << 16 |
                            std::uint32_t(b[o + 2]) << 8 | std::uint32_t(b[o + 3]));
    };
    const auto le32 = [&b](std::size_t o) {
        return std::int64_t(std::int32_t(std::uint32_t(b[o]) | std::uint32_t(b[o + 1]) << 8 |
                                         std::uint32_t(b[o + 2]) << 16 |
                                         std::uint32_t(b[o + 3]) << 24));
    };
    const auto le16 = [&b](std::size_t o) { return std::int64_t(b[o] | b[o + 1] << 8); };
    const auto starts = [&b](std::string_view magic) {
        return b.size() >= magic.size() &&
               std::equal(magic.begin(), magic.end(), b.begin(),
                          [](char m, std::uint8_t c) { return static_cast<std::uint8_t>(m) == c; });
    };
    if (starts("\x89PNG\r\n\x1a\n")) {
        if (b.size() >= 24 && std::memcmp(&b[12], "IHDR", 4) == 0)
            return Sniffed{"PNG", be32(16), be32(20)};
        return Sniffed{"PNG", {}, {}};
    }
    if (starts("BM") && b.size() >= 26 && le32(14) >= 40)
        return Sniffed{"BMP", le32(18), std::abs(le32(22))}; // negative height: top-down rows
    if (starts("GIF87a") || starts("GIF89a")) {
        if (b.size() >= 10) return Sniffed{"GIF", le16(6), le16(8)};
        return Sniffed{"GIF", {}, {}};
    }
    if (starts("8BPS")) {
        if (b.size() >= 22) return Sniffed{"PSD", be32(18), be32(14)};
        return Sniffed{"PSD", {}, {}};
    }
    // (Named, not "unknown format" where they are listed as readable: a Radiance file in a layout
    // stb does not read, a PIC with no pixel data; found by an exploratory session, thirty-fifth.)
    if (starts("#?RADIANCE\n") || starts("#?RGBE\n")) return Sniffed{"HDR", {}, {}};
    if (is_pic(b)) {
        if (b.size() >= 96) return Sniffed{"PIC", std::int64_t(b[92] << 8 | b[93]), std::int64_t(b[94] << 8 | b[95])};
        return Sniffed{"PIC", {}, {}};
    }
    return std::nullopt;
}

} // namespace

void check_image_dimensions(const std::string& subject, std::int64_t w, std::int64_t h, const ImageLimits& limits)
{
    if (w <= 0 || h <= 0)
        throw Error(subject, fmt::format("the image is {}x{} pixels: nothing to use", w, h));
    if (w > limits.max_dimension || h > limits.max_dimension)
        throw Error(subject, fmt::format("the image is {}x{} pixels, more than the limit of {} "
                                         "per side",
                                         w, h, limits.max_dimension));
    const std::int64_t pixels = w * h;
    if (pixels > limits.max_pixels)
        throw Error(subject, fmt::format("the image is {}x{} = {} pixels, more than the limit "
                                         "of {}",
                                         w, h, pixels, limits.max_pixels));
}

namespace {

// stb_image 2.27 (Debian 12) trusts the symbol counts of a JPEG Huffman table (DHT segment): a
// table of more than 256 symbols writes past its arrays (found by tests/fuzz/fuzz_image; later
// stb versions refuse it). It also decodes a scan with a Huffman table that no DHT defined:
// the table is uninitialized memory and the decoder indexes its arrays with garbage (found by
// tests/fuzz/fuzz_image). Walk the marker segments the way stb reads them and refuse both
// before stb sees the file.
void check_jpeg_tables(const std::string& subject, const std::vector<std::uint8_t>& b)
{
    const auto at = [&b](std::size_t i) -> unsigned { return i < b.size() ? b[i] : 0u; }; // stb reads 0 past the end
    std::size_t i = jpeg_start(b);
    if (i == 0) return; // not JPEG
    bool defined[2][4] = {}; // [0: DC, 1: AC][table id]: set by a DHT
    bool progressive = false;
    while (i + 1 < b.size()) {
        if (b[i] != 0xFF) { // entropy-coded data or junk: stb skips to the next marker
            ++i;
            continue;
        }
        const unsigned m = b[i + 1];
        if (m == 0xFF) { // fill bytes
            ++i;
            continue;
        }
        if (m == 0xD9) return; // EOI
        if (m == 0x00 || m == 0x01 || m == 0xD8 || (m >= 0xD0 && m <= 0xD7)) { // no length
            i += 2;
            continue;
        }
        const std::size_t length = at(i + 2) << 8 | at(i + 3);
        if (m == 0xC4) {
            long remaining = long(length) - 2;
            std::size_t p = i + 4;
            while (remaining > 0 && p < b.size()) {
                unsigned n = 0;
                for (std::size_t k = 1; k <= 16; ++k) n += at(p + k);
                if (n > 256)
                    throw Error(subject, fmt::format("not a supported image (corrupt JPEG: a Huffman "
                                                     "table of {} symbols, at most 256)",
                                                     n));
                const unsigned tc = at(p) >> 4, th = at(p) & 15; // stb refuses tc > 1, th > 3
                if (tc <= 1 && th <= 3) defined[tc][th] = true;
                p += 17 + n;
                remaining -= long(17 + n);
            }
        } else if (m == 0xC2) {
            progressive = true;
        } else if (m == 0xDA) {
            // SOS: Ns, then Ns x (component, DC table << 4 | AC table), then Ss, Se, Ah << 4 | Al.
            // The tables stb's decoder will use must exist (out-of-range ids stb refuses itself).
            const unsigned ns = at(i + 4);
            const unsigned ss = at(i + 5 + 2 * ns), ah = at(i + 7 + 2 * ns) >> 4;
            const bool uses_dc = !progressive || (ss == 0 && ah == 0);
            const bool uses_ac = !progressive || ss != 0;
            for (unsigned c = 0; c < ns && c < 4; ++c) {
                const unsigned td = at(i + 6 + 2 * c) >> 4, ta = at(i + 6 + 2 * c) & 15;
                const char* missing = uses_dc && td <= 3 && !defined[0][td]   ? "DC"
                                      : uses_ac && ta <= 3 && !defined[1][ta] ? "AC"
                                                                              : nullptr;
                if (missing)
                    throw Error(subject, fmt::format("not a supported image (corrupt JPEG: a scan uses "
                                                     "{} Huffman table {}, which no DHT segment defines)",
                                                     missing, std::string_view(missing) == "DC" ? td : ta));
            }
        }
        // (A segment past the end, once what it holds is checked: stb reported "unknown image
        // type", which said the format was not JPEG; found by an exploratory session, thirtieth.)
        if (i + 2 + length > b.size())
            throw Error(subject, fmt::format("not a supported image (truncated or corrupt data: the JPEG "
                                             "segment FF{:02X} at byte {} is {} bytes long, past the end of "
                                             "the file)",
                                             m, i, length));
        i += 2 + length;
    }
}

// stb_image 2.27 (Debian 12) copies an IDAT chunk's data with memcpy even when the chunk is
// empty; for an empty IDAT before any data the destination is a null pointer (undefined
// behaviour, found by tests/fuzz/fuzz_image). Empty IDAT chunks carry nothing: drop them before
// stb sees the file. Chunks are walked as stb walks them (length, type, data, CRC); a chunk that
// runs past the end stops the walk and is left for check_png to refuse.
} // namespace

void drop_empty_png_idat(std::vector<std::uint8_t>& b)
{
    std::vector<std::size_t> empty; // the empty IDAT chunks' offsets
    walk_png_chunks(b, [&](std::size_t at, std::uint32_t length, std::string_view type) {
        if (length == 0 && type == "IDAT") empty.push_back(at);
        return true;
    });
    if (empty.empty()) return;
    std::size_t out = empty.front();
    for (std::size_t k = 0; k < empty.size(); ++k) { // what lies between one and the next (or the end) moves up
        const std::size_t from = empty[k] + 12, to = k + 1 < empty.size() ? empty[k + 1] : b.size();
        std::memmove(b.data() + out, b.data() + from, to - from);
        out += to - from;
    }
    b.resize(out);
}

namespace {

// Image bytes whose header passed the limits: decoding may allocate w*h*channels safely.
struct Checked {
    const stbi_uc* data;
    int len;
};

Checked check_header(const std::string& subject, std::vector<std::uint8_t>& bytes,
                     const ImageLimits& limits)
{
    if (bytes.empty()) throw Error(subject, "not a supported image (empty file)");
    check_jpeg_tables(subject, bytes);
    drop_empty_png_idat(bytes);
    const std::optional<Sniffed> sniffed = sniff(bytes);
    if (sniffed && sniffed->width && sniffed->height)
        check_image_dimensions(subject, *sniffed->width, *sniffed->height, limits);
    check_png(subject, bytes);
    // A PNM's header before stb's first look at it (check_pnm_header: stb's reader overflows, and
    // the ASCII and bitmap forms it does not read are named).
    if (const auto pnm = check_pnm_header(subject, bytes)) check_image_dimensions(subject, pnm->first, pnm->second, limits);
    const Checked c{bytes.data(), static_cast<int>(bytes.size())};
    int w = 0, h = 0, comp = 0;
    if (!stbi_info_from_memory(c.data, c.len, &w, &h, &comp)) {
        // stb tried every decoder and kept the last one's reason; with a known signature, the
        // useful thing to say is which format is damaged.
        // Its own decoder's reason, where the format is known (stb's info tried every decoder
        // and kept the last one's, so a greyscale PSD or a run-length BMP read "corrupt or
        // unsupported PSD" without stb's why; found by an exploratory session, thirty-fifth).
        // Asked for 4 channels: stb's PIC decoder converts a failed decode's null (req 0 crashed).
        if (sniffed || jpeg_start(bytes) != 0) {
            const std::string format = sniffed ? sniffed->format : std::string("JPEG");
            // (Not a PIC: its decoder allocates and clears the whole image before it reads a
            // packet, and its info fails only in the packets: 1 GiB for a 108-byte file; found by
            // a review. The other decoders refuse in their headers, before allocating.)
            if (format == "PIC")
                throw Error(subject, "not a supported image (truncated or corrupt PIC: its pixel packets are damaged or cut short)");
            stbi_image_free(stbi_load_from_memory(c.data, c.len, &w, &h, &comp, 4));
            const char* raw = stbi_failure_reason();
            const std::string why = raw ? raw : "";
            if (why == "outofmem") fail_decode(subject); // ("out of memory while decoding")
            const bool own = showable_code(why) && !another_decoders_code(why) && why != "unknown image type" &&
                             why != "not TGA";
            // stb's words for what it leaves out, said as what to do.
            const std::string said = why == "wrong color format" ? "not in RGB colour mode (stb reads RGB PSD only): save it as RGB"
                                     : why == "BMP RLE"          ? "run-length compressed (stb reads uncompressed BMP only)"
                                     // (Said of an empty PLTE too; found by an exploratory session, fiftieth.)
                                     : why == "no PLTE" ? "a palette image without the colours of its palette (PLTE)"
                                     : why == "unsupported data layout"
                                         ? "a pixel layout other than -Y height +X width (the only one stb reads)"
                                         : why;
            throw Error(subject, fmt::format("not a supported image (corrupt or unsupported {}{})", format,
                                             own ? ": " + said : std::string()));
        }
        fail_decode(subject);
    }
    // (stb 2.27 reports a top-down BMP's height negative, as its header stores it: "8x-8 pixels".)
    check_image_dimensions(subject, w, std::abs(std::int64_t(h)), limits);
    check_image_data(subject, bytes);
    return c;
}

// A file whose data ends before its pixels do (decode_image, check_gif_frame).
constexpr const char* kEndsBeforeItsPixels =
    "not a supported image (truncated or corrupt data: the file ends before its pixels do)";

// stb's decode of `c` by `decode` (stbi_load_from_memory's arguments). Where a decoder could
// read past the end without failing (needs_padding_check: every format but PNG, JPEG and HDR),
// it decodes the bytes followed by kPadding zeros and again followed by as many 0xFF bytes: a
// file that ends before its pixels do gives two different images (stb read zeros past the end,
// and such rows came out black: BMP, GIF, PSD, run-length TGA cut short). A palette PNG whose
// indices could run past its PLTE is decoded twice the same way, with two palettes filled up.
template <typename T, typename Decode>
StbiPtr<T> decode_image(const std::string& subject, const std::vector<std::uint8_t>& bytes, const Checked& c,
                        int* w, int* h, int* n, int channels, Decode decode)
{
    // stb 2.27's PIC decoder frees its result on a damaged file and then converts it to the
    // channels asked for: a null pointer read where they differ from the file's (a height map asks
    // for its own, 0: a segmentation fault; found by an exploratory session, thirty-fifth). Asked
    // for 4, as many as it decodes to, and given back in the file's own.
    if (channels == 0 && is_pic(bytes)) {
        StbiPtr<T> four = decode_image<T>(subject, bytes, c, w, h, n, 4, decode);
        if (!four || *n == 4) return four;
        const std::size_t count = std::size_t(*w) * std::size_t(*h), k = std::size_t(std::clamp(*n, 1, 4));
        StbiPtr<T> own(static_cast<T*>(STBI_MALLOC(count * k * sizeof(T))));
        if (!own) throw Error(subject, "out of memory");
        for (std::size_t i = 0; i < count; ++i)
            for (std::size_t j = 0; j < k; ++j) own.get()[i * k + j] = four.get()[i * 4 + j];
        return own;
    }
    constexpr std::size_t kPadding = 64;
    if (std::optional<PngPaletteProbe> probe = png_palette_probe(bytes)) {
        // A palette PNG whose PLTE leaves some indices uncovered: decoded with the palette filled
        // up two ways (png_palette_probe), a pixel whose index is past the file's own entries
        // comes out different, its index in the first's red.
        if (probe->low.size() > std::size_t(INT_MAX)) // (stb takes an int length)
            throw Error(subject, "not a supported image (a palette PNG of 2 GiB)");
        StbiPtr<T> low(decode(probe->low.data(), int(probe->low.size()), w, h, n, channels));
        if (!low) return low;
        int w2 = 0, h2 = 0, n2 = 0;
        StbiPtr<T> high(decode(probe->high.data(), int(probe->high.size()), &w2, &h2, &n2, channels));
        if (!high || w2 != *w || h2 != *h || n2 != *n) fail_decode(subject); // (it decoded once)
        const std::size_t stride = std::size_t(channels ? channels : *n), count = std::size_t(*w) * std::size_t(*h);
        std::optional<unsigned> index;
        for (std::size_t k = 0; k < count; ++k)
            if (low.get()[k * stride] != high.get()[k * stride]) index = std::max(index.value_or(0), unsigned(low.get()[k * stride]));
        if (index)
            throw Error(subject, fmt::format("not a supported image (corrupt PNG: a pixel's colour index is {}, past "
                                             "its palette of {} colours)",
                                             *index, probe->entries));
        return low;
    }
    if (!needs_padding_check(bytes) || c.len > INT_MAX - int(kPadding))
        return StbiPtr<T>(decode(c.data, c.len, w, h, n, channels));
    std::vector<stbi_uc> padded(c.data, c.data + c.len);
    padded.resize(std::size_t(c.len) + kPadding, 0x00);
    StbiPtr<T> zeros(decode(padded.data(), int(padded.size()), w, h, n, channels));
    std::fill(padded.begin() + c.len, padded.end(), stbi_uc(0xFF));
    int w2 = 0, h2 = 0, n2 = 0;
    StbiPtr<T> ones(decode(padded.data(), int(padded.size()), &w2, &h2, &n2, channels));
    if (!zeros && !ones) return zeros;
    const std::size_t count = zeros ? std::size_t(*w) * std::size_t(*h) * std::size_t(channels ? channels : *n) : 0;
    if (!zeros || !ones || w2 != *w || h2 != *h || n2 != *n ||
        std::memcmp(zeros.get(), ones.get(), count * sizeof(T)) != 0)
        throw Error(subject, kEndsBeforeItsPixels);
    return zeros;
}

// Decoders that learn the size late (JPEG's DNL marker) could disagree with the header.
void check_decoded(const std::string& subject, int w, int h, const ImageLimits& limits)
{
    check_image_dimensions(subject, w, h, limits);
}

float quantize16(float x) { return std::round(std::clamp(x, 0.0f, 1.0f) * 65535.0f) / 65535.0f; }

// Keeps channel 0 of an interleaved image with `n` channels, flipping to bottom row first.
// Warns once when the other colour channels differ: a colour picture used as a height.
template <typename T, typename Convert>
void take_first_channel(HeightField& hf, const T* src, int n, Convert convert)
{
    const int w = hf.width, h = hf.height;
    hf.texels.resize(std::size_t(w) * h);
    bool colour = false;
    for (int y = 0; y < h; ++y) {
        const T* row = src + std::size_t(h - 1 - y) * w * n;
        for (int x = 0; x < w; ++x) {
            const T* p = row + std::size_t(x) * n;
            hf.texels[std::size_t(y) * w + x] = convert(p[0]);
            if (n >= 3 && (p[1] != p[0] || p[2] != p[0])) colour = true;
        }
    }
    if (colour) warn(hf.name + ": colour image; using its first (red) channel as the height");
}

bool is_pnm(const std::vector<std::uint8_t>& b)
{
    return b.size() >= 2 && b[0] == 'P' && (b[1] == '5' || b[1] == '6');
}

// stb_image 2.27 (Debian 12) copies 16-bit PNM samples without converting them from big endian,
// so on little-endian machines they come out byte-swapped. Decoding a one-pixel PGM once tells
// whether this stb has the bug, so a fixed stb needs no change here.
bool stb_swaps_16_bit_pnm()
{
    static const bool swaps = [] {
        const std::uint8_t pgm[] = {'P', '5', ' ', '1', ' ', '1', ' ', '6', '5', '5', '3', '5',
                                    '\n', 0x01, 0x02};
        int w = 0, h = 0, n = 0;
        StbiPtr<stbi_us> px(stbi_load_16_from_memory(pgm, sizeof pgm, &w, &h, &n, 1));
        return px && px.get()[0] == 0x0201;
    }();
    return swaps;
}

// stb_image 2.27 reads a TGA's vertical origin (descriptor bit 5) but not its horizontal one
// (bit 4, pixels stored right to left): such a file came out mirrored.
template <typename T>
void fix_tga_origin(const std::vector<std::uint8_t>& bytes, T* pixels, int w, int h, int n)
{
    if (!is_tga(bytes) || !(bytes[17] & 0x10)) return;
    for (int y = 0; y < h; ++y) {
        T* row = pixels + std::size_t(y) * w * n;
        for (int a = 0, b = w - 1; a < b; ++a, --b)
            for (int k = 0; k < n; ++k) std::swap(row[std::size_t(a) * n + k], row[std::size_t(b) * n + k]);
    }
}

// Turns stb's pixels (top row first, as stored) as a JPEG's EXIF orientation says they are
// shown (jpeg_exif_orientation): orientations 5 to 8 swap the width and the height.
template <typename T>
void apply_orientation(StbiPtr<T>& data, int& w, int& h, int n, int orientation)
{
    if (orientation <= 1 || orientation > 8 || !data) return;
    const bool swap = orientation >= 5;
    const int ow = swap ? h : w, oh = swap ? w : h;
    StbiPtr<T> out(static_cast<T*>(STBI_MALLOC(std::size_t(w) * std::size_t(h) * std::size_t(n) * sizeof(T))));
    if (!out) throw Error("image", "out of memory");
    for (int y = 0; y < oh; ++y)
        for (int x = 0; x < ow; ++x) {
            int sx = x, sy = y; // the stored pixel shown at (x, y)
            switch (orientation) {
            case 2: sx = w - 1 - x; break;
            case 3: sx = w - 1 - x, sy = h - 1 - y; break;
            case 4: sy = h - 1 - y; break;
            case 5: sx = y, sy = x; break;
            case 6: sx = y, sy = h - 1 - x; break;
            case 7: sx = w - 1 - y, sy = h - 1 - x; break;
            case 8: sx = w - 1 - y, sy = x; break;
            }
            std::memcpy(out.get() + (std::size_t(y) * ow + x) * n, data.get() + (std::size_t(sy) * w + sx) * n,
                        std::size_t(n) * sizeof(T));
        }
    data = std::move(out);
    w = ow;
    h = oh;
}

// A GIF's first frame must draw every pixel of its screen. stb fills the ones it does not with the
// background colour, or leaves them transparent black where the background index is 0, without a
// word: image data that ends before the frame is full (an end code, or its blocks ending early,
// in a file complete to its trailer, which the padding check cannot see) made an 8 x 8 map of 10
// pixels all white, or warned of "transparent" pixels the file does not have; a frame smaller
// than the screen read its surroundings as white or as 0 by the background's index alone (found
// by an exploratory session, fiftieth). Found by stb's own first-frame decode, whose record of
// the pixels drawn (this file holds its implementation) stb_image's API does not give.
void check_gif_frame(const std::string& subject, const std::vector<std::uint8_t>& bytes)
{
    const std::optional<Sniffed> kind = sniff(bytes);
    if (!kind || std::strcmp(kind->format, "GIF") != 0 || bytes.size() > std::size_t(INT_MAX)) return;
    stbi__context s;
    stbi__start_mem(&s, bytes.data(), int(bytes.size()));
    const auto g = std::make_unique<stbi__gif>(); // (value-initialized: all zero, as stb's own call makes it)
    int comp = 0;
    const stbi_uc* frame = stbi__gif_load_next(&s, g.get(), &comp, 4, nullptr);
    const bool no_image = frame == reinterpret_cast<const stbi_uc*>(&s); // (the trailer before any image)
    std::size_t drawn = 0, frame_w = 0, frame_h = 0, frame_x = 0, frame_y = 0;
    if (frame && !no_image && g->line_size > 0) {
        frame_x = std::size_t(g->start_x / 4);
        frame_y = std::size_t(g->start_y / g->line_size);
        frame_w = std::size_t((g->max_x - g->start_x) / 4);
        frame_h = std::size_t((g->max_y - g->start_y) / g->line_size);
        for (std::size_t k = 0; k < std::size_t(g->w) * std::size_t(g->h); ++k) drawn += g->history[k] != 0;
    }
    const std::size_t screen = std::size_t(g->w) * std::size_t(g->h);
    const bool file_ended = s.img_buffer >= s.img_buffer_end; // (stb reads zeros past the end)
    STBI_FREE(g->out);
    STBI_FREE(g->history);
    STBI_FREE(g->background);
    if (no_image) throw Error(subject, "not a supported image (a GIF with no image in it)");
    if (!frame) return; // (the decode proper says what is wrong)
    if (drawn < frame_w * frame_h && file_ended)
        throw Error(subject, kEndsBeforeItsPixels);
    if (drawn < frame_w * frame_h)
        throw Error(subject, fmt::format("not a supported image (truncated or corrupt data: the GIF's image data "
                                         "ends after {} of its {} pixels)",
                                         drawn, frame_w * frame_h));
    if (frame_w * frame_h < screen)
        throw Error(subject, fmt::format("not a supported image (the GIF's first frame covers {}x{} pixels, from "
                                         "{},{} at the top left, of its {}x{} screen, and the rest has no pixel of its "
                                         "own: save the map whole, as PNG)",
                                         frame_w, frame_h, frame_x, frame_y, g->w, g->h));
}

// stb gives a GIF's transparent pixels no colour (0, 0, 0, 0), where a PNG's keep their palette
// entry's: said, not silent, with what they were read as (`as`). RGBA `data` of w x h. (As a
// height a transparent white made whole areas fall from 1 to 0; as a colour map its pixels came
// out black; both found by exploratory sessions, the colour's in the thirty-fourth.)
void warn_transparent_gif(const std::string& path, const std::vector<std::uint8_t>& bytes, const stbi_uc* data, int w,
                          int h, const char* as)
{
    const std::optional<Sniffed> kind = sniff(bytes);
    if (!kind || std::strcmp(kind->format, "GIF") != 0) return;
    std::size_t clear = 0;
    for (std::size_t k = 3; k < std::size_t(w) * std::size_t(h) * 4; k += 4) clear += data[k] == 0;
    if (clear > 0)
        warn(path + ": " + std::to_string(clear) + " transparent GIF pixel" + (clear == 1 ? "" : "s") + " read as " + as +
             " (their palette colour is not kept; save the map as PNG to keep it)");
}

HeightField load_height_file(const std::string& path, const ImageLimits& limits)
{
    std::vector<std::uint8_t> bytes = read_file(path, limits);
    const Checked c = check_header(path, bytes, limits);
    check_gif_frame(path, bytes);
    HeightField hf;
    hf.name = path;
    int n = 0;
    // A PNM's samples run from 0 to its maxval (stb returns them as stored).
    const std::optional<int> maxval = pnm_maxval(bytes);
    // (stb's own test misses every 16-bit PSD: psd_is_16_bit.)
    if (psd_is_16_bit(bytes) || stbi_is_16_bit_from_memory(c.data, c.len)) {
        StbiPtr<stbi_us> data = decode_image<stbi_us>(path, bytes, c, &hf.width, &hf.height, &n, 0, stbi_load_16_from_memory);
        if (!data) fail_decode(path);
        check_decoded(path, hf.width, hf.height, limits);
        hf.bits = 16;
        const bool swap = is_pnm(bytes) && stb_swaps_16_bit_pnm();
        const float top = float(maxval.value_or(65535));
        // A PNM's maxval other than 65535 gives heights between 16-bit steps: kept to the steps
        // the GPU holds (R16), as HDR's and the 8-bit PNM's are (v/1023 was kept as a float, so
        // the reference's geometry and the R16 texture differed by up to half a step, and a map
        // equal to a 16-bit PNG's had a cache entry of its own; found by an exploratory session).
        take_first_channel(hf, data.get(), n, [swap, top](stbi_us v) {
            if (swap) v = stbi_us(v >> 8 | v << 8);
            return quantize16(float(v) / top); // (v / 65535 itself where the maxval is 65535)
        });
    } else if (stbi_is_hdr_from_memory(c.data, c.len)) {
        // Radiance HDR holds floats: clamp to the height range and keep 16 bits, which is what
        // the GPU will hold (R16), so CPU and GPU agree.
        StbiPtr<float> data(stbi_loadf_from_memory(c.data, c.len, &hf.width, &hf.height, &n, 0));
        if (!data) fail_decode(path);
        check_decoded(path, hf.width, hf.height, limits);
        hf.bits = 16;
        bool clamped = false;
        take_first_channel(hf, data.get(), n, [&clamped](float v) {
            if (!(v >= 0.0f && v <= 1.0f)) clamped = true;
            return quantize16(std::isnan(v) ? 0.0f : v);
        });
        if (clamped) warn(path + ": HDR heights outside [0,1] were clamped");
    } else {
        StbiPtr<stbi_uc> data = decode_image<stbi_uc>(path, bytes, c, &hf.width, &hf.height, &n, 0, stbi_load_from_memory);
        if (!data) fail_decode(path);
        check_decoded(path, hf.width, hf.height, limits);
        apply_orientation(data, hf.width, hf.height, n, jpeg_exif_orientation(bytes));
        // 8 bits, or a PNM's maxval under 255 taken at 16 (maxval 100: steps of 1/100).
        hf.bits = maxval.value_or(255) == 255 ? 8 : 16;
        fix_tga_origin(bytes, data.get(), hf.width, hf.height, n);
        // stb gives a GIF's transparent pixels no colour (0, 0, 0, 0): their height is 0, not
        // their palette entry's, where a PNG's transparent pixels keep theirs. Said, not silent (a
        // transparent white made whole areas fall from 1 to 0; found by an exploratory session).
        if (n == 4) warn_transparent_gif(path, bytes, data.get(), hf.width, hf.height, "height 0");
        const float top = float(maxval.value_or(255));
        take_first_channel(hf, data.get(), n, [top, quantize = hf.bits == 16](stbi_uc v) {
            const float x = std::min(float(v) / top, 1.0f);
            return quantize ? quantize16(x) : x;
        });
    }
    return hf;
}

RgbaImage load_rgba_file(const std::string& path, const ImageLimits& limits, bool colour_map)
{
    std::vector<std::uint8_t> bytes = read_file(path, limits);
    const Checked c = check_header(path, bytes, limits);
    check_gif_frame(path, bytes);
    int w = 0, h = 0, n = 0;
    StbiPtr<stbi_uc> data;
    if (is_pnm(bytes) && stbi_is_16_bit_from_memory(c.data, c.len)) {
        // stb 2.27 mangles 16-bit PNM on the way to 8-bit RGBA (an 8-bit channel conversion on
        // 16-bit samples, after the byte-order slip above): take the samples as they are and
        // expand grey or RGB to RGBA here.
        StbiPtr<stbi_us> wide = decode_image<stbi_us>(path, bytes, c, &w, &h, &n, 0, stbi_load_16_from_memory);
        if (!wide) fail_decode(path);
        check_decoded(path, w, h, limits);
        const bool swap = stb_swaps_16_bit_pnm();
        const float top = float(pnm_maxval(bytes).value_or(65535));
        const auto high_byte = [swap, top](stbi_us v) {
            if (swap) v = stbi_us(v >> 8 | v << 8);
            return top == 65535.0f ? stbi_uc(v >> 8) : stbi_uc(std::lround(std::min(float(v) / top, 1.0f) * 255.0f));
        };
        const std::size_t count = std::size_t(w) * h;
        data.reset(static_cast<stbi_uc*>(STBI_MALLOC(count * 4)));
        if (!data) throw Error(path, "out of memory");
        for (std::size_t k = 0; k < count; ++k) {
            const stbi_us* p = wide.get() + k * std::size_t(n);
            stbi_uc* q = data.get() + k * 4;
            q[0] = high_byte(p[0]);
            q[1] = high_byte(p[n >= 3 ? 1 : 0]);
            q[2] = high_byte(p[n >= 3 ? 2 : 0]);
            q[3] = 255;
        }
    } else {
        // Asking for 4 channels makes stb replicate grey into RGB, add opaque alpha where there
        // is none, expand palettes and reduce 16-bit input to 8 bits.
        data = decode_image<stbi_uc>(path, bytes, c, &w, &h, &n, 4, stbi_load_from_memory);
        // A PNM's maxval under 255 (stb returns its samples as stored).
        if (const std::optional<int> maxval = pnm_maxval(bytes); data && maxval && *maxval < 255)
            for (std::size_t k = 0; k < std::size_t(w) * h * 4; ++k)
                if (k % 4 != 3) data.get()[k] = stbi_uc(std::lround(std::min(data.get()[k] / float(*maxval), 1.0f) * 255.0f));
    }
    if (!data) fail_decode(path);
    check_decoded(path, w, h, limits);
    // stb encodes a Radiance HDR file's floats as an 8-bit image's (gamma 2.2, as the colour map
    // of a PNG is read), and a channel past 1 is clipped to 255: said, not silent (an observation
    // of the thirty-fourth session).
    if (stbi_is_hdr_from_memory(c.data, c.len)) {
        int fw = 0, fh = 0, fn = 0;
        StbiPtr<float> f(stbi_loadf_from_memory(c.data, c.len, &fw, &fh, &fn, 0));
        std::size_t over = 0;
        if (f)
            for (std::size_t k = 0; k < std::size_t(fw) * fh * fn; ++k)
                if (k % fn < 3 && !(f.get()[k] <= 1.0f)) ++over; // (NaN too)
        if (over > 0)
            warn(path + ": " + std::to_string(over) + " HDR colour value" + (over == 1 ? " is" : "s are") +
                 " past 1 (or not a number): the colour map clips " + (over == 1 ? "it" : "them") +
                 " to full intensity (an 8-bit colour, gamma 2.2)");
    }
    warn_transparent_gif(path, bytes, data.get(), w, h, "black");
    // A colour map's alpha is not read: its pixels are drawn opaque, in the colour stored (often
    // black where an editor leaves transparent pixels as 0, 0, 0, 0). Said, not silent (found by
    // an exploratory session, thirty-sixth; a GIF's are said above).
    // (Not a TGA whose header gives no alpha bits: stb reads its fourth byte as alpha all the
    // same, where exporters often leave 0; found by a review.)
    const bool tga_without_alpha = is_tga(bytes) && (bytes[17] & 0x0F) == 0;
    if (colour_map && !tga_without_alpha && !(bytes.size() >= 3 && std::memcmp(bytes.data(), "GIF", 3) == 0)) {
        std::size_t translucent = 0;
        for (std::size_t k = 3; k < std::size_t(w) * h * 4; k += 4) translucent += data.get()[k] < 255;
        if (translucent > 0)
            warn(path + ": " + std::to_string(translucent) + " colour map pixel" + (translucent == 1 ? " is" : "s are") +
                 " transparent or translucent: a colour map's alpha is not read, its colour is drawn opaque as stored");
    }
    apply_orientation(data, w, h, 4, jpeg_exif_orientation(bytes));
    fix_tga_origin(bytes, data.get(), w, h, 4);
    RgbaImage img;
    img.width = w;
    img.height = h;
    img.pixels.resize(std::size_t(w) * h * 4);
    const std::size_t row_bytes = std::size_t(w) * 4;
    for (int y = 0; y < h; ++y)
        std::memcpy(&img.pixels[std::size_t(y) * row_bytes],
                    data.get() + std::size_t(h - 1 - y) * row_bytes, row_bytes);
    return img;
}

void append_bytes(void* context, void* data, int size)
{
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* p = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), p, p + size);
}

} // namespace

float HeightField::at(int x, int y) const
{
    return texels[std::size_t(wrap_index(y, height)) * width + wrap_index(x, width)];
}

float HeightField::sample(glm::vec2 uv) const
{
    // OpenGL 4.6 §8.14.2, LINEAR with REPEAT at level 0: u' = s·w − ½, i0 = wrap(⌊u'⌋),
    // i1 = wrap(⌊u'⌋ + 1), α = frac(u'); the same along t. Done in double so the reference
    // geometry is at least as precise as the GPU's fixed-point weights.
    struct Axis {
        int i0, i1;
        double a;
    };
    const auto axis = [](float s, int n) {
        double x = std::isfinite(s) ? double(s) : 0.0;
        x = (x - std::floor(x)) * n - 0.5; // one period first, so the index fits an int
        const double f = std::floor(x);
        const auto i = static_cast<std::int64_t>(f);
        return Axis{wrap_index(i, n), wrap_index(i + 1, n), x - f};
    };
    const Axis u = axis(uv.x, width), v = axis(uv.y, height);
    const auto t = [this](int x, int y) { return double(texels[std::size_t(y) * width + x]); };
    const double bottom = (1.0 - u.a) * t(u.i0, v.i0) + u.a * t(u.i1, v.i0);
    const double top = (1.0 - u.a) * t(u.i0, v.i1) + u.a * t(u.i1, v.i1);
    return static_cast<float>((1.0 - v.a) * bottom + v.a * top);
}

float HeightField::min_value() const
{
    return texels.empty() ? 0.0f : *std::min_element(texels.begin(), texels.end());
}

float HeightField::max_value() const
{
    return texels.empty() ? 0.0f : *std::max_element(texels.begin(), texels.end());
}

HeightField load_height(const std::string& spec, const ImageLimits& limits)
{
    if (builtin::is_builtin(spec)) return builtin::make_height(spec, limits);
    return load_height_file(spec, limits);
}

RgbaImage load_color(const std::string& spec, const ImageLimits& limits)
{
    if (builtin::is_builtin(spec)) return builtin::make_color(spec, limits);
    return load_rgba_file(spec, limits, true);
}

bool png_encodable(int width, int height)
{
    // With room for the compressed stream, also an int, which may come out larger than the rows
    // where they do not compress (stb's fixed Huffman codes: up to 9 bits a byte).
    const std::uint64_t rows = (std::uint64_t(std::max(width, 0)) * 4 + 1) * std::uint64_t(std::max(height, 0));
    return width > 0 && height > 0 && rows / 8 * 9 + 65536 <= std::uint64_t(std::numeric_limits<int>::max());
}

std::vector<std::uint8_t> encode_png(const RgbaImage& image)
{
    const std::size_t expected = std::size_t(std::max(image.width, 0)) *
                                 std::size_t(std::max(image.height, 0)) * 4;
    if (image.width <= 0 || image.height <= 0)
        throw Error("PNG", fmt::format("cannot encode a {}x{} image", image.width, image.height));
    if (image.pixels.size() != expected)
        throw Error("PNG", fmt::format("image data holds {} bytes, {}x{} RGBA needs {}",
                                       image.pixels.size(), image.width, image.height, expected));
    if (!png_encodable(image.width, image.height))
        throw Error("PNG", fmt::format("a {}x{} image is too large for the PNG encoder (2 GiB of rows at most)",
                                       image.width, image.height));
    // Files store the top row first; pointing at the last row with a negative stride flips
    // without a copy (stb only ever adds multiples of the stride to the pointer).
    const int stride = image.width * 4;
    const std::uint8_t* last_row = image.pixels.data() + std::size_t(image.height - 1) * stride;
    std::vector<std::uint8_t> out;
    if (!stbi_write_png_to_func(append_bytes, &out, image.width, image.height, 4, last_row,
                                -stride))
        throw Error("PNG", "out of memory while encoding it"); // (stb's encoder fails only where an allocation does)
    return out;
}

std::vector<std::uint8_t> encode_png_for(const std::filesystem::path& path, const RgbaImage& image)
{
    try {
        return encode_png(image);
    } catch (const Error& e) {
        throw Error(path.string(), e.problem());
    }
}

void write_png(const std::filesystem::path& path, const RgbaImage& image)
{
    write_file_atomic(path, encode_png_for(path, image));
}

RgbaImage read_rgba(const std::filesystem::path& path) { return load_rgba_file(path.string(), {}, false); }

} // namespace pr
