#!/usr/bin/env python3
"""Writes a UV sphere as OBJ for the mesh-input checks of docs/mesh-input.md (write it outside the
source tree):

    python3 scripts/make_test_sphere.py 32 16 normal > /tmp/sphere.obj        # UVs 0..2 x 0..1
    python3 scripts/make_test_sphere.py 32 16 uvpoint > /tmp/uvpoint.obj      # every vt at (0.3, 0.3)
    python3 scripts/make_test_sphere.py 32 16 inverted_dup > /tmp/invdup.obj  # wound inward, one face twice
"""
import math
import sys


def main():
    if len(sys.argv) != 4 or sys.argv[3] not in ("normal", "uvpoint", "inverted_dup"):
        sys.exit(__doc__)
    nlon, nlat, mode = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    positions, ids, uvs, faces = [], {}, [], []

    def position(i, j):  # the poles are one vertex each
        key = "s" if j == 0 else "n" if j == nlat else (i % nlon, j)
        if key not in ids:
            p, t = 2 * math.pi * i / nlon, math.pi * j / nlat
            ids[key] = len(positions) + 1
            positions.append((math.sin(t) * math.cos(p), -math.cos(t), -math.sin(t) * math.sin(p)))
        return ids[key]

    def corner(i, j):
        uvs.append((0.3, 0.3) if mode == "uvpoint" else (2 * i / nlon, j / nlat))
        return position(i, j), len(uvs)

    for j in range(nlat):
        for i in range(nlon):
            a, b, c, d = corner(i, j), corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)
            if j > 0:
                faces.append((a, b, c))
            if j < nlat - 1:
                faces.append((a, c, d))
    if mode == "inverted_dup":
        faces = [f[::-1] for f in faces]
        faces.append(faces[min(200, len(faces) - 1)])
    for p in positions:
        print("v %.9g %.9g %.9g" % p)
    for t in uvs:
        print("vt %.9g %.9g" % t)
    for f in faces:
        print("f " + " ".join("%d/%d" % c for c in f))


main()
