// The prism shell of one base triangle (contract: the displaced surface lies inside the
// straight-edged prism P_i + t * depth * N_i, t in [-midlevel, 1 - midlevel]).
// Shared by prism.vert/.geom/.frag so every stage builds bit-identical corners and exits.

// World-space position and unit normal of a mesh vertex.
void shell_vertex(vec3 position, vec3 normal, out vec3 world, out vec3 n)
{
    world = (u_model * vec4(position, 1.0)).xyz;
    n = normalize(mat3(u_normal_matrix) * normal);
}

// Corner of the shell at height h (0 = bottom cap, 1 = top cap).
vec3 shell_corner(vec3 world, vec3 n, float h)
{
    return world + u_displace.x * (h - u_displace.y) * n;
}

// The side quad of edge (a, b) is split along the diagonal from the bottom of the vertex with
// the smaller welded id to the top of the other, so the two prisms sharing the edge build the
// same two triangles (ids split by UV seams would disagree; welded ids cannot).
bool diagonal_from_a(uint weld_a, uint weld_b)
{
    return weld_a < weld_b;
}

// The six corners of the prism being processed: 0..2 bottom (h = 0), 3..5 top (h = 1, or the
// walk's tight top), world space and texture space (u, v, height). Filled by the stage before it
// looks for an exit (nearest_exit, prism_exit).
vec3 corner_world[6];
vec3 corner_tex[6];
// The unit normals (world) of the current prism's vertices (load_walk_prism, and load_prism in
// prism.frag): the frame at a hit, and the prism's map (prism.frag, prism_tex_at).
vec3 corner_normal[3];

// Whether barycentric weights w lie in the triangle grown by `slack` (barycentric units).
bool in_triangle(vec3 w, float slack)
{
    return w.y >= -slack && w.z >= -slack && w.y + w.z <= 1.0 + slack;
}

// +1 when the walk's current prism (load_walk_prism) winds counter-clockwise seen from outside.
// Judged on the base triangle (height `midlevel`), which is never folded: a bottom or top cap
// offset by more than the surface's radius of curvature may be (inward shells at sharp convex
// edges, outward ones in tight creases). Judged once per triangle on the CPU (renderer.cpp,
// walk_triangles): here it cost 2 % of the rock's frame.
float walk_orientation;

// ---- The prism walk's buffers ------------------------------------------------------------------
// Buffer textures (shared.h): one texelFetch brings a whole texel for every lane; llvmpipe reads
// a storage buffer one lane and one component at a time, which made these loads the walk's
// largest cost.
layout(binding = PR_TEX_INDICES) uniform usamplerBuffer t_indices;

// The vertex indices of triangle `prim`.
uvec3 triangle_indices(uint prim)
{
    return texelFetch(t_indices, int(prim)).xyz;
}

#ifdef PR_PRISM_WALK
// Per vertex (src/render/renderer.cpp, make_shell_corners): the shell's bottom corner and u,
// the unit normal N and v, and the height of the top (shell_bounds.hpp) with the welded id.
// The caps' vertices (prism_caps.vert) read it.
struct ShellVertex {
    vec4 bottom_u;
    vec4 n_v;
    vec4 top_weld;
};
layout(binding = PR_TEX_CORNERS) uniform usamplerBuffer t_corners;

ShellVertex shell_corners(uint vertex)
{
    int o = int(3u * vertex);
    return ShellVertex(uintBitsToFloat(texelFetch(t_corners, o)), uintBitsToFloat(texelFetch(t_corners, o + 1)),
                       uintBitsToFloat(texelFetch(t_corners, o + 2)));
}

// Per prism (renderer.cpp, walk_triangles; PR_TEX_PRISMS): its three corners as in t_corners, their
// tops, its neighbours and flags, in eight texels that the prism's number alone locates, so a
// walk's step waits on one round of fetches, not on its indices first and then its vertices.
layout(binding = PR_TEX_PRISMS) uniform usamplerBuffer t_prisms;

// Prisms loaded with their tops at 1 whatever the shell (the light's walk, prism.frag: a tight
// top bounds the heights around its own vertex only).
bool g_full_tops = false;

// The height of a top whose tight height is `tight` (1 with PR_PRISM_FULL_SHELL or g_full_tops),
// and its corner. Every stage that builds a top corner calls these (`precise`: no stage may fuse
// it differently), so entry faces and exits agree to the bit.
float shell_top_height(float tight)
{
#ifdef PR_PRISM_FULL_SHELL
    return 1.0;
#else
    return g_full_tops ? 1.0 : tight;
#endif
}

vec3 shell_top_corner(vec3 bottom, vec3 n, float top)
{
    precise vec3 corner = bottom + top * (u_displace.x * n);
    return corner;
}

