#!/usr/bin/env python3
"""Writes a finely subdivided torus as OBJ (with UVs) for the memory and time measurements of
docs/robustness.md. The file is large (about 68 MB for a million triangles): write it outside the
source tree and do not commit it.

    python3 scripts/make_big_mesh.py /tmp/torus_1m.obj            # 1000 x 500 quads = 1,000,000 triangles
    python3 scripts/make_big_mesh.py /tmp/t.obj --rings 200 --sides 100
"""
import argparse
import math


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out")
    ap.add_argument("--rings", type=int, default=1000, help="segments around the main axis")
    ap.add_argument("--sides", type=int, default=500, help="segments around the tube")
    ap.add_argument("--major", type=float, default=1.0)
    ap.add_argument("--minor", type=float, default=0.35)
    a = ap.parse_args()
    n, m = a.rings, a.sides
    with open(a.out, "w") as f:
        f.write(f"# torus, {n} x {m} quads, {2 * n * m} triangles (scripts/make_big_mesh.py)\n")
        # Positions wrap around (n*m distinct); UVs get a seam ((n+1)*(m+1) of them).
        for i in range(n):
            u = 2 * math.pi * i / n
            for j in range(m):
                v = 2 * math.pi * j / m
                r = a.major + a.minor * math.cos(v)
                f.write(f"v {r * math.cos(u):.6f} {a.minor * math.sin(v):.6f} {r * math.sin(u):.6f}\n")
        for i in range(n + 1):
            for j in range(m + 1):
                f.write(f"vt {4.0 * i / n:.6f} {1.0 * j / m:.6f}\n")
        for i in range(n):
            for j in range(m):
                p = lambda di, dj: ((i + di) % n) * m + (j + dj) % m + 1
                t = lambda di, dj: (i + di) * (m + 1) + (j + dj) + 1
                a0, b0, c0, d0 = p(0, 0), p(1, 0), p(1, 1), p(0, 1)
                ta, tb, tc, td = t(0, 0), t(1, 0), t(1, 1), t(0, 1)
                # Counter-clockwise seen from outside.
                f.write(f"f {a0}/{ta} {d0}/{td} {c0}/{tc}\nf {a0}/{ta} {c0}/{tc} {b0}/{tb}\n")


if __name__ == "__main__":
    main()
