// Prism silhouettes, stage 2: extrude each triangle into its shell prism and emit only the
// faces that face the eye. Each face is planar (sides are split into two triangles), and a ray
// enters each prism through exactly one front face, so nothing is shaded twice. The walk
// (PR_PRISM_WALK) draws its caps by prism_caps.vert and the rest of the shell's outside here, from
// listed prisms (PR_PRISM_LISTED).
// Output per vertex: 4 (position) + 3 (world) + 3 (texture coordinate) scalars (+ 8 for the
// per-vertex exit variant); at most 18 vertices (top 3 + bottom 3 + three sides of 4) — geometry-shader cost grows with both.
#include "common/shared.h"
#include "prism/shell.glsl"

#ifdef PR_PRISM_LISTED
// The walk draws its caps without this shader (prism_caps.vert). This one then gets one point per
// listed prism, its entry in PR_TEX_PRISM_LIST (picked on the CPU, src/render/renderer.cpp,
// walk_triangles): the prism's number, with bit 31 set where its shell folds, whose other front
// faces it emits, else a prism with an edge without a neighbour (open meshes), whose wall there
// it emits; in the second pass over a torn mesh, a prism whose bottom may cover a marked tile.
layout(points) in;
flat in int g_list_index[]; // prism_caps.vert: gl_VertexID, so a draw may start anywhere in the list
layout(binding = PR_TEX_PRISM_LIST) uniform usamplerBuffer t_prism_list;
#else
layout(triangles) in;

in vec3 g_world[];
in vec3 g_normal[];
in vec2 g_uv[];
flat in uint g_weld[];
in vec3 g_tangent[];
in vec3 g_bitangent[];
#endif
layout(triangle_strip, max_vertices = 18) out;

// The prism being emitted: its number (the fragment shader's gl_PrimitiveID) and its sides'
// diagonals (diagonal_from_a).
int prism_id;
bool prism_from_a[3];

out vec3 v_world; // world position on the shell face
out vec3 v_tex;   // (u, v, height) there
#ifdef PR_PRISM_EXIT_VERTEX
// The seed's draft, done in texture space, where the prism is straight (the uv triangle times
// [0, 1]: five planes): the view direction in this corner's metric tangent frame, and the
// distances along it to the planes the ray leaves through (large for the others). A plane
// through the corner gets distance 0 there, so the interpolated distances vanish where they
// should; the fragment takes their minimum as its exit.
out vec3 v_dir_tex;
out vec4 v_dist_sides; // xyz: the three side planes (edges 0-1, 1-2, 2-0), w: the bottom
out float v_dist_top;

const float kFar = 1e6;

void exit_distances(int corner)
{
    int i = corner % 3;
    mat3 frame = mat3(g_tangent[i], g_bitangent[i], g_normal[i] * u_displace.x);
    vec3 d = abs(determinant(frame)) > 1e-30 ? inverse(frame) * (corner_world[corner] - u_eye.xyz)
                                             : vec3(0.0, 0.0, -1.0);
    vec3 p = corner_tex[corner];
    v_dir_tex = d;
    vec3 sides;
    for (int e = 0; e < 3; ++e) {
        vec2 a = g_uv[e], b = g_uv[(e + 1) % 3], c = g_uv[(e + 2) % 3];
        vec2 n = vec2(a.y - b.y, b.x - a.x); // normal of edge a-b, turned towards c
        if (dot(n, c - a) < 0.0) n = -n;
        float rate = dot(n, d.xy);           // < 0: the ray leaves through this side
        sides[e] = rate < 0.0 ? max(dot(n, p.xy - a), 0.0) / -rate : kFar;
    }
    float bottom = d.z < 0.0 ? p.z / -d.z : kFar;
    v_dist_sides = vec4(sides, bottom);
    v_dist_top = d.z > 0.0 ? (1.0 - p.z) / d.z : kFar;
}
#endif