// The triangles across the current prism's edges (edge e from corner e to e + 1), each as
// prism << 2 | its edge; 0xffffffff where there is none (load_walk_prism).
uvec3 prism_across;

// Fills corner_world/corner_tex/corner_normal, prism_across and walk_orientation with prism
// `prim` (top at the tight height, or at 1 with PR_PRISM_FULL_SHELL), and `from_a` with its
// sides' diagonals (diagonal_from_a). The geometry shader and the walk both build their prisms
// here, so they agree to the bit.
void load_walk_prism(uint prim, out bool from_a[3])
{
    int o = int(8u * prim);
    vec4 tops = uintBitsToFloat(texelFetch(t_prisms, o + 6));
    // The neighbours, and in w bit 0 the winding (set where the base triangle winds clockwise
    // about its vertices' summed normals), bits 1..3 the sides' diagonals.
    uvec4 adjacency = texelFetch(t_prisms, o + 7);
    for (int i = 0; i < 3; ++i) {
        vec4 bottom_u = uintBitsToFloat(texelFetch(t_prisms, o + i));
        vec4 n_v = uintBitsToFloat(texelFetch(t_prisms, o + 3 + i));
        float top = shell_top_height(tops[i]);
        corner_world[i] = bottom_u.xyz;
        corner_world[i + 3] = shell_top_corner(bottom_u.xyz, n_v.xyz, top);
        corner_tex[i] = vec3(bottom_u.w, n_v.w, 0.0);
        corner_tex[i + 3] = vec3(bottom_u.w, n_v.w, top);
        corner_normal[i] = n_v.xyz;
        from_a[i] = (adjacency.w & (2u << uint(i))) != 0u;
    }
    prism_across = adjacency.xyz;
    walk_orientation = (adjacency.w & 1u) != 0u ? -1.0 : 1.0;
}
#endif

// ---- Where a ray leaves a prism -----------------------------------------------------------------
// The nearest of the prism's eight triangles (all eight: a twisted side can make the prism
// non-convex) that the ray ray_origin + t * dir (the eye's, or a light ray's) crosses beyond t_min. Face: 0 top, 1 bottom, 2 + e the
// side of edge e, with `lambda` the crossing's position along that edge (0 at corner e, 1 at
// corner e + 1); -1: none. `inside`: the crossing lies in its triangle; false where the ray
// crosses no triangle and this is the nearest crossing of their planes (nearest_exit).
struct ExitFace {
    float t;
    vec3 tex;
    int face;
    float lambda;
    bool inside;
};

// The crossing of a triangle (corners i0, i1, i2 of the prism) by the ray, from edge products
// (nearest_exit): e0, e1, e2 = edge(i1, i2), edge(i2, i0), edge(i0, i1), whose sum is
// dot(dir, the triangle's normal) and whose ratios to it are the barycentric weights of the
// plane's crossing; a0..a2 = dot(corner - origin, dir), the origin being the ray's point at
// t_origin (nearest_exit). `best` keeps the nearest crossing beyond
// t_min within the triangle grown by `slack`, or while there is none, the nearest of the planes.
// (One key orders both: the bits of t > 0 as an unsigned integer, bit 31 set outside the
// triangle; one comparison and one set of selects per candidate, not two.) It keeps the
// crossing's weights, not its texture coordinates, which nearest_exit works out for the nearest
// alone; `second`: the triangle is the second of its side's two (nearest_exit's calls). `orient`: 0 counts every
// crossing; +1 only those the ray goes *out* through, for a prism whose faces wind
// counter-clockwise seen from outside, -1 the same for one turned inside out by normals that
// oppose the winding (the walk: walk_orientation), so the face of entry needs no epsilon; and
// a crossing of `back_face` up to t_back is not one (nearest_exit).
struct ExitCandidate {
    float t;
    vec3 w;     // barycentric weights in the triangle's corner order
    int face;
    bool second; // the second of a side's two triangles
    bool inside;
};

void keep_exit(float e0, float e1, float e2, float a0, float a1, float a2, float inv_dd, float t_origin, int face,
               bool second, float t_min, int back_face, float t_back, float orient, float slack,
               inout ExitCandidate best, inout uint best_key)
{
    float den = e0 + e1 + e2; // dot(dir, normal): > 0 going out through a counter-clockwise face
    if (abs(den) < 1e-30 || den * orient < 0.0) return;
    vec3 w = vec3(e0, e1, e2) / den;
    float t = t_origin + (a0 * w.x + a1 * w.y + a2 * w.z) * inv_dd;
    if (!(t > t_min) || (face == back_face && t <= t_back)) return;
    bool inside = in_triangle(w, slack);
    uint key = floatBitsToUint(t) | (inside ? 0u : 0x80000000u);
    if (key < best_key) {
        best = ExitCandidate(t, w, face, second, inside);
        best_key = key;
    }
}

