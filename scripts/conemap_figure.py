#!/usr/bin/env python3
"""docs/images/conemap_boxes.png: a height map next to its cone and relaxed-cone ratios.

Reads two 8-bit cone maps written by `prismrelief conemap --format rg8` (PNG, R = height,
G = sqrt(c)) and writes one grey PNG of three panels: height, cone ratio, relaxed ratio, with a
4-pixel white gap. Python standard library only (scripts/pngio.py).

    prismrelief conemap --height builtin:boxes@256 --format rg8 --out cone.png --no-cache
    prismrelief conemap --height builtin:boxes@256 --format rg8 --kind relaxed --out relaxed.png --no-cache
    python3 scripts/conemap_figure.py cone.png relaxed.png docs/images/conemap_boxes.png
"""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pngio import read_png8, write_png  # noqa: E402


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
    write_png(sys.argv[3], 3 * w + 2 * gap, out)


if __name__ == "__main__":
    main()
