#!/usr/bin/env python3
"""Writes the hostile and odd input files of tests/bad/ that are binary (images, binary meshes).

Python standard library only (zlib + struct write PNGs; a baseline JPEG is assembled by hand).
The outputs are tiny and committed; run this again only to regenerate them:

    python3 tests/bad/make_bad_images.py        # writes next to this script

Each file's expected outcome is in docs/robustness.md and tests/cli/robustness_tests.cmake.
"""
import os
import random
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(HERE, name), "wb") as f:
        f.write(data)


# ---- PNG ------------------------------------------------------------------------------------

def chunk(kind, payload):
    body = kind + payload
    return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)


def png(width, height, bit_depth, colour_type, rows, palette=None):
    """rows: list of bytes objects, one per row (top row first), already packed."""
    sig = b"\x89PNG\r\n\x1a\n"
    ihdr = struct.pack(">IIBBBBB", width, height, bit_depth, colour_type, 0, 0, 0)
    raw = b"".join(b"\x00" + r for r in rows)  # filter 0 (None) on every row
    out = sig + chunk(b"IHDR", ihdr)
    if palette is not None:
        out += chunk(b"PLTE", b"".join(bytes(c) for c in palette))
    return out + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")


def bumps(x, y, n):
    """A smooth, tileable bump pattern in [0, 1]."""
    import math
    return 0.5 + 0.25 * math.sin(2 * math.pi * 2 * x / n) + 0.25 * math.sin(2 * math.pi * 2 * y / n)


N = 32
grey8 = [bytes(int(round(255 * bumps(x, y, N))) for x in range(N)) for y in range(N)]
valid_grey = png(N, N, 8, 0, grey8)

# Valid but odd: each must render.
write("one_pixel.png", png(1, 1, 8, 0, [bytes([200])]))
write("sixteen_bit.png", png(N, N, 16, 0, [b"".join(struct.pack(">H", int(round(65535 * bumps(x, y, N))))
                                                       for x in range(N)) for y in range(N)]))
