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

// Ray eye + t * dir against the plane of triangle (p0, p1, p2) (Moller-Trumbore): false when they
// are parallel; else the parameter t, the barycentric weights w of p0, p1, p2 (inside the
// triangle when none is negative), and det, whose sign tells the side: det < 0 where the ray
// goes out through a face wound counter-clockwise seen from outside.
bool ray_plane(vec3 p0, vec3 p1, vec3 p2, vec3 dir, out float t, out vec3 w, out float det)
{
    t = 0.0;
    w = vec3(0.0);
    vec3 e1 = p1 - p0;
    vec3 e2 = p2 - p0;
    vec3 p = cross(dir, e2);
    det = dot(e1, p);
    if (abs(det) < 1e-30) return false;
    float inv = 1.0 / det;
    vec3 s = u_eye.xyz - p0;
    float bu = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    float bv = dot(dir, q) * inv;
    t = dot(e2, q) * inv;
    w = vec3(1.0 - bu - bv, bu, bv);
    return true;
}

// Whether weights w from ray_plane() lie in the triangle grown by `slack` (barycentric units).
bool in_triangle(vec3 w, float slack)
{
    return w.y >= -slack && w.z >= -slack && w.y + w.z <= 1.0 + slack;
}

// +1 when the walk's current prism (load_walk_prism) winds counter-clockwise seen from outside.
// Judged on the base triangle (height `midlevel`), which is never folded: a bottom or top cap
// offset by more than the surface's radius of curvature may be (inward shells at sharp convex
// edges, outward ones in tight creases).
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
struct ShellVertex {
    vec4 bottom_u;
    vec4 n_v;
    vec4 top_weld;
};
layout(binding = PR_TEX_CORNERS) uniform usamplerBuffer t_corners;
layout(binding = PR_TEX_ADJACENCY) uniform usamplerBuffer t_adjacency;

ShellVertex shell_corners(uint vertex)
{
    int o = int(3u * vertex);
    return ShellVertex(uintBitsToFloat(texelFetch(t_corners, o)), uintBitsToFloat(texelFetch(t_corners, o + 1)),
                       uintBitsToFloat(texelFetch(t_corners, o + 2)));
}

// The height of vertex c's top (tight, or 1 with PR_PRISM_FULL_SHELL) and its corner there. Every
// stage that builds a top corner calls this (`precise`: no stage may fuse it differently), so
// entry faces and exits agree to the bit.
float shell_top_height(ShellVertex c)
{
#ifdef PR_PRISM_FULL_SHELL
    return 1.0;
#else
    return c.top_weld.x;
#endif
}

vec3 shell_top_corner(ShellVertex c, float top)
{
    precise vec3 corner = c.bottom_u.xyz + top * (u_displace.x * c.n_v.xyz);
    return corner;
}

// The triangles across the edges of triangle `prim` (edge e from corner e to e + 1), each as
// prism << 2 | its edge; 0xffffffff where there is none.
uvec3 triangle_neighbours(uint prim)
{
    return texelFetch(t_adjacency, int(prim)).xyz;
}

// The unit normals (world) of the current prism's vertices (load_walk_prism): the frame at a hit.
vec3 corner_normal[3];

// Fills corner_world/corner_tex/corner_normal with prism `prim` (top at the tight height, or at
// 1 with PR_PRISM_FULL_SHELL); returns its vertex indices and welded ids. The geometry shader and
// the walk both build their prisms here, so they agree to the bit.
void load_walk_prism(uint prim, out uint index[3], out uint weld[3])
{
    vec3 base[3], up = vec3(0.0);
    uvec3 tri = triangle_indices(prim);
    for (int i = 0; i < 3; ++i) {
        index[i] = tri[i];
        ShellVertex c = shell_corners(index[i]);
        float top = shell_top_height(c);
        vec3 dn = u_displace.x * c.n_v.xyz;
        corner_world[i] = c.bottom_u.xyz;
        corner_world[i + 3] = shell_top_corner(c, top);
        corner_tex[i] = vec3(c.bottom_u.w, c.n_v.w, 0.0);
        corner_tex[i + 3] = vec3(c.bottom_u.w, c.n_v.w, top);
        corner_normal[i] = c.n_v.xyz;
        weld[i] = floatBitsToUint(c.top_weld.y);
        base[i] = c.bottom_u.xyz + u_displace.y * dn;
        up += c.n_v.xyz;
    }
    walk_orientation = dot(cross(base[1] - base[0], base[2] - base[0]), up) < 0.0 ? -1.0 : 1.0;
}
#endif

// ---- Where a ray leaves a prism -----------------------------------------------------------------
// The nearest of the prism's eight triangles (all eight: a twisted side can make the prism
// non-convex) that the ray eye + t * dir crosses beyond t_min. Face: 0 top, 1 bottom, 2 + e the
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