// `from_a[e]`: diagonal_from_a() of edge e. `slack` grows the faces (in_triangle): 1e-5 lets an
// exit lie exactly on an edge between two triangles. Where no triangle is crossed, the nearest of
// their planes, which on a convex prism still finds the way out of a ray that comes in just
// outside it (the rasterizer snaps vertices to its subpixel grid, so a fragment on an edge may lie
// a little outside its face). Each side's two triangles are chosen by selects, not branches
// (llvmpipe runs both arms of a branch): eight triangles in all, from the twelve edges of the
// prism: with the corners relative to the ray (P, from its point at t_entry), edge(i, j) =
// dot(dir, cross(P_i, P_j)) is the signed volume that the barycentric weights of every triangle
// on that edge come from, so two triangles sharing an edge share its value (with opposite
// signs): a ray crosses exactly one of them (Plücker-style tests, about half the arithmetic of
// one Möller-Trumbore test per triangle). The same pass tells whether the ray goes *in* through
// the top cap (grown by `slack`) at t_entry or after it (from 1e-5 * t_entry before it):
// `top_entry` (the walk, where it came from the top of the prism before), at `g_top_entry_t`, and
// gives the barycentric weights of the top's
// plane crossing, `w_top` (corners 3, 4, 5). `entry_face` (or -1): the face the walk came in by, which is no exit up to
// 1e-5 * t_entry past the entry — the prism before computed that face's products from its own
// corner order, so where the ray grazes the face's plane both prisms could find it an exit, and
// the walk would go back and forth between them to its prism limit (a hole).
float g_top_entry_t; // nearest_exit: where the ray crosses the top's plane
bool g_top_entering; // nearest_exit: it crosses that plane going in, at t_entry or after it (in the triangle or not)

