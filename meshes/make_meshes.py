#!/usr/bin/env python3
"""Writes the bundled meshes of prismrelief (see meshes/README.md).

Python 3 standard library only; deterministic (fixed seeds, fixed number formatting), so running
it again reproduces the committed files byte for byte:

    python3 meshes/make_meshes.py            # writes into the folder of this script
    python3 meshes/make_meshes.py OUT_DIR

Conventions shared by every mesh: Y is up, faces are counter-clockwise seen from outside,
closed shapes are closed (every edge shared by exactly two faces), UVs have their origin at the
bottom left and are never mirrored: dP/du x dP/dv points outwards. The script checks these
properties before writing.
"""
import math
import os
import random
import sys


# ---- small vector helpers --------------------------------------------------------------------

def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def mul(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    length = math.sqrt(dot(a, a))
    return mul(a, 1.0 / length)


def num(x):
    """Fixed formatting: six decimals, trailing zeros stripped, no negative zero."""
    s = '%.6f' % x
    s = s.rstrip('0').rstrip('.')
    return '0' if s in ('-0', '') else s


# ---- checks ----------------------------------------------------------------------------------

def check(name, positions, faces, uvs=None, face_uvs=None, closed=True, centre=None):
    """Faces CCW seen from outside, edges shared by two faces with opposite directions when
    closed, and UV triangles not mirrored (positive area when the UV map is orientation
    preserving)."""
    edges = {}
    for f in faces:
        for i in range(len(f)):
            a, b = f[i], f[(i + 1) % len(f)]
            assert a != b, name + ': repeated vertex'
            assert (a, b) not in edges, name + ': edge used twice in one direction'
            edges[(a, b)] = True
    if closed:
        for (a, b) in edges:
            assert (b, a) in edges, name + ': open edge'
    volume = 0.0
    for fi, f in enumerate(faces):
        p0 = positions[f[0]]
        for i in range(1, len(f) - 1):
            p1, p2 = positions[f[i]], positions[f[i + 1]]
            n = cross(sub(p1, p0), sub(p2, p0))
            volume += dot(p0, cross(p1, p2)) / 6.0
            if centre is not None:
                c = mul(add(add(p0, p1), p2), 1.0 / 3.0)
                assert dot(n, sub(c, centre)) > 0.0, name + ': face %d points inwards' % fi
            if face_uvs is not None:
                t = face_uvs[fi]
                u0, u1, u2 = uvs[t[0]], uvs[t[i]], uvs[t[i + 1]]
                area = (u1[0] - u0[0]) * (u2[1] - u0[1]) - (u2[0] - u0[0]) * (u1[1] - u0[1])
                assert area > 0.0, name + ': face %d has mirrored or degenerate UVs' % fi
    if closed:
        assert volume > 0.0, name + ': negative volume (inside out)'


# ---- writers ---------------------------------------------------------------------------------

def write(path, lines):
    with open(path, 'w', newline='\n') as f:
        f.write('\n'.join(lines) + '\n')


def write_obj(path, comment, positions, faces, uvs=None, face_uvs=None, normals=None,
              face_normals=None):
    lines = ['# ' + c for c in comment]
    lines += ['v %s %s %s' % tuple(num(c) for c in p) for p in positions]
    if uvs is not None:
        lines += ['vt %s %s' % (num(u), num(v)) for (u, v) in uvs]
    if normals is not None:
        lines += ['vn %s %s %s' % tuple(num(c) for c in n) for n in normals]
    for fi, f in enumerate(faces):
        corners = []
        for i, v in enumerate(f):
            s = str(v + 1)
            if face_uvs is not None:
                s += '/' + str(face_uvs[fi][i] + 1)
            if face_normals is not None:
                s += ('/' if face_uvs is not None else '//') + str(face_normals[fi][i] + 1)
            corners.append(s)
        lines.append('f ' + ' '.join(corners))
    write(path, lines)


# ---- cube ------------------------------------------------------------------------------------

# Six faces as (outward normal, U axis, V axis) with U x V = normal: the same "seen from
# outside, U right, V up" layout as the renderer's generated box UVs.
CUBE_FRAMES = [
    ((1, 0, 0), (0, 0, -1), (0, 1, 0)),
    ((-1, 0, 0), (0, 0, 1), (0, 1, 0)),
    ((0, 1, 0), (1, 0, 0), (0, 0, -1)),
    ((0, -1, 0), (1, 0, 0), (0, 0, 1)),
    ((0, 0, 1), (1, 0, 0), (0, 1, 0)),
    ((0, 0, -1), (-1, 0, 0), (0, 1, 0)),
]


def make_cube(out):
    positions = [(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    index = {p: i for i, p in enumerate(positions)}
    uvs = [(0, 0), (1, 0), (1, 1), (0, 1)]
    faces, face_uvs, face_normals = [], [], []
    for k, (n, a, b) in enumerate(CUBE_FRAMES):
        quad = []
        for (s, t) in uvs:
            p = add(add(n, mul(a, 2 * s - 1)), mul(b, 2 * t - 1))
            quad.append(index[p])
        faces.append(quad)
        face_uvs.append([0, 1, 2, 3])
        face_normals.append([k] * 4)
    normals = [n for (n, _, _) in CUBE_FRAMES]
    check('cube', positions, faces, uvs, face_uvs, centre=(0, 0, 0))
    write_obj(os.path.join(out, 'cube.obj'),
              ['cube.obj: side 2, centred at the origin; 8 positions, 6 quads with per-face UVs',
               '0..1 (U right, V up seen from outside) and per-face normals. make_meshes.py'],
              positions, faces, uvs, face_uvs, normals, face_normals)


# ---- UV sphere -------------------------------------------------------------------------------

def make_uv_sphere(out, segments=32, rings=16):
    # u = longitude (seam at -Z, u = 0.5 faces +Z), v = latitude from the south pole (v = 0) to
    # the north pole (v = 1); one position per pole, one UV per pole triangle.
    def point(u, v):
        phi = 2.0 * math.pi * u - math.pi
        theta = math.pi * v - 0.5 * math.pi
        c = math.cos(theta)
        return (c * math.sin(phi), math.sin(theta), c * math.cos(phi))

    positions = [(0.0, -1.0, 0.0), (0.0, 1.0, 0.0)]
    ring_start = len(positions)
    for j in range(1, rings):
        for i in range(segments):
            positions.append(point(i / segments, j / rings))

    def pos(i, j):
        if j == 0:
            return 0
        if j == rings:
            return 1
        return ring_start + (j - 1) * segments + (i % segments)

    uvs = [(i / segments, j / rings) for j in range(rings + 1) for i in range(segments + 1)]

    def uv(i, j):
        return j * (segments + 1) + i

    faces, face_uvs = [], []
    for j in range(rings):
        for i in range(segments):
            if j == 0:
                # south cap: the pole UV sits under the middle of the segment
                faces.append([pos(i, 0), pos(i + 1, 1), pos(i, 1)])
                pole = len(uvs)
                uvs.append(((i + 0.5) / segments, 0.0))
                face_uvs.append([pole, uv(i + 1, 1), uv(i, 1)])
            elif j == rings - 1:
                faces.append([pos(i, j), pos(i + 1, j), pos(i, rings)])
                pole = len(uvs)
                uvs.append(((i + 0.5) / segments, 1.0))
                face_uvs.append([uv(i, j), uv(i + 1, j), pole])
            else:
                faces.append([pos(i, j), pos(i + 1, j), pos(i + 1, j + 1), pos(i, j + 1)])
                face_uvs.append([uv(i, j), uv(i + 1, j), uv(i + 1, j + 1), uv(i, j + 1)])
    check('uv_sphere', positions, faces, uvs, face_uvs, centre=(0, 0, 0))
    write_obj(os.path.join(out, 'uv_sphere.obj'),
              ['uv_sphere.obj: radius 1, %d segments x %d rings, Y up. u = longitude with the'
               % (segments, rings),
               'seam at -Z, v = latitude from the south pole (0) to the north pole (1).',
               'make_meshes.py'],
              positions, faces, uvs, face_uvs)


# ---- torus -----------------------------------------------------------------------------------

def make_torus(out, major=48, minor=24, R=1.0, r=0.35, u_repeat=3):
    # Lies in the XZ plane around the Y axis. u runs around the ring (u_repeat times), v around
    # the tube (once); u_repeat = 3 makes texels about square at the tube's middle
    # (2 pi R / 3 = 2.09 vs 2 pi r = 2.20).
    def point(a, b):
        theta, psi = 2.0 * math.pi * a, 2.0 * math.pi * b
        w = R + r * math.cos(psi)
        return (w * math.cos(theta), r * math.sin(psi), -w * math.sin(theta))

    positions = [point(i / major, j / minor) for i in range(major) for j in range(minor)]
    uvs = [(u_repeat * i / major, j / minor) for i in range(major + 1) for j in range(minor + 1)]
    faces, face_uvs = [], []
    for i in range(major):
        for j in range(minor):
            def p(a, b):
                return (a % major) * minor + (b % minor)

            def t(a, b):
                return a * (minor + 1) + b
            faces.append([p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1)])
            face_uvs.append([t(i, j), t(i + 1, j), t(i + 1, j + 1), t(i, j + 1)])
    check('torus', positions, faces, uvs, face_uvs)
    write_obj(os.path.join(out, 'torus.obj'),
              ['torus.obj: R = %g, r = %g around the Y axis, %d x %d quads (not triangulated).'
               % (R, r, major, minor),
               'u: %d repeats around the ring, v: once around the tube. make_meshes.py' % u_repeat],
              positions, faces, uvs, face_uvs)


# ---- plane -----------------------------------------------------------------------------------

def make_plane(out, n=16, size=2.0):
    # Faces +Y (a floor). U = +X, V = -Z: seen from above with -Z at the top, U goes right and
    # V up, so dP/du x dP/dv = +Y.
    positions, uvs = [], []
    for j in range(n + 1):
        for i in range(n + 1):
            s, t = i / n, j / n
            positions.append(((s - 0.5) * size, 0.0, (0.5 - t) * size))
            uvs.append((s, t))
    faces = []
    for j in range(n):
        for i in range(n):
            a = j * (n + 1) + i
            faces.append([a, a + 1, a + n + 2, a + n + 1])
    check('plane', positions, faces, uvs, faces, closed=False)
    for f in faces:
        p0, p1, p2 = positions[f[0]], positions[f[1]], positions[f[2]]
        assert cross(sub(p1, p0), sub(p2, p0))[1] > 0.0
    write_obj(os.path.join(out, 'plane.obj'),
              ['plane.obj: %g x %g in the XZ plane facing +Y, %d x %d quads, UV 0..1 with'
               % (size, size, n, n),
               'U = +X and V = -Z. make_meshes.py'],
              positions, faces, uvs, faces)


# ---- blob (OFF, no UVs) ----------------------------------------------------------------------

def icosphere(levels):
    t = (1.0 + math.sqrt(5.0)) / 2.0
    verts = [norm(v) for v in [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
                                (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
                                (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
             (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
             (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
             (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        cache = {}

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                cache[key] = len(verts)
                verts.append(norm(mul(add(verts[a], verts[b]), 0.5)))
            return cache[key]
        new = []
        for (a, b, c) in faces:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            new += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        faces = new
    return verts, [list(f) for f in faces]


def make_blob(out, levels=4):
    rng = random.Random(20240601)
    waves = []
    for k in range(9):
        d = norm((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        freq = 1.5 + 1.2 * k
        waves.append((d, freq, rng.uniform(0, 2 * math.pi), 0.16 / (1.0 + 0.6 * k)))
    dirs, faces = icosphere(levels)
    positions = []
    for d in dirs:
        r = 1.0 + sum(a * math.sin(f * dot(d, w) + ph) for (w, f, ph, a) in waves)
        positions.append(mul(d, r))
    check('blob', positions, faces, centre=(0, 0, 0))
    lines = ['OFF', '%d %d 0' % (len(positions), len(faces))]
    lines += ['%s %s %s' % tuple(num(c) for c in p) for p in positions]
    lines += ['3 %d %d %d' % tuple(f) for f in faces]
    write(os.path.join(out, 'blob.off'), lines)


# ---- rock (OBJ with an atlas of six UV islands) ----------------------------------------------

def make_rock(out, n=28):
    """A cube sphere pushed out radially into a lumpy, chipped stone. UVs: the six cube faces are
    six unmirrored islands in a 3 x 2 atlas, as a modelling tool would lay them out; texel
    density varies mildly (equal-angle cube mapping plus the displacement)."""
    rng = random.Random(7)
    waves = []
    for k in range(12):
        d = norm((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        waves.append((d, 1.3 + 0.9 * k, rng.uniform(0, 2 * math.pi), 0.11 / (1.0 + 0.7 * k)))
    chips = []  # flat cuts: a plane with normal c at distance h clips the radius
    for _ in range(7):
        c = norm((rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1)))
        chips.append((c, rng.uniform(0.78, 0.9)))
    squash = (1.15, 0.72, 0.95)

    def radius(d):
        r = 1.0 + sum(a * math.sin(f * dot(d, w) + ph) for (w, f, ph, a) in waves)
        for (c, h) in chips:
            cd = dot(d, c)
            if cd > 1e-6:
                r = min(r, h / cd)
        return r

    def cube_coord(c):
        # lattice 0..n -> [-1, 1] with equal angles; the ends are exact
        if c == 0:
            return -1.0
        if c == n:
            return 1.0
        return math.tan(math.pi / 4.0 * (2.0 * c / n - 1.0))

    positions, index = [], {}

    def vertex(key):
        if key not in index:
            d = norm(tuple(cube_coord(c) for c in key))
            p = mul(d, radius(d))
            index[key] = len(positions)
            positions.append((p[0] * squash[0], p[1] * squash[1], p[2] * squash[2]))
        return index[key]

    margin = 0.02
    uvs, faces, face_uvs = [], [], []
    for island, (nrm, a, b) in enumerate(CUBE_FRAMES):
        col, row = island % 3, island // 3
        base = len(uvs)
        for j in range(n + 1):
            for i in range(n + 1):
                s = margin + (1 - 2 * margin) * i / n
                t = margin + (1 - 2 * margin) * j / n
                uvs.append(((col + s) / 3.0, (row + t) / 2.0))

        def key(i, j):
            # lattice point of the cube surface: n on the face's normal axis, (i, j) along a, b
            k = [0, 0, 0]
            for axis in range(3):
                k[axis] = n if nrm[axis] > 0 else 0
                if a[axis] != 0:
                    k[axis] = i if a[axis] > 0 else n - i
                if b[axis] != 0:
                    k[axis] = j if b[axis] > 0 else n - j
            return tuple(k)

        for j in range(n):
            for i in range(n):
                q = [vertex(key(i, j)), vertex(key(i + 1, j)), vertex(key(i + 1, j + 1)),
                     vertex(key(i, j + 1))]
                t = [base + j * (n + 1) + i, base + j * (n + 1) + i + 1,
                     base + (j + 1) * (n + 1) + i + 1, base + (j + 1) * (n + 1) + i]
                # alternate the diagonal so the triangulation has no preferred direction
                if (i + j) % 2 == 0:
                    faces += [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                    face_uvs += [[t[0], t[1], t[2]], [t[0], t[2], t[3]]]
                else:
                    faces += [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
                    face_uvs += [[t[0], t[1], t[3]], [t[1], t[2], t[3]]]
    check('rock', positions, faces, uvs, face_uvs, centre=(0, 0, 0))
    write_obj(os.path.join(out, 'rock.obj'),
              ['rock.obj: a lumpy, chipped stone (cube sphere displaced radially, %d triangles),'
               % len(faces),
               'about 2.2 x 1.5 x 1.7 units, Y up. UVs: six unmirrored islands (one per cube face)',
               'in a 3 x 2 atlas inside 0..1. make_meshes.py'],
              positions, faces, uvs, face_uvs)


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    os.makedirs(out, exist_ok=True)
    make_cube(out)
    make_uv_sphere(out)
    make_torus(out)
    make_plane(out)
    make_blob(out)
    make_rock(out)


if __name__ == '__main__':
    main()