// A crossing of triangle (p0, p1, p2) (texture coordinates x0, x1, x2) beyond t_min: `best` keeps
// the nearest within the triangle grown by `slack`, or while there is none, the nearest of the
// planes. (One key orders both: the bits of t > 0 as an unsigned integer, bit 31 set outside the
// triangle; one comparison and one set of selects per candidate, not two.) `second` picks the
// weights of the corners at the edge's second end (side faces: lambda). `orient`: 0 counts every
// crossing; +1 only those the ray goes *out* through, for a prism whose faces wind
// counter-clockwise seen from outside, -1 the same for one turned inside out by normals that
// oppose the winding (the walk: walk_orientation), so the face of entry needs no epsilon.
// (From ray_plane()'s results: `crossed`, t, w, det.)
void keep_exit(bool crossed, float t, vec3 w, float det, vec3 x0, vec3 x1, vec3 x2, int face, vec3 second,
               float t_min, float orient, float slack, inout ExitFace best, inout uint best_key)
{
    if (!crossed || det * orient > 0.0 || !(t > t_min)) return;
    bool inside = in_triangle(w, slack);
    uint key = floatBitsToUint(t) | (inside ? 0u : 0x80000000u);
    if (key < best_key) {
        best = ExitFace(t, x0 * w.x + x1 * w.y + x2 * w.z, face, dot(w, second), inside);
        best_key = key;
    }
}

// keep_exit() of the ray's crossing of triangle (p0, p1, p2).
void exit_candidate(vec3 p0, vec3 p1, vec3 p2, vec3 x0, vec3 x1, vec3 x2, int face, vec3 second, vec3 dir,
                    float t_min, float orient, float slack, inout ExitFace best, inout uint best_key)
{
    float t, det;
    vec3 w;
    bool crossed = ray_plane(p0, p1, p2, dir, t, w, det);
    keep_exit(crossed, t, w, det, x0, x1, x2, face, second, t_min, orient, slack, best, best_key);
}

// `from_a[e]`: diagonal_from_a() of edge e. `slack` grows the faces (in_triangle): 1e-5 lets an
// exit lie exactly on an edge between two triangles. Where no triangle is crossed, the nearest of
// their planes, which on a convex prism still finds the way out of a ray that comes in just
// outside it (the rasterizer snaps vertices to its subpixel grid, so a fragment on an edge may lie
// a little outside its face). Each side's two triangles are chosen by selects, not branches
// (llvmpipe runs both arms of a branch): eight ray-plane tests in all. The same pass tells
// whether the ray goes *in* through the top cap (grown by `slack`) at t_entry, within
// 1e-5 * t_entry: `top_entry` (the walk, where it came from the top of the prism before), and
// gives the barycentric weights of the top's plane crossing, `w_top` (corners 3, 4, 5).
ExitFace nearest_exit(vec3 dir, float t_min, bool from_a[3], float slack, float orient, float t_entry,
                      out bool top_entry, out vec3 w_top)
{
    ExitFace best = ExitFace(1e30, vec3(0.0), -1, 0.0, false);
    uint key = 0xffffffffu;
    const vec3 none = vec3(0.0);
    // The top: in (the walk's check) or out.
    float t_top, det_top;
    bool top = ray_plane(corner_world[3], corner_world[4], corner_world[5], dir, t_top, w_top, det_top);
    top_entry = top && det_top * orient > 0.0 && in_triangle(w_top, slack) && abs(t_top - t_entry) <= 1e-5 * t_entry;
    keep_exit(top, t_top, w_top, det_top, corner_tex[3], corner_tex[4], corner_tex[5], 0, none, t_min, orient, slack,
              best, key);
    exit_candidate(corner_world[0], corner_world[2], corner_world[1], corner_tex[0], corner_tex[2], corner_tex[1],
                   1, none, dir, t_min, orient, slack, best, key);
    for (int e = 0; e < 3; ++e) {
        // The side quad a b b' a' (' = top), split along a-b' (from_a) or b-a'.
        int a = e, b = (e + 1) % 3;
        bool f = from_a[e];
        vec3 pa = corner_world[a], pb = corner_world[b], pat = corner_world[a + 3], pbt = corner_world[b + 3];
        vec3 xa = corner_tex[a], xb = corner_tex[b], xat = corner_tex[a + 3], xbt = corner_tex[b + 3];
        // a b b' or a b a'; then a b' a' or b b' a'.
        exit_candidate(pa, pb, f ? pbt : pat, xa, xb, f ? xbt : xat, 2 + e, vec3(0.0, 1.0, f ? 1.0 : 0.0), dir,
                       t_min, orient, slack, best, key);
        exit_candidate(f ? pa : pb, pbt, pat, f ? xa : xb, xbt, xat, 2 + e, vec3(f ? 0.0 : 1.0, 1.0, 0.0), dir,
                       t_min, orient, slack, best, key);
    }
    return best;
}

// The exact exit (--prism-exit exact) of the ray eye + t * dir, t = 1 at a point on the prism's
// surface: the nearest crossing beyond t = 1. Returns false when none is found (the ray grazes an
// edge); then t = 1 and tex = entry_tex.
bool prism_exit(vec3 dir, vec3 entry_tex, bool from_a[3], out float t_exit, out vec3 tex_exit)
{
    bool top_entry;
    vec3 w_top;
    ExitFace ex = nearest_exit(dir, 1.0 + 1e-5, from_a, 1e-5, 0.0, 1.0, top_entry, w_top);
    bool found = ex.inside; // the exact exit has no planes-only fallback
    t_exit = found ? ex.t : 1.0;
    tex_exit = found ? ex.tex : entry_tex;
    return found;
}