bool faces_eye(int a, int b, int c)
{
    vec3 n = cross(corner_world[b] - corner_world[a], corner_world[c] - corner_world[a]);
    return dot(n, u_eye.xyz - corner_world[a]) > 0.0;
}

void put(int i)
{
    v_world = corner_world[i];
    v_tex = corner_tex[i];
#ifdef PR_PRISM_EXIT_VERTEX
    exit_distances(i);
#endif

    gl_Position = u_view_proj * vec4(corner_world[i], 1.0);
    gl_PrimitiveID = prism_id;
    EmitVertex();
}

void triangle(int a, int b, int c)
{
    if (!faces_eye(a, b, c)) return;
    put(a);
    put(b);
    put(c);
    EndPrimitive();
}

// The side quad of edge e (a0 b0 b1 a1, outward), split along a0-b1 or b0-a1 (shell.glsl).
// Called with constant e, so that every corner index is known at compile time (an index that is
// not would send the corner arrays to memory on llvmpipe).
void side(int e)
{
    int a = e, b = (e + 1) % 3;
    if (prism_from_a[a]) {
        triangle(a, b, b + 3);
        triangle(a, b + 3, a + 3);
    } else {
        triangle(a, b, a + 3);
        triangle(b, b + 3, a + 3);
    }
}

void main()
{
#ifdef PR_PRISM_LISTED
    uint entry = texelFetch(t_prism_list, g_list_index[0]).r;
    prism_id = int(entry & 0x3fffffffu);
    load_walk_prism(uint(prism_id), prism_from_a);
#ifdef PR_PRISM_INSIDE
    // The second pass over a torn mesh (prism.frag): the bottom the eye sees from inside the
    // object, where rays that went in through a tear come out into the far side's shell. The CPU
    // listed the prism for a marked tile and draws it with that tile as scissor, or (on a GPU,
    // Renderer::TearPass::Whole) every prism is listed.
    triangle(0, 2, 1);
#else
    // Where the shell folds (a cap offset past the surface's centre of curvature turns over:
    // inward shells at sharp convex edges, outward ones in tight creases), its outside is not
    // just the caps, and a walk through the folded prisms can lose its way: such prisms emit all
    // their front faces, as with the exact exit, and each of those fragments walks too. (Open
    // meshes have every bottom drawn by prism_caps.vert already.)
    bool folded = (entry & 0x80000000u) != 0u;
    if (folded && (u_march.w & PR_FLAG_OPEN_SHELL) == 0) triangle(0, 2, 1);
    uvec3 across = prism_across;
    // A folded prism's walls carry PR_PRISM_FOLDED_WALL_ID: on a torn mesh a ray that comes in
    // there may be under the surface, come out of a tear's crack, and the walk from there decides
    // it (prism.frag). (Not its bottom: rays come in there from the object's body.)
    if (folded) prism_id |= PR_PRISM_FOLDED_WALL_ID;
    if (folded || across.x == 0xffffffffu) side(0);
    if (folded || across.y == 0xffffffffu) side(1);
    if (folded || across.z == 0xffffffffu) side(2);
#endif
#else
    prism_id = gl_PrimitiveIDIn;
    for (int e = 0; e < 3; ++e) prism_from_a[e] = diagonal_from_a(g_weld[e], g_weld[(e + 1) % 3]);
    for (int i = 0; i < 3; ++i) {
        corner_world[i] = shell_corner(g_world[i], g_normal[i], 0.0);
        corner_world[i + 3] = shell_corner(g_world[i], g_normal[i], 1.0);
        corner_tex[i] = vec3(g_uv[i], 0.0);
        corner_tex[i + 3] = vec3(g_uv[i], 1.0);
    }
    triangle(3, 4, 5); // top cap, outward along +N (base triangles are counter-clockwise)
    // Bottom cap, outward along -N. Needed on open meshes (seen from below), and on closed ones
    // it also catches grazing rays whose exit falls numerically on an edge of the neighbour.
    triangle(0, 2, 1);
    side(0);
    side(1);
    side(2);
#endif // PR_PRISM_LISTED
}
