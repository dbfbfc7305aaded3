// Prism silhouettes, stage 2: extrude each triangle into its shell prism and emit only the
// faces that face the eye. Each face is planar (sides are split into two triangles), and a ray
// enters the shell through exactly one front face of one prism, so nothing is shaded twice.
// Output per vertex: 4 (position) + 3 (world) + 3 (texture coordinate) scalars; at most 18
// vertices (top 3 + bottom 3 + three sides of 4) — geometry-shader cost grows with both.
#include "common/shared.h"
#include "prism/shell.glsl"

layout(triangles) in;
layout(triangle_strip, max_vertices = 18) out;

in vec3 g_world[];
in vec3 g_normal[];
in vec2 g_uv[];
flat in uint g_weld[];

out vec3 v_world; // world position on the shell face
out vec3 v_tex;   // (u, v, height) there


bool faces_eye(int a, int b, int c)
{
    vec3 n = cross(corner_world[b] - corner_world[a], corner_world[c] - corner_world[a]);
    return dot(n, u_eye.xyz - corner_world[a]) > 0.0;
}

void put(int i)
{
    v_world = corner_world[i];
    v_tex = corner_tex[i];

    gl_Position = u_view_proj * vec4(corner_world[i], 1.0);
    gl_PrimitiveID = gl_PrimitiveIDIn;
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

void main()
{
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
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        // Quad a0 b0 b1 a1, outward; split along a0-b1 or b0-a1 (shell.glsl).
        if (diagonal_from_a(g_weld[a], g_weld[b])) {
            triangle(a, b, b + 3);
            triangle(a, b + 3, a + 3);
        } else {
            triangle(a, b, a + 3);
            triangle(b, b + 3, a + 3);
        }
    }
}