# Eight steps along u that use a sliver of the 16-bit range (64/65535 each; max 448): under a
# large --depth the steps are as tall as the full-range map's under a small one (cli.compare_
# prism_hit_tolerance_low_range_map, the hit tolerance against the pixel; forty-first session).
write("low_range_steps16.png", png(64, 64, 16, 0, [b"".join(struct.pack(">H", (x * 8 // 64) * 64) for x in range(64))
                                                  for y in range(64)]))
palette = [(i * 16, i * 16, i * 16) for i in range(16)]  # grey ramp, 16 entries
write("paletted.png", png(N, N, 8, 3, [bytes(int(round(15 * bumps(x, y, N))) for x in range(N))
                                       for y in range(N)], palette))
write("alpha.png", png(N, N, 8, 6, [b"".join(bytes([int(round(255 * bumps(x, y, N))), 64 + x * 4, 128,
                                                     255 if (x + y) % 8 else 0]) for x in range(N))
                                    for y in range(N)]))
write("grey_alpha.png", png(N, N, 8, 4, [b"".join(bytes([int(round(255 * bumps(x, y, N))), 255 - 4 * y])
                                                  for x in range(N)) for y in range(N)]))
# Found by fuzzing (tests/fuzz/fuzz_image): an empty IDAT chunk before the image data made
# stb_image 2.27 memcpy to a null pointer (undefined behaviour). A valid PNG: it must render.
sig_ihdr = valid_grey[:8 + 25]  # signature and IHDR chunk
assert valid_grey[8 + 25 + 4:8 + 25 + 8] == b"IDAT"
write("fuzz_png_empty_idat.png", sig_ihdr + chunk(b"IDAT", b"") + valid_grey[8 + 25:])

# Refused with one line naming the file.
write("truncated.png", valid_grey[: len(valid_grey) * 2 // 3])
write("truncated_header.png", valid_grey[:20])  # cut inside IHDR
write("zero_size.png", png(0, 0, 8, 0, []))
write("huge_header.png", b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 100000, 100000, 8, 0, 0, 0, 0))
      + chunk(b"IEND", b""))
write("huge_area.png", b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", 16000, 16000, 8, 0, 0, 0, 0))
      + chunk(b"IEND", b""))
# Found by an exploratory session: stb_image 2.27 checks no CRC (nor zlib's Adler-32), and
# decoded a damaged IDAT to wrong heights with exit 0 (here one bit flipped where the deflate
# stream still inflates to as many bytes); it refused a file without IEND for an empty reason.
damaged = bytearray(valid_grey)
damaged[valid_grey.index(b"IDAT") + 4 + 66] ^= 0x01
assert len(zlib.decompressobj(-15).decompress(bytes(damaged[valid_grey.index(b"IDAT") + 6:]))) == N * (N + 1)
write("damaged_idat.png", bytes(damaged))
write("no_iend.png", valid_grey[:-12])
# Found by an exploratory session: stb_image 2.27 looked palette indices past the PLTE up in
# uninitialised stack memory (exit 0). A 2-entry PLTE, indices 0 to 7.
write("palette_index_past_plte.png", png(N, N, 8, 3, [bytes(x % 8 for x in range(N)) for y in range(N)],
                                         [(0, 0, 0), (255, 255, 255)]))

# ---- PNM ----------------------------------------------------------------------------------------

# A sample past the maxval (found by an exploratory session): it was clamped to the top height.
write("over_maxval.pgm", b"P5\n4 4\n100\n" + bytes([100] * 15 + [255]))
# Sizes and a maxval past an int (found by an exploratory session): stb_image 2.27 read them with
# signed overflow and said "-2147483648x1 pixels", or "unknown format" for the maxval.
write("pnm_huge_width.pgm", b"P5\n2147483648 1\n255\n" + bytes(16))
write("pnm_huge_maxval.pgm", b"P5\n2 2\n99999999999\n" + bytes(16))

# ---- TGA ----------------------------------------------------------------------------------------

def tga(image_type, width, height, bits, data, cmap=None):
    """cmap: the colour map's entries (24-bit BGR triples) for a colour-mapped image (types 1, 9)."""
    entries = b"".join(bytes(c) for c in cmap) if cmap else b""
    header = struct.pack("<BBBHHBHHHHBB", 0, 1 if cmap else 0, image_type, 0, len(cmap) if cmap else 0,
                         24 if cmap else 0, 0, 0, width, height, bits, 0)
    return header + entries + data


# Valid: a 16-entry grey ramp, 8-bit indices of the bumps; must render.
write("paletted.tga", tga(1, N, N, 8, b"".join(bytes(int(round(15 * bumps(x, y, N))) for x in range(N))
                                                for y in range(N)), palette))
# Found by an exploratory session: indices past the colour map's 2 entries, which stb_image 2.27
# took for entry 0 without a word (raw 8-bit, run-length 8-bit, raw 16-bit indices).
black_white = [(0, 0, 0), (255, 255, 255)]
write("palette_index_past_map.tga", tga(1, 4, 4, 8, bytes([0, 1, 7, 1] * 4), black_white))
write("palette_index_past_map_rle.tga", tga(9, 4, 4, 8, bytes([0x87, 1, 0x03, 0, 1, 0, 9, 0x83, 0]), black_white))
write("palette_index_past_map_16bit.tga", tga(1, 2, 2, 16, struct.pack("<4H", 0, 1, 1, 300), black_white))

# ---- JPEG (baseline, one grey component, every coefficient zero: a uniform 50 % grey) ---------

def segment(marker, payload):
    return bytes([0xFF, marker]) + struct.pack(">H", len(payload) + 2) + payload


def jpeg(width, height, scan=True):
    dqt = segment(0xDB, b"\x00" + bytes([1] * 64))
    sof = segment(0xC0, struct.pack(">BHHB", 8, height, width, 1) + bytes([1, 0x11, 0]))
    one_code = bytes([1] + [0] * 15)  # a single Huffman code of length 1 ('0')
    dht = segment(0xC4, b"\x00" + one_code + b"\x00" + b"\x10" + one_code + b"\x00")
    sos = segment(0xDA, bytes([1, 1, 0x00, 0, 63, 0]))
    blocks = ((width + 7) // 8) * ((height + 7) // 8)
    bits = "00" * blocks  # DC difference category 0, then end-of-block
    bits += "1" * (-len(bits) % 8)
    data = bytes(int(bits[i:i + 8], 2) for i in range(0, len(bits), 8))
    data = data.replace(b"\xff", b"\xff\x00")
    out = b"\xff\xd8" + dqt + sof + dht
    if scan:
        out += sos + data + b"\xff\xd9"
    return out


tiny = jpeg(16, 16)
write("tiny.jpg", tiny)                                   # valid: renders (uniform height)
write("truncated.jpg", tiny[: len(tiny) - 30])            # cut inside the Huffman tables
write("huge_header.jpg", jpeg(60000, 60000, scan=False))  # claims 60000x60000, no scan
# An APP1 segment claiming 65535 bytes in a file of a few hundred, and one claiming 1 (less than
# its own length field): stb said "unknown format" of both.
write("segment_past_end.jpg", b"\xff\xd8" + b"\xff\xe1\xff\xff" + b"Exif\x00\x00" + tiny[2:])
write("segment_too_short.jpg", b"\xff\xd8" + b"\xff\xe1\x00\x01" + tiny[2:])

# ---- binary meshes -----------------------------------------------------------------------------

rng = random.Random(7)
noise = bytes(rng.randrange(256) for _ in range(1000))
write("garbage.stl", noise)                              # neither ASCII nor binary STL
write("garbage_binary.ply", noise)                       # no PLY header at all
# A binary STL header claiming 42,949,672 triangles (2.1 GB) in an 84-byte file.
write("huge_header.stl", b"binary STL header claiming 2 GB".ljust(80, b" ") + struct.pack("<I", 42949672))
# A PLY header claiming 2^31-1 vertices and faces: nothing may be allocated for it.
write("huge_header.ply", b"ply\nformat binary_little_endian 1.0\nelement vertex 2147483647\n"
      b"property float x\nproperty float y\nproperty float z\nelement face 2147483647\n"
      b"property list uchar int vertex_indices\nend_header\n" + noise[:64])
# A binary PLY triangle, its face list counted in an int: read as it is. A count of -1 or 1e9
# (found by an exploratory session) made OpenMesh size a vector from it: minutes, gigabytes.
ply_triangle = (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                b"property float z\nelement face 1\nproperty list int int vertex_indices\nend_header\n"
                + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0))
write("binary_triangle.ply", ply_triangle + struct.pack("<4i", 3, 0, 1, 2))
write("ply_negative_face_count.ply", ply_triangle + struct.pack("<4i", -1, 0, 1, 2))
write("ply_huge_face_count.ply", ply_triangle + struct.pack("<4i", 1000000000, 0, 1, 2))
# An unsigned index past 2^31 (forty-second session): the reader's 32-bit handles said it as
# "-1294967296".
write("ply_uint_index_past_2_31.ply",
      ply_triangle.replace(b"property list int int vertex_indices", b"property list uchar uint vertex_indices")
      + struct.pack("<B3I", 3, 0, 1, 3000000000))
# A face with a second list of indices (found by an exploratory session, forty-second): the
# reader took each list for a face and drew another mesh, exit 0.
write("ply_two_index_lists.ply",
      ply_triangle.replace(b"property list int int vertex_indices\n",
                           b"property list uchar int vertex_indices\nproperty list uchar int vertex_index\n")
      + struct.pack("<B3iB3i", 3, 0, 1, 2, 3, 0, 2, 1))

# ---- named, where stb's info said nothing of the format (thirty-fifth session) -------------------
# A Softimage PIC whose packet type is none of 0-2, and a valid RGB one cut short: stb 2.27 freed
# the failed decode and converted the null pointer (a height map, which asks for the file's own
# channels: a segmentation fault).
def pic_header(w, h):
    return b"\x53\x80\xF6\x34" + struct.pack(">f", 3.71) + b"\0" * 80 + b"PICT" + struct.pack(">HHfHH", w, h, 1.0, 3, 0)


write("pic_bad_packet.pic", pic_header(4, 4) + bytes([0, 8, 7, 0xE0]) + b"\x80" * 48)
write("pic_cut.pic", (pic_header(32, 24) + bytes([0, 8, 0, 0xE0]) + bytes((x * 8) & 255 for y in range(24) for x in range(32)
                                                                         for c in range(3)))[:400])
# Readable formats in forms stb does not read: a Radiance file stored bottom row first, a greyscale
# PSD, a run-length BMP (they said "unknown format", or "corrupt or unsupported" without why).
write("hdr_plus_y.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 3 +X 4\n" + bytes([128, 128, 128, 128]) * 12)
write("psd_grey.psd", b"8BPS" + struct.pack(">H6xHIIHH", 1, 1, 3, 4, 8, 1) + struct.pack(">III", 0, 0, 0) +
      struct.pack(">H", 0) + bytes(range(12)))
rle = bytearray()
for y in range(3):
    for x in range(4):
        rle += bytes([1, x * 60 + y * 20])
    rle += b"\0\0"
rle[-2:] = b"\0\1"
grey_palette = b"".join(bytes([i, i, i, 0]) for i in range(256))
bmp_offset = 14 + 40 + len(grey_palette)
write("bmp_rle8.bmp", b"BM" + struct.pack("<IHHI", bmp_offset + len(rle), 0, 0, bmp_offset) +
      struct.pack("<IiiHHIIiiII", 40, 4, 3, 1, 8, 1, len(rle), 2835, 2835, 256, 0) + grey_palette + bytes(rle))
# A PIC header of 16384x4096 and no packets: stb's info fails in the packets; decoding it for a
# reason allocated and cleared the whole image first (256 MiB for 104 bytes).
write("pic_no_packets.pic", pic_header(16384, 4096))
# A PIC header of 16384x4096, one mixed run-length packet and no rows: decoding it allocated and
# cleared the whole image before it found the rows missing (thirty-sixth session); and a mixed run
# of 65 pixels in a row of 64.
write("pic_no_rows.pic", pic_header(16384, 4096) + bytes([0, 8, 2, 0xE0]) + b"\x80")
pic_row = bytes([128]) + struct.pack(">H", 64) + bytes([100, 100, 100])
write("pic_overrun.pic", pic_header(64, 4) + bytes([0, 8, 2, 0xE0]) + pic_row +
      bytes([128]) + struct.pack(">H", 65) + bytes([1, 2, 3]) + pic_row * 2)
# A PIC header of 16384x4096 whose one packet carries no channel: every row whole without a byte,
# and stb decoded the image it cleared (580 MB for 109 bytes; thirty-sixth session, a review).
write("pic_no_channel.pic", pic_header(16384, 4096) + bytes([0, 8, 0, 0x0F]) + b"\x80")
