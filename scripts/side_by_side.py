#!/usr/bin/env python3
"""Puts rendered PNGs (8-bit RGBA, same size) side by side on white, 4-pixel gaps, as one RGB PNG.

    python3 scripts/side_by_side.py none.png hard.png soft.png docs/images/shadows.png
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pngio import read_png8, write_png  # noqa: E402


def main():
    if len(sys.argv) < 4:
        sys.exit(__doc__)
    images = [read_png8(p) for p in sys.argv[1:-1]]
    w, h = images[0][0], images[0][1]
    if any((i[0], i[1]) != (w, h) for i in images):
        sys.exit("the images differ in size")
    gap = 4
    rows = []
    for y in range(h):
        row = bytearray()
        for k, (_, _, ch, pixels) in enumerate(images):
            for x in range(w):
                px = pixels[y][x * ch:x * ch + ch]
                a = px[3] / 255 if ch == 4 else 1.0  # alpha = coverage: the background shows white
                row += bytes(int(px[c] * a + 255 * (1 - a)) for c in range(3))
            if k + 1 < len(images):
                row += b"\xff\xff\xff" * gap
        rows.append(row)
    write_png(sys.argv[-1], len(images) * w + (len(images) - 1) * gap, rows, colour_type=2)


if __name__ == "__main__":
    main()
