#pragma once
// Checks of an image file's data against its own header, for the formats whose stb_image decoder
// does not notice that the file ends early (sixteenth session, found by an exploratory session):
// a truncated PNM, raw TGA or PIC came out as uninitialised memory (a different map each run),
// BMP, GIF, PSD and run-length TGA rows past the end as zeros, and a truncated run-length Radiance
// HDR file hung stb's scanline loop forever. A short JPEG is left to stb, which refuses it; a
// short PNG is refused by check_png, which also checks what stb does not (its CRCs).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pr {

// Throws Error(subject, ...) when the header of `bytes` claims more pixel data than the file
// holds (PNM, raw and run-length TGA, uncompressed BMP, PSD), when a Radiance HDR file's
// run-length scanlines are cut short or hold a run stb's decoder would loop on, for PSD
// run-length data of 16 bits, which stb decodes as 8 (garbage), and for a colour-mapped TGA's
// index past its map's entries (stb takes it for entry 0) or a palette BMP's past its palette,
// and for a PIC whose packets or rows stb's decoder would refuse, after allocating the image.
// A PNM's header is taken as checked by check_pnm_header (its maxval within 1 to 65535).
void check_image_data(const std::string& subject, const std::vector<std::uint8_t>& bytes);

// A binary PNM's (P5, P6) header, checked before stb_image reads it: stb 2.27 reads its numbers
// into an int with no bound, so a width, height or maxval past 2^31 - 1 overflowed (undefined
// behaviour; found by an exploratory session) and the message gave a wrapped size
// ("-2147483648x1 pixels") or "unknown format" for a maxval over 65535. Throws Error(subject, ...)
// for a maxval outside 1 to 65535; returns the width and height as the header states them (0 for
// one it does not hold, as stb takes it; more digits than an int64 holds saturate), for the
// caller to check against the limits; nullopt for other formats. A PNM in its ASCII forms
// (P1-P3) or a bitmap (P4), which stb does not read, is refused as such.
std::optional<std::pair<std::int64_t, std::int64_t>> check_pnm_header(const std::string& subject,
                                                                      const std::vector<std::uint8_t>& bytes);

// Walks a PNG's chunks from its signature on as stb walks them (a big-endian length, the type,
// the data, the CRC), calling visit(offset, length, type) for each whole one until it returns
// false. Returns the offset where the walk stopped: at the chunk `visit` declined, the end of the
// file, or a chunk that runs past it (or fewer than its 12 bytes left). 0 for bytes that are not
// a PNG. (check_png, png_palette_probe and drop_empty_png_idat walk the same way.)
std::size_t walk_png_chunks(const std::vector<std::uint8_t>& bytes,
                            const std::function<bool(std::size_t, std::uint32_t, std::string_view)>& visit);

// Throws Error(subject, ...) when a PNG's chunks, walked from its signature to IEND, run past
// the end of the file, end without IEND, or carry a CRC that does not match their type and data.
// stb_image 2.27 checks no CRC: a damaged IDAT decoded to wrong heights with exit 0 (found by an
// exploratory session), and a file without IEND was refused for a reason it left empty. Other
// formats are left alone.
void check_png(const std::string& subject, const std::vector<std::uint8_t>& bytes);

// stb_image 2.27 looks a palette PNG's indices up unchecked in a palette array of 256 entries,
// of which only those of its (last) PLTE chunk are set: an index past them coloured pixels with
// uninitialised stack memory (found by an exploratory session). Where the PLTE leaves indices
// that the bit depth allows uncovered, these are two copies of the file whose PLTE is filled up
// to 256 entries, entry k grey k in `low` and grey 255 - k in `high`: decoded, they agree
// wherever the pixels' indices lie within the `entries` the file gives, and where they do not,
// `low`'s red is the index. nullopt for every other file, and for those stb refuses anyway (no
// PLTE, a tRNS longer than the palette) or check_png does.
struct PngPaletteProbe {
    std::vector<std::uint8_t> low, high;
    unsigned entries = 0;
};
std::optional<PngPaletteProbe> png_palette_probe(const std::vector<std::uint8_t>& bytes);

// Whether stb could read past the end of these bytes without failing: every format but PNG,
// JPEG and HDR (whose readers check, or check_image_data() did). Such files are decoded twice,
// padded with zeros and with 0xFF bytes (image.cpp): a decoder that reads past the end gives
// two different images.
bool needs_padding_check(const std::vector<std::uint8_t>& bytes);

// The offset just past a JPEG's start-of-image marker, as stb's test finds it (any number of
// 0xFF bytes, then 0xD8), or 0 where the bytes are not a JPEG.
std::size_t jpeg_start(const std::vector<std::uint8_t>& bytes);

// Whether stb decodes these bytes as TGA: it tries TGA last, as the format without a signature,
// so a file none of the other decoders' signatures match, whose header names a TGA image type.
bool is_tga(const std::vector<std::uint8_t>& bytes);

// Whether these bytes are a PSD of 16 bits a channel. stb 2.27's stbi_is_16_bit says no to every
// PSD: its test skips the height and width with STBI_NOTUSED(get32be(s)), a sizeof that never
// reads them, and takes the height's first bytes for the depth (16-bit PSD heights came at 8 bits).
bool psd_is_16_bit(const std::vector<std::uint8_t>& bytes);

// A JPEG's EXIF orientation (tag 0x0112 of its APP1 "Exif" segment's first IFD): 1 (as stored,
// also for other formats and where there is none or it is unreadable) to 8. stb_image ignores
// it: a photo taken upright on a phone turned, as colour or height, on its side.
int jpeg_exif_orientation(const std::vector<std::uint8_t>& bytes);

// A binary PNM's (P5, P6) largest sample value, from its header; nullopt for other formats.
// stb_image returns the samples as stored, so values of a maxval other than 255 or 65535 must
// be scaled by the caller (stb took 127 for a full 8-bit sample, and 4095 for a 16-bit one).
std::optional<int> pnm_maxval(const std::vector<std::uint8_t>& bytes);

} // namespace pr
