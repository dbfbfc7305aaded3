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

// The six corners of the prism being processed: 0..2 bottom (h = 0), 3..5 top (h = 1), world
// space and texture space (u, v, height). Filled by the stage before calling prism_exit().
vec3 corner_world[6];
vec3 corner_tex[6];

// Ray eye + t * dir against triangle (a, b, c) (Moller-Trumbore). Keeps the nearest hit with
// t > t_min: its parameter and texture coordinate (barycentric mix of the corners').
void exit_candidate(int a, int b, int c, vec3 dir, float t_min, inout float t_best, inout vec3 tex_best)
{
    vec3 e1 = corner_world[b] - corner_world[a];
    vec3 e2 = corner_world[c] - corner_world[a];
    vec3 p = cross(dir, e2);
    float det = dot(e1, p);
    if (abs(det) < 1e-30) return;
    float inv = 1.0 / det;
    vec3 s = u_eye.xyz - corner_world[a];
    float bu = dot(s, p) * inv;
    vec3 q = cross(s, e1);
    float bv = dot(dir, q) * inv;
    const float slack = 1e-5; // the exit may lie exactly on an edge between two triangles
    if (bu < -slack || bv < -slack || bu + bv > 1.0 + slack) return;
    float t = dot(e2, q) * inv;
    if (t > t_min && t < t_best) {
        t_best = t;
        tex_best = corner_tex[a] * (1.0 - bu - bv) + corner_tex[b] * bu + corner_tex[c] * bv;
    }
}

// Where the ray eye + t * dir (t = 1 at a point on the prism's surface) leaves the prism: the
// nearest of its eight triangles beyond t = 1 (all eight: a twisted side can make the prism
// non-convex). `from_a[e]`: diagonal_from_a() of edge e. Returns false when no face is found
// (the ray grazes an edge); then t = 1 and tex = entry_tex.
bool prism_exit(vec3 dir, vec3 entry_tex, bool from_a[3], out float t_exit, out vec3 tex_exit)
{
    t_exit = 1e30;
    tex_exit = entry_tex;
    float t_min = 1.0 + 1e-5;
    exit_candidate(3, 4, 5, dir, t_min, t_exit, tex_exit);
    exit_candidate(0, 2, 1, dir, t_min, t_exit, tex_exit);
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        if (from_a[e]) {
            exit_candidate(a, b, b + 3, dir, t_min, t_exit, tex_exit);
            exit_candidate(a, b + 3, a + 3, dir, t_min, t_exit, tex_exit);
        } else {
            exit_candidate(a, b, a + 3, dir, t_min, t_exit, tex_exit);
            exit_candidate(b, b + 3, a + 3, dir, t_min, t_exit, tex_exit);
        }
    }
    if (t_exit > 1e29) {
        t_exit = 1.0;
        return false;
    }
    return true;
}
