#!/usr/bin/env python3
"""docs/images/conemap_bumps.png: a height map next to its cone and relaxed-cone ratios.

Reads two 8-bit cone maps written by `prismrelief conemap --format rg8` (PNG, R = height,
G = sqrt(c)) and writes one grey PNG of three panels: height, cone ratio, relaxed ratio, with a
4-pixel white gap. Python standard library only (zlib + struct).

    prismrelief conemap --height builtin:bumps@256 --format rg8 --out cone.png --no-cache
    prismrelief conemap --height builtin:bumps@256 --format rg8 --kind relaxed --out relaxed.png --no-cache
    python3 scripts/conemap_figure.py cone.png relaxed.png docs/images/conemap_bumps.png
"""
import struct
import sys
import zlib


def read_png8(path):
    """Returns (width, height, channels, rows) of a non-interlaced 8-bit grey/GA/RGB/RGBA PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"{path}: not a PNG")
    pos, idat, header = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    channels = {0: 1, 4: 2, 2: 3, 6: 4}[colour]
    if depth != 8 or interlace:
        sys.exit(f"{path}: needs an 8-bit non-interlaced PNG (conemap --format rg8)")
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1:
                line[i] = (line[i] + a) & 255
            elif f == 2:
                line[i] = (line[i] + b) & 255
            elif f == 3:
                line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, channels, rows


def write_grey(path, width, rows):
    raw = b"".join(b"\0" + bytes(r) for r in rows)
    chunk = lambda k, p: struct.pack(">I", len(p)) + k + p + struct.pack(">I", zlib.crc32(k + p) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, len(rows), 8, 0, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    w, h, ch, cone = read_png8(sys.argv[1])
    w2, h2, ch2, relaxed = read_png8(sys.argv[2])
    if (w, h) != (w2, h2):
        sys.exit("the two maps differ in size")
    gap = 4
    out = []
    for y in range(h):
        row = bytearray()
        row += bytes(cone[y][x * ch] for x in range(w))          # height (R)
        row += b"\xff" * gap
        row += bytes(cone[y][x * ch + 1] for x in range(w))      # cone ratio (G)
        row += b"\xff" * gap
        row += bytes(relaxed[y][x * ch2 + 1] for x in range(w))  # relaxed ratio (G)
        out.append(row)
    write_grey(sys.argv[3], 3 * w + 2 * gap, out)


if __name__ == "__main__":
    main()
