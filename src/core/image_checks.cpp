#include "core/image_checks.hpp"

#include "core/error.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <functional>
#include <string_view>

namespace pr {
namespace {

using Bytes = std::vector<std::uint8_t>;

bool starts_with(const Bytes& b, std::string_view magic)
{
    return b.size() >= magic.size() && std::memcmp(b.data(), magic.data(), magic.size()) == 0;
}

std::uint32_t le16(const Bytes& b, std::size_t o) { return std::uint32_t(b[o]) | std::uint32_t(b[o + 1]) << 8; }
std::uint32_t le32(const Bytes& b, std::size_t o) { return le16(b, o) | le16(b, o + 2) << 16; }
std::uint32_t be16(const Bytes& b, std::size_t o) { return std::uint32_t(b[o]) << 8 | std::uint32_t(b[o + 1]); }
std::uint32_t be32(const Bytes& b, std::size_t o) { return be16(b, o) << 16 | be16(b, o + 2); }

[[noreturn]] void cut_short(const std::string& subject, const char* format, std::uint64_t needed, std::size_t size)
{
    throw Error(subject, fmt::format("not a supported image (truncated {}: it needs at least {} bytes, "
                                     "the file has {})",
                                     format, needed, size));
}

// White space between a PNM header's words.
bool pnm_space(std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

struct PnmHeader {
    std::uint64_t width = 0, height = 0, maxval = 0; // (each at most INT64_MAX: more digits saturate)
    int channels = 0;
    int numbers = 0;      // of the three, those the header holds (stb takes a missing one as 0)
    std::size_t data = 0; // offset of the first sample
};

// A binary PNM header as stb_image reads it: P5 or P6, then width, height and maxval separated by
// whitespace and '#' comments, then one whitespace character before the samples. `numbers` says
// how many of the three it holds before something else (or the end of the file) comes.
std::optional<PnmHeader> scan_pnm(const Bytes& b)
{
    if (b.size() < 2 || b[0] != 'P' || (b[1] != '5' && b[1] != '6')) return std::nullopt;
    PnmHeader h;
    h.channels = b[1] == '6' ? 3 : 1;
    std::size_t i = 2;
    const auto skip = [&] {
        while (i < b.size() && (pnm_space(b[i]) || b[i] == '#')) {
            if (b[i] == '#')
                while (i < b.size() && b[i] != '\n' && b[i] != '\r') ++i;
            else
                ++i;
        }
    };
    const auto number = [&](std::uint64_t& v) {
        if (i >= b.size() || b[i] < '0' || b[i] > '9') return false;
        v = 0;
        constexpr std::uint64_t top = std::uint64_t(INT64_MAX);
        while (i < b.size() && b[i] >= '0' && b[i] <= '9') {
            const std::uint64_t d = b[i] - '0';
            v = v > (top - d) / 10 ? top : v * 10 + d;
            ++i;
        }
        return true;
    };
    for (std::uint64_t* v : {&h.width, &h.height, &h.maxval}) {
        skip();
        if (!number(*v)) return h;
        ++h.numbers;
    }
    h.data = i + 1;
    return h;
}

// The header when it holds all three numbers.
std::optional<PnmHeader> parse_pnm(const Bytes& b)
{
    const std::optional<PnmHeader> h = scan_pnm(b);
    if (!h || h->numbers < 3) return std::nullopt;
    return h;
}

// a * b, or UINT64_MAX where that does not fit.
std::uint64_t saturating_product(std::uint64_t a, std::uint64_t b)
{
    return a != 0 && b > UINT64_MAX / a ? UINT64_MAX : a * b;
}

void check_pnm(const std::string& subject, const Bytes& b)
{
    const std::optional<PnmHeader> h = parse_pnm(b);
    if (!h) return; // stb refuses it
    // (Its maxval lies within 1 to 65535: check_pnm_header refused any other before stb read it.)
    const std::uint64_t sample = h->maxval > 255 ? 2 : 1;
    // (The size was checked against the limits first, check_pnm_header; saturating all the same.)
    const std::uint64_t samples = saturating_product(saturating_product(h->width, h->height), std::uint64_t(h->channels) * sample);
    const std::uint64_t needed = samples > UINT64_MAX - h->data ? UINT64_MAX : h->data + samples;
    if (needed > b.size()) cut_short(subject, "PNM", needed, b.size());
    // Samples run from 0 to maxval (netpbm refuses one past it). stb returns them as stored and
    // image.cpp scales them by maxval: one past it came out clamped to the top height without a
    // word (maxval 100 and a sample of 255: found by an exploratory session).
    if (h->maxval == 255 || h->maxval == 65535) return; // every sample fits
    const std::uint64_t count = h->width * h->height * std::uint64_t(h->channels); // (fits: the file holds them)
    for (std::uint64_t k = 0; k < count && h->data + sample * (k + 1) <= b.size(); ++k) {
        const std::uint64_t v = sample == 2 ? be16(b, h->data + 2 * k) : b[h->data + k];
        if (v > h->maxval)
            throw Error(subject, fmt::format("not a supported image (corrupt PNM: a sample is {}, more than its "
                                             "maxval of {})",
                                             v, h->maxval));
    }
}

// A TGA's pixel data: raw (types 1-3) or run-length (9-11) packets, each a header byte and then
// one pixel (a run) or 1-128 pixels (raw). A colour-mapped one's (types 1 and 9) pixels are
// indices of 8 or 16 bits into its colour map: stb 2.27 took an index past the map's entries for
// entry 0 without a word, where a PNG or BMP with the same defect is refused (found by an
// exploratory session). stb compares the index with the map's entry count alone (it skips the
// first-entry field as bytes before the entries): so does this.
void check_tga(const std::string& subject, const Bytes& b)
{
    if (b.size() < 18) return;
    const unsigned type = b[2];
    const bool rle = type >= 9;
    // (stb skips the colour map's first-entry index in bytes before reading its entries.)
    const std::uint64_t cmap_bytes = b[1] ? le16(b, 3) + std::uint64_t(le16(b, 5)) * ((b[7] + 7u) / 8u) : 0;
    const std::uint64_t pixel = (b[16] + 7u) / 8u;
    const std::uint64_t count = std::uint64_t(le16(b, 12)) * le16(b, 14);
    std::uint64_t at = 18 + std::uint64_t(b[0]) + cmap_bytes;
    if (pixel == 0) return; // stb refuses it
    // stb reads a colour-mapped image's pixels as indices only of 8 or 16 bits (its test refuses
    // the others), into a map of at least one entry (it refuses none).
    const bool indexed = b[1] == 1 && (type == 1 || type == 9) && (b[16] == 8 || b[16] == 16) && le16(b, 5) > 0;
    const auto check_index = [&](std::uint64_t o) {
        if (!indexed) return;
        const std::uint32_t index = pixel == 1 ? b[o] : le16(b, o);
        if (index >= le16(b, 5))
            throw Error(subject, fmt::format("not a supported image (corrupt TGA: a pixel's colour index is {}, past its "
                                             "palette of {} colours)",
                                             index, le16(b, 5)));
    };
    if (!rle) {
        if (at + count * pixel > b.size()) cut_short(subject, "TGA", at + count * pixel, b.size());
        for (std::uint64_t k = 0; indexed && k < count; ++k) check_index(at + k * pixel);
        return;
    }
    for (std::uint64_t done = 0; done < count;) {
        if (at >= b.size()) cut_short(subject, "run-length TGA", at + 1, b.size());
        const unsigned head = b[at++];
        const std::uint64_t n = (head & 0x7Fu) + 1u;
        const std::uint64_t stored = head & 0x80u ? 1 : std::min(n, count - done); // (stb stops at the last pixel)
        if (at + stored * pixel > b.size()) cut_short(subject, "run-length TGA", at + stored * pixel, b.size());
        for (std::uint64_t k = 0; k < stored; ++k) check_index(at + k * pixel);
        at += stored * pixel;
        done += n;
    }
}

// A Softimage PIC: a header of 104 bytes, up to 10 chained packets of 4 bytes (chained, bits,
// compression, channel mask), then each row's data, packet after packet: uncompressed (a byte
// per channel in the mask, a pixel after another), pure run-length (a count of up to 255 pixels
// and one value) or mixed run-length (a count under 128: that many pixels plus one, raw; 128: a
// 16-bit count follows; above: the count less 127, of one value). Walked as stb 2.27 reads it,
// its end-of-file tests included, without decoding: stb allocates and clears the whole image
// before it reads a packet (256 MiB for a header of 16384 x 4096; the run's peak 320 MB), so a
// file that claims a large image and holds a packet header and no rows took that memory before
// it was refused (found by an exploratory session, thirty-fifth). The walk reads each byte once
// or, for a run of no pixels, a few: its time is the file's, never the image's (a file it passes
// then decodes to the image its rows hold).
void check_pic(const std::string& subject, const Bytes& b)
{
    if (b.size() < 104) return; // stb refuses it in its header (stbi_info)
    const std::uint64_t width = be16(b, 92), height = be16(b, 94);
    std::size_t at = 104;
    const auto get8 = [&]() -> unsigned { return at < b.size() ? b[at++] : 0u; }; // (stb's: 0 past the end)
    const auto eof = [&] { return at >= b.size(); };
    struct Packet {
        unsigned type, channels;
    };
    std::vector<Packet> packets;
    for (bool chained = true; chained;) {
        if (packets.size() == 10) return; // stb's info refuses these (too many packets, not 8 bits, cut short)
        chained = get8() != 0;
        const unsigned bits = get8(), type = get8(), mask = get8();
        if (eof() || bits != 8) return;
        packets.push_back({type, unsigned(std::popcount(mask & 0xF0u))});
    }
    // Packets that carry no channel read no byte: every row is whole without data, and stb
    // decodes the image it cleared (a 109-byte file of 16384 x 4096 took 580 MB; found by a
    // review, thirty-sixth). Such a file holds no picture.
    if (std::all_of(packets.begin(), packets.end(), [](const Packet& p) { return p.channels == 0; }))
        throw Error(subject, "not a supported image (corrupt PIC: its packets carry no channel, so it holds no pixel)");
    const auto truncated = [&](std::uint64_t row) {
        throw Error(subject, fmt::format("not a supported image (truncated PIC: the file ends in row {} of {}, "
                                         "after {} bytes)",
                                         row + 1, height, b.size()));
    };
    for (std::size_t k = 0; k < packets.size(); ++k)
        if (packets[k].type > 2)
            throw Error(subject, fmt::format("not a supported image (corrupt PIC: packet {} has compression type "
                                             "{}; 0, 1 and 2 are read)",
                                             k + 1, packets[k].type));
    for (std::uint64_t y = 0; y < height; ++y)
        for (const Packet& p : packets) {
            // A value: a byte per channel, each read only where the file has one left.
            const auto value = [&](std::uint64_t pixels) {
                const std::uint64_t bytes = pixels * p.channels;
                if (bytes > b.size() - at) truncated(y);
                at += bytes;
            };
            if (p.type == 0) {
                value(width);
                continue;
            }
            for (std::uint64_t left = width; left > 0;) {
                std::uint64_t count = get8();
                if (eof()) truncated(y);
                if (p.type == 1) {
                    value(1);
                    left -= std::min(count, left);
                    continue;
                }
                const bool run = count >= 128;
                if (count == 128)
                    count = get8() << 8, count |= get8();
                else
                    count = run ? count - 127 : count + 1;
                if (count > left)
                    throw Error(subject, fmt::format("not a supported image (corrupt PIC: a run of {} pixels in "
                                                     "row {} of {} overruns the row's {})",
                                                     count, y + 1, height, left));
                value(run ? 1 : count);
                left -= count;
            }
        }
}

// An uncompressed BMP (BI_RGB, BI_BITFIELDS): rows padded to 4 bytes from the data offset; stb
// reads the last row without its padding.
void check_bmp(const std::string& subject, const Bytes& b)
{
    if (b.size() < 30) return;
    const std::uint32_t header = le32(b, 14);
    std::uint64_t w = 0, h = 0, bpp = 0, compression = 0;
    if (header == 12) {
        w = le16(b, 18);
        h = le16(b, 20);
        bpp = le16(b, 24);
    } else if (header >= 40 && b.size() >= 34) {
        w = std::uint64_t(std::abs(std::int64_t(std::int32_t(le32(b, 18)))));
        h = std::uint64_t(std::abs(std::int64_t(std::int32_t(le32(b, 22)))));
        bpp = le16(b, 28);
        compression = le32(b, 30);
    } else {
        return;
    }
    if ((compression != 0 && compression != 3) || w == 0 || h == 0 || bpp == 0) return;
    const std::uint64_t offset = le32(b, 10);
    const std::uint64_t stride = (w * bpp + 31) / 32 * 4;
    const std::uint64_t needed = offset + stride * (h - 1) + (w * bpp + 7) / 8;
    if (needed > b.size()) cut_short(subject, "BMP", needed, b.size());
    if (bpp != 1 && bpp != 4 && bpp != 8) return;
    // A palette image: stb fills its palette array only up to the entries the data offset
    // leaves room for (its own arithmetic, OS/2 headers included), and looks up every index in
    // it unchecked: an index past them, or an offset inside the header (no entries at all),
    // coloured pixels with uninitialised memory (a different map each run; found by a review).
    const std::int64_t psize = header == 12 ? (std::int64_t(offset) - 14 - 24) / 3
                                            : (std::int64_t(offset) - 14 - std::int64_t(header)) >> 2;
    if (psize == 0 || psize > 256) return; // stb refuses it
    if (psize < 0) throw Error(subject, "not a supported image (corrupt BMP: its data offset lies inside its header)");
    const std::uint64_t per_byte = 8 / bpp, mask = (1u << bpp) - 1;
    for (std::uint64_t y = 0; y < h; ++y)
        for (std::uint64_t x = 0; x < w; ++x) {
            const std::uint8_t byte = b[offset + y * stride + x / per_byte];
            const std::uint64_t index = (byte >> ((per_byte - 1 - x % per_byte) * bpp)) & mask;
            if (std::int64_t(index) >= psize)
                throw Error(subject, fmt::format("not a supported image (corrupt BMP: a pixel's colour index is {}, "
                                                 "past its palette of {} colours)",
                                                 index, psize));
        }
}

// PSD: after the header, three blocks each led by its length, then the compression and the
// image data: raw planes, or (RLE) a table of every row's byte count and the rows. stb reads the
// first four channels.
void check_psd(const std::string& subject, const Bytes& b)
{
    if (b.size() < 26) return;
    const std::uint64_t channels = be16(b, 12), h = be32(b, 14), w = be32(b, 18), depth = be16(b, 22);
    std::uint64_t at = 26;
    for (int block = 0; block < 3; ++block) {
        if (at + 4 > b.size()) cut_short(subject, "PSD", at + 4, b.size());
        at += 4 + std::uint64_t(be32(b, at));
    }
    if (at + 2 > b.size()) cut_short(subject, "PSD", at + 2, b.size());
    const unsigned compression = be16(b, at);
    at += 2;
    const std::uint64_t used = std::min<std::uint64_t>(channels, 4);
    if (compression == 0) {
        const std::uint64_t needed = at + used * w * h * (depth / 8);
        if (needed > b.size()) cut_short(subject, "PSD", needed, b.size());
        return;
    }
    if (compression != 1) return; // stb refuses it
    if (depth == 16)
        throw Error(subject, "not a supported image (16-bit PSD with run-length compression, which stb_image "
                             "decodes wrongly: save it uncompressed, or as a 16-bit PNG)");
    const std::uint64_t table = at, rows = channels * h;
    at += 2 * rows;
    if (at > b.size()) cut_short(subject, "PSD", at, b.size());
    for (std::uint64_t r = 0; r < used * h; ++r) at += be16(b, table + 2 * r);
    if (at > b.size()) cut_short(subject, "run-length PSD", at, b.size());
}

// Radiance HDR, as stb_image reads it: text lines up to an empty one, the resolution line
// "-Y H +X W", then per scanline either run-length data (2, 2, W as two bytes, then four
// channels of runs and dumps) or, from the first scanline that does not start so, flat RGBE
// pixels to the end. stb's scanline loop makes no progress on a count of 0 (a dump of 0 bytes,
// or a run of 128 + 0) at the end of the file, where every missing byte reads as 0, hung it.
void check_hdr(const std::string& subject, const Bytes& b)
{
    std::size_t i = 0;
    const auto line = [&] {
        const std::size_t start = i;
        while (i < b.size() && b[i] != '\n') ++i;
        std::string text(b.begin() + std::ptrdiff_t(start), b.begin() + std::ptrdiff_t(i));
        if (i < b.size()) ++i;
        return text;
    };
    line(); // #?RADIANCE
    while (i < b.size() && !line().empty()) {
    }
    long long height = 0, width = 0;
    if (std::sscanf(line().c_str(), "-Y %lld +X %lld", &height, &width) != 2 || height <= 0 || width <= 0)
        return; // stb refuses it
    const auto need = [&](std::uint64_t n) {
        if (i + n > b.size()) cut_short(subject, "HDR", i + n, b.size());
    };
    const std::uint64_t w = std::uint64_t(width);
    for (long long y = 0; y < height; ++y) {
        if (w < 8 || w >= 32768 || i + 4 > b.size() || b[i] != 2 || b[i + 1] != 2 || (b[i + 2] & 0x80)) {
            // Flat from here: stb starts the image over (j = 0) and reads every pixel flat.
            need(std::uint64_t(height) * w * 4);
            return;
        }
        if ((std::uint64_t(b[i + 2]) << 8 | b[i + 3]) != w) return; // stb refuses it
        i += 4;
        for (int k = 0; k < 4; ++k) {
            for (std::uint64_t x = 0; x < w;) {
                need(1);
                unsigned count = b[i++];
                const bool run = count > 128;
                if (run) count -= 128;
                // (A count of 0 reads nothing, or one value, and moves on; only at the end of the
                // file, where every byte reads as 0, does stb loop on it: need() above.)
                if (count > w - x) return; // stb refuses it
                need(run ? 1 : count);
                i += run ? 1 : count;
                x += count;
            }
        }
    }
}

bool is_hdr(const Bytes& b) { return starts_with(b, "#?RADIANCE\n") || starts_with(b, "#?RGBE\n"); }

bool is_png(const Bytes& b) { return starts_with(b, "\x89PNG\r\n\x1a\n"); }

// The CRC-32 of PNG chunks (ISO 3309, as zlib's crc32), a table of the 256 byte values.
std::uint32_t png_crc(const std::uint8_t* p, std::size_t n)
{
    static const auto table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xFFFFFFFFu;
    for (std::size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

// A chunk's type as the message can show it: its four letters, or its bytes in hex where they
// are not letters (a damaged length puts any bytes there).
std::string chunk_name(const Bytes& b, std::size_t o)
{
    const bool letters = std::all_of(b.begin() + std::ptrdiff_t(o), b.begin() + std::ptrdiff_t(o + 4), [](std::uint8_t c) {
        return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
    });
    if (letters) return std::string(b.begin() + std::ptrdiff_t(o), b.begin() + std::ptrdiff_t(o + 4));
    return fmt::format("0x{:08X}", be32(b, o));
}

} // namespace

std::optional<std::pair<std::int64_t, std::int64_t>> check_pnm_header(const std::string& subject,
                                                                      const std::vector<std::uint8_t>& b)
{
    // The ASCII forms (P1-P3) and the bitmap (P4), which stb does not read: its "unknown format"
    // listed PNM among the readable ones (found by an exploratory session, thirty-fourth).
    if (b.size() >= 3 && b[0] == 'P' && b[1] >= '1' && b[1] <= '4' && (pnm_space(b[2]) || b[2] == '#'))
        throw Error(subject, fmt::format("a PNM in the {} form (P{}), which is not read: save it as a binary "
                                         "greymap or pixmap (P5, P6) or as PNG",
                                         b[1] == '4' ? "bitmap" : "ASCII", char(b[1])));
    const std::optional<PnmHeader> h = scan_pnm(b);
    if (!h) return std::nullopt;
    if (h->numbers == 3 && (h->maxval == 0 || h->maxval > 65535))
        throw Error(subject, fmt::format("not a supported image (PNM maxval {}: must be 1 to 65535)", h->maxval));
    return std::pair{std::int64_t(h->width), std::int64_t(h->height)};
}

bool psd_is_16_bit(const std::vector<std::uint8_t>& b)
{
    return b.size() >= 26 && starts_with(b, "8BPS") && be16(b, 22) == 16;
}

std::size_t jpeg_start(const std::vector<std::uint8_t>& b)
{
    std::size_t i = 0;
    while (i < b.size() && b[i] == 0xFF) ++i;
    return i > 0 && i < b.size() && b[i] == 0xD8 ? i + 1 : 0;
}

bool is_tga(const std::vector<std::uint8_t>& b)
{
    if (b.size() < 18) return false;
    for (std::string_view magic : {"\x89PNG", "BM", "GIF8", "8BPS", "\x53\x80\xF6\x34", "P5", "P6", "#?RADIANCE", "#?RGBE"})
        if (starts_with(b, magic)) return false;
    if (jpeg_start(b)) return false;
    const unsigned type = b[2];
    return b[1] <= 1 && (type == 1 || type == 2 || type == 3 || type == 9 || type == 10 || type == 11);
}

void check_image_data(const std::string& subject, const std::vector<std::uint8_t>& bytes)
{
    if (parse_pnm(bytes))
        check_pnm(subject, bytes);
    else if (starts_with(bytes, "BM"))
        check_bmp(subject, bytes);
    else if (starts_with(bytes, "8BPS"))
        check_psd(subject, bytes);
    else if (is_hdr(bytes))
        check_hdr(subject, bytes);
    else if (is_tga(bytes))
        check_tga(subject, bytes);
    else if (starts_with(bytes, "\x53\x80\xF6\x34"))
        check_pic(subject, bytes);
}

std::size_t walk_png_chunks(const std::vector<std::uint8_t>& b,
                            const std::function<bool(std::size_t, std::uint32_t, std::string_view)>& visit)
{
    if (!is_png(b)) return 0;
    std::size_t at = 8;
    while (b.size() - at >= 12) {
        const std::uint32_t length = be32(b, at);
        if (length > b.size() - at - 12) break; // runs past the end
        if (!visit(at, length, std::string_view(reinterpret_cast<const char*>(&b[at + 4]), 4))) break;
        at += 12 + std::size_t(length);
    }
    return at;
}

void check_png(const std::string& subject, const std::vector<std::uint8_t>& b)
{
    if (!is_png(b)) return;
    std::string last = "its signature";
    bool iend = false;
    const std::size_t at = walk_png_chunks(b, [&](std::size_t chunk, std::uint32_t length, std::string_view type) {
        const std::string name = chunk_name(b, chunk + 4);
#ifndef FUZZING_BUILD_MODE_UNSAFE_FOR_PRODUCTION // (fuzz builds: mutated files would stop here)
        if (png_crc(&b[chunk + 4], std::size_t(length) + 4) != be32(b, chunk + 8 + length))
            throw Error(subject, fmt::format("not a supported image (corrupt PNG: the CRC of its {} chunk does not "
                                             "match its data: a damaged file)",
                                             name));
#endif
        iend = type == "IEND"; // stb reads no further, nor do we: trailing bytes are left alone
        last = "its " + name + " chunk";
        return !iend;
    });
    if (iend) return;
    if (b.size() == at)
        throw Error(subject, fmt::format("not a supported image (truncated PNG: the file ends after {}, "
                                         "without the IEND chunk that closes a PNG)",
                                         last));
    cut_short(subject, "PNG", b.size() - at < 12 ? at + 12 : at + 12 + std::uint64_t(be32(b, at)), b.size());
}

std::optional<PngPaletteProbe> png_palette_probe(const std::vector<std::uint8_t>& b)
{
    // IHDR first (stb refuses anything else), colour type 3.
    if (!is_png(b) || b.size() < 33 || std::memcmp(&b[12], "IHDR", 4) != 0 || b[25] != 3) return std::nullopt;
    const unsigned depth = b[24];
    std::size_t plte = 0;
    std::uint32_t entries = 0;
    bool refused = false; // by stb, or check_png (a chunk past the end)
    const std::size_t at = walk_png_chunks(b, [&](std::size_t chunk, std::uint32_t length, std::string_view type) {
        if (type == "IEND") return false;
        if (type == "PLTE") {
            refused = length > 256 * 3 || length % 3 != 0;
            plte = chunk;
            entries = length / 3;
        }
        // A tRNS longer than the palette before it: stb refuses it, and would not once the
        // palette is full.
        refused = refused || (type == "tRNS" && length > entries);
        return !refused;
    });
    refused = refused || (b.size() - at >= 12 && be32(b, at) > b.size() - at - 12);
    // No PLTE (stb refuses it), or one no index can get past.
    if (refused || plte == 0 || entries >= 256 || (depth < 8 && entries >= (1u << depth))) return std::nullopt;
    PngPaletteProbe probe{{}, {}, entries};
    for (const bool high : {false, true}) {
        Bytes& out = high ? probe.high : probe.low;
        out.reserve(b.size() + 3 * (256 - entries));
        out.assign(b.begin(), b.begin() + std::ptrdiff_t(plte));
        Bytes body = {0, 0, 3, 0, 'P', 'L', 'T', 'E'}; // length 768, type
        body.insert(body.end(), b.begin() + std::ptrdiff_t(plte + 8), b.begin() + std::ptrdiff_t(plte + 8 + 3 * entries));
        for (unsigned k = entries; k < 256; ++k) body.insert(body.end(), 3, std::uint8_t(high ? 255 - k : k));
        const std::uint32_t crc = png_crc(body.data() + 4, body.size() - 4);
        body.insert(body.end(), {std::uint8_t(crc >> 24), std::uint8_t(crc >> 16), std::uint8_t(crc >> 8), std::uint8_t(crc)});
        out.insert(out.end(), body.begin(), body.end());
        out.insert(out.end(), b.begin() + std::ptrdiff_t(plte + 12 + 3 * entries), b.end());
    }
    return probe;
}

bool needs_padding_check(const std::vector<std::uint8_t>& bytes)
{
    return !starts_with(bytes, "\x89PNG") && !is_hdr(bytes) && !jpeg_start(bytes);
}

int jpeg_exif_orientation(const std::vector<std::uint8_t>& b)
{
    const auto at = [&b](std::size_t i) -> unsigned { return i < b.size() ? b[i] : 0u; };
    std::size_t i = jpeg_start(b);
    if (i == 0) return 1; // not JPEG
    while (i + 3 < b.size()) {
        if (b[i] != 0xFF) return 1; // the segments before the image data end here
        const unsigned m = b[i + 1];
        if (m == 0xFF) {
            ++i;
            continue;
        }
        if (m == 0xDA || m == 0xD9) return 1; // start of scan, end of image: no EXIF before
        const std::size_t length = at(i + 2) << 8 | at(i + 3);
        const std::size_t start = i + 4, end = std::min(b.size(), i + 2 + length);
        if (m == 0xE1 && end >= start + 14 && std::memcmp(&b[start], "Exif\0\0", 6) == 0) {
            const std::size_t tiff = start + 6;
            const bool little = b[tiff] == 'I' && b[tiff + 1] == 'I';
            if (!little && !(b[tiff] == 'M' && b[tiff + 1] == 'M')) return 1;
            const auto u16 = [&](std::size_t o) -> std::uint32_t {
                if (o + 2 > end) return 0;
                return little ? std::uint32_t(b[o]) | std::uint32_t(b[o + 1]) << 8
                              : std::uint32_t(b[o]) << 8 | std::uint32_t(b[o + 1]);
            };
            const auto u32 = [&](std::size_t o) -> std::uint32_t {
                return little ? u16(o) | u16(o + 2) << 16 : u16(o) << 16 | u16(o + 2);
            };
            const std::size_t ifd = tiff + u32(tiff + 4);
            const std::uint32_t entries = u16(ifd);
            for (std::uint32_t e = 0; e < entries && ifd + 2 + 12 * (e + 1) <= end; ++e) {
                const std::size_t entry = ifd + 2 + 12 * e;
                if (u16(entry) == 0x0112 && u16(entry + 2) == 3) { // SHORT
                    const std::uint32_t value = u16(entry + 8);
                    return value >= 1 && value <= 8 ? int(value) : 1;
                }
            }
            return 1;
        }
        i += 2 + length;
    }
    return 1;
}

std::optional<int> pnm_maxval(const std::vector<std::uint8_t>& bytes)
{
    const std::optional<PnmHeader> h = parse_pnm(bytes);
    if (!h || h->maxval == 0 || h->maxval > 65535) return std::nullopt;
    return int(h->maxval);
}

} // namespace pr