ExitFace nearest_exit(vec3 ray_origin, vec3 dir, float t_min, bool from_a[3], float slack, float orient, float t_entry,
                      int entry_face, out bool top_entry, out vec3 w_top)
{
    float t_back = t_entry * (1.0 + 1e-5);
    ExitCandidate best = ExitCandidate(1e30, vec3(0.0), -1, false, false);
    uint key = 0xffffffffu;
    float inv_dd = 1.0 / dot(dir, dir);
    // The corners relative to the ray's point at t_entry, next to the prism, not to the eye: the
    // edge values are then of the prism's size, and their sums (dot(dir, normal)) keep their
    // precision (relative to the eye, terms of the eye's distance squared cancelled to a size
    // squared, and barycentric weights erred by 1e-4 at 3 units).
    vec3 origin = ray_origin + t_entry * dir;
    vec3 p[6], c[6];
    float a[6];
    for (int i = 0; i < 6; ++i) {
        p[i] = corner_world[i] - origin;
        c[i] = cross(dir, p[i]);
        a[i] = dot(p[i], dir);
    }
    // edge(i, j) = dot(c_i, p_j); the bottom's (0-1, 1-2, 2-0), the top's, the verticals (i, i+3).
    float eb0 = dot(c[0], p[1]), eb1 = dot(c[1], p[2]), eb2 = dot(c[2], p[0]);
    float et0 = dot(c[3], p[4]), et1 = dot(c[4], p[5]), et2 = dot(c[5], p[3]);
    float ev0 = dot(c[0], p[3]), ev1 = dot(c[1], p[4]), ev2 = dot(c[2], p[5]);
    // The top (3, 4, 5): in (the walk's check) or out.
    float den_top = et0 + et1 + et2;
    bool top = abs(den_top) >= 1e-30;
    w_top = top ? vec3(et1, et2, et0) / den_top : vec3(0.0);
    float t_top = t_entry + (a[3] * w_top.x + a[4] * w_top.y + a[5] * w_top.z) * inv_dd;
    g_top_entering = top && den_top * orient < 0.0 && t_top >= t_entry - 1e-5 * abs(t_entry);
    top_entry = g_top_entering && in_triangle(w_top, slack);
    g_top_entry_t = t_top;
    keep_exit(et1, et2, et0, a[3], a[4], a[5], inv_dd, t_entry, 0, false, t_min, entry_face, t_back, orient, slack,
              best, key);
    // The bottom (0, 2, 1): edges 2-1, 1-0, 0-2.
    keep_exit(-eb1, -eb0, -eb2, a[0], a[2], a[1], inv_dd, t_entry, 1, false, t_min, entry_face, t_back, orient, slack,
              best, key);
    for (int e = 0; e < 3; ++e) {
        // The side quad a b b' a' (' = top), split along a-b' (from_a) or b-a'.
        int a_ = e, b_ = (e + 1) % 3;
        bool f = from_a[e];
        float e_ab = e == 0 ? eb0 : (e == 1 ? eb1 : eb2);           // edge(a, b)
        float e_tt = -(e == 0 ? et0 : (e == 1 ? et1 : et2));        // edge(b', a')
        float v_a = e == 0 ? ev0 : (e == 1 ? ev1 : ev2);            // edge(a, a')
        float v_b = e == 0 ? ev1 : (e == 1 ? ev2 : ev0);            // edge(b, b')
        // The diagonal: edge(a, b') (from_a) or edge(b, a').
        float diag = dot(f ? c[a_] : c[b_], f ? p[b_ + 3] : p[a_ + 3]);
        float aa = a[a_], ab = a[b_], aat = a[a_ + 3], abt = a[b_ + 3];
        // from_a: (a, b, b') and (a, b', a'); else (a, b, a') and (b, b', a').
        // (a, b, b'): edge(b, b'), edge(b', a) = -diag, edge(a, b); (a, b, a'): edge(b, a') = diag,
        // edge(a', a) = -v_a, edge(a, b).
        keep_exit(f ? v_b : diag, f ? -diag : -v_a, e_ab, aa, ab, f ? abt : aat, inv_dd, t_entry, 2 + e, false, t_min,
                  entry_face, t_back, orient, slack, best, key);
        // (a, b', a'): edge(b', a'), edge(a', a) = -v_a, edge(a, b') = diag;
        // (b, b', a'): edge(b', a'), edge(a', b) = -diag, edge(b, b') = v_b.
        keep_exit(e_tt, f ? -v_a : -diag, f ? diag : v_b, f ? aa : ab, abt, aat, inv_dd, t_entry, 2 + e, true, t_min,
                  entry_face, t_back, orient, slack, best, key);
    }
    // The nearest's texture coordinates and place along its edge, once (for each of the eight
    // candidates they cost a quarter of the test). Its corners, as keep_exit's calls above took
    // them: top (3, 4, 5), bottom (0, 2, 1); side e's first triangle (a, b, b') or (a, b, a'),
    // its second (a, b', a') or (b, b', a'), by from_a[e]. (Selects: see corner_tex's note in
    // entry_point, prism.frag.)
    vec3 w = best.w;
    int e = clamp(best.face - 2, 0, 2);
    bool f = e == 0 ? from_a[0] : (e == 1 ? from_a[1] : from_a[2]);
    vec3 xa = e == 0 ? corner_tex[0] : (e == 1 ? corner_tex[1] : corner_tex[2]);
    vec3 xb = e == 0 ? corner_tex[1] : (e == 1 ? corner_tex[2] : corner_tex[0]);
    vec3 xat = e == 0 ? corner_tex[3] : (e == 1 ? corner_tex[4] : corner_tex[5]);
    vec3 xbt = e == 0 ? corner_tex[4] : (e == 1 ? corner_tex[5] : corner_tex[3]);
    bool s = best.second;
    vec3 x0 = best.face == 0 ? corner_tex[3] : (best.face == 1 ? corner_tex[0] : (s && !f ? xb : xa));
    vec3 x1 = best.face == 0 ? corner_tex[4] : (best.face == 1 ? corner_tex[2] : (s ? xbt : xb));
    vec3 x2 = best.face == 0 ? corner_tex[5] : (best.face == 1 ? corner_tex[1] : (s || !f ? xat : xbt));
    // The weight of the corners at the edge's second end (b, b').
    float lambda = s ? (f ? 0.0 : w.x) + w.y : w.y + (f ? w.z : 0.0);
    return ExitFace(best.t, x0 * w.x + x1 * w.y + x2 * w.z, best.face, best.face >= 2 ? lambda : 0.0, best.inside);
}

// The exact exit (--prism-exit exact) of the ray eye + t * dir, t = 1 at a point on the prism's
// surface: the nearest crossing beyond t = 1. Returns false when none is found (the ray grazes an
// edge); then t = 1 and tex = entry_tex.
bool prism_exit(vec3 dir, vec3 entry_tex, bool from_a[3], out float t_exit, out vec3 tex_exit)
{
    bool top_entry;
    vec3 w_top;
    ExitFace ex = nearest_exit(u_eye.xyz, dir, 1.0 + 1e-5, from_a, 1e-5, 0.0, 1.0, -1, top_entry, w_top);
    bool found = ex.inside; // the exact exit has no planes-only fallback
    t_exit = found ? ex.t : 1.0;
    tex_exit = found ? ex.tex : entry_tex;
    return found;
}
