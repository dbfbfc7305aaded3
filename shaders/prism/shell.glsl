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

// Ray eye + t * dir against the prism's triangle (a, b, c) (Moller-Trumbore), grown by `slack`
// in barycentric units: false when they do not meet; else the parameter t, the barycentric
// weights of a, b, c, and det, whose sign tells the side: det < 0 where the ray goes out through
// a face wound counter-clockwise seen from outside.
bool ray_triangle(int a, int b, int c, vec3 dir, float slack, out float t, out vec3 w, out float det)
{
    t = 0.0;
    w = vec3(0.0);
    vec3 e1 = corner_world[b] - corner_world[a];
    vec3 e2 = corner_world[c] - corner_world[a];
    vec3 p = cross(dir, e2);
    det = dot(e1, p);
    if (abs(det) < 1e-30) return false;
    float inv = 1.0 / det;
    vec3 s = u_eye.xyz - corner_world[a];
    float bu = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    float bv = dot(dir, q) * inv;
    if (bu < -slack || bv < -slack || bu + bv > 1.0 + slack) return false;
    t = dot(e2, q) * inv;
    w = vec3(1.0 - bu - bv, bu, bv);
    return true;
}

// +1 when the walk's current prism (load_walk_prism) winds counter-clockwise seen from outside.
// Judged on the base triangle (height `midlevel`), which is never folded: a bottom or top cap
// offset by more than the surface's radius of curvature may be (inward shells at sharp convex
// edges, outward ones in tight creases).
float walk_orientation;

// ---- The prism walk's buffers ------------------------------------------------------------------
layout(std430, binding = PR_SSBO_INDICES) readonly buffer Indices { uint b_indices[]; };
#ifdef PR_PRISM_WALK
// Per vertex (src/render/renderer.cpp, make_shell_corners): the shell's bottom corner and u,
// depth * N and v, and the height of the top (shell_bounds.hpp) with the welded id.
struct ShellVertex {
    vec4 bottom_u;
    vec4 dn_v;
    vec4 top_weld;
};
layout(std430, binding = PR_SSBO_CORNERS) readonly buffer Corners { ShellVertex b_corners[]; };
layout(std430, binding = PR_SSBO_ADJACENCY) readonly buffer Adjacency { uint b_adjacency[]; };

// Fills corner_world/corner_tex with prism `prim` (top at the tight height, or at 1 with
// PR_PRISM_FULL_SHELL); returns its vertex indices and welded ids. The geometry shader and the
// walk both build their prisms here, so they agree to the bit.
void load_walk_prism(uint prim, out uint index[3], out uint weld[3])
{
    vec3 base[3], up = vec3(0.0);
    for (int i = 0; i < 3; ++i) {
        index[i] = b_indices[3u * prim + uint(i)];
        ShellVertex c = b_corners[index[i]];
#ifdef PR_PRISM_FULL_SHELL
        float top = 1.0;
#else
        float top = c.top_weld.x;
#endif
        corner_world[i] = c.bottom_u.xyz;
        corner_world[i + 3] = c.bottom_u.xyz + top * c.dn_v.xyz;
        corner_tex[i] = vec3(c.bottom_u.w, c.dn_v.w, 0.0);
        corner_tex[i + 3] = vec3(c.bottom_u.w, c.dn_v.w, top);
        weld[i] = floatBitsToUint(c.top_weld.y);
        base[i] = c.bottom_u.xyz + u_displace.y * c.dn_v.xyz;
        up += c.dn_v.xyz;
    }
    walk_orientation = dot(cross(base[1] - base[0], base[2] - base[0]), up) < 0.0 ? -1.0 : 1.0;
}
#endif

// ---- Where a ray leaves a prism -----------------------------------------------------------------
// The nearest of the prism's eight triangles (all eight: a twisted side can make the prism
// non-convex) that the ray eye + t * dir crosses beyond t_min. Face: 0 top, 1 bottom, 2 + e the
// side of edge e, with `lambda` the crossing's position along that edge (0 at corner e, 1 at
// corner e + 1); -1: none.
struct ExitFace {
    float t;
    vec3 tex;
    int face;
    float lambda;
};

// `orient`: 0 counts every crossing; +1 only those the ray goes *out* through, for a prism whose
// faces wind counter-clockwise seen from outside, -1 the same for one turned inside out by
// normals that oppose the winding (the walk: walk_orientation), so the face of entry needs no
// epsilon.
void exit_candidate(int a, int b, int c, int face, vec3 dir, float t_min, float orient, float slack,
                    inout ExitFace best)
{
    float t, det;
    vec3 w;
    if (!ray_triangle(a, b, c, dir, slack, t, w, det) || det * orient > 0.0) return;
    if (t > t_min && t < best.t) {
        best.t = t;
        best.tex = corner_tex[a] * w.x + corner_tex[b] * w.y + corner_tex[c] * w.z;
        best.face = face;
        // Weight of the edge's second corner (bottom or top), for the side faces.
        int second = (face + 2) % 3;
        best.lambda = (a % 3 == second ? w.x : 0.0) + (b % 3 == second ? w.y : 0.0) + (c % 3 == second ? w.z : 0.0);
    }
}

// `from_a[e]`: diagonal_from_a() of edge e. `slack` grows the faces (ray_triangle): 1e-5 lets an
// exit lie exactly on an edge between two triangles; a huge one compares planes only, which on a
// convex prism still finds the way out of a ray that comes in just outside it (the rasterizer
// snaps vertices to its subpixel grid, so a fragment on an edge may lie a little outside its face).
ExitFace nearest_exit(vec3 dir, float t_min, bool from_a[3], float slack, float orient)
{
    ExitFace best = ExitFace(1e30, vec3(0.0), -1, 0.0);
    exit_candidate(3, 4, 5, 0, dir, t_min, orient, slack, best);
    exit_candidate(0, 2, 1, 1, dir, t_min, orient, slack, best);
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        if (from_a[e]) {
            exit_candidate(a, b, b + 3, 2 + e, dir, t_min, orient, slack, best);
            exit_candidate(a, b + 3, a + 3, 2 + e, dir, t_min, orient, slack, best);
        } else {
            exit_candidate(a, b, a + 3, 2 + e, dir, t_min, orient, slack, best);
            exit_candidate(b, b + 3, a + 3, 2 + e, dir, t_min, orient, slack, best);
        }
    }
    return best;
}

// The exact exit (--prism-exit exact) of the ray eye + t * dir, t = 1 at a point on the prism's
// surface: the nearest crossing beyond t = 1. Returns false when none is found (the ray grazes an
// edge); then t = 1 and tex = entry_tex.
bool prism_exit(vec3 dir, vec3 entry_tex, bool from_a[3], out float t_exit, out vec3 tex_exit)
{
    ExitFace ex = nearest_exit(dir, 1.0 + 1e-5, from_a, 1e-5, 0.0);
    t_exit = ex.face < 0 ? 1.0 : ex.t;
    tex_exit = ex.face < 0 ? entry_tex : ex.tex;
    return ex.face >= 0;
}
