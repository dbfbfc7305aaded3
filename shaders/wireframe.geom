// Wireframe overlays, drawn after prism.vert (the prism's own shell vertices): the edges of one
// base triangle as line strips, or (variant PR_OVERLAY_SHELL) the edges of its shell prism: bottom
// and top triangles, the three vertical edges and the diagonal that splits each side quad —
// corners from shell_corner() (or, for the prism walk, load_walk_prism() with its tight tops) and
// the diagonal from diagonal_from_a(), exactly as prism.geom builds the faces it rasterizes.
// Edges shared by neighbouring triangles are drawn twice (same pixels, same colour).
#include "common/shared.h"
#include "prism/shell.glsl"

layout(triangles) in;
#ifdef PR_OVERLAY_SHELL
layout(line_strip, max_vertices = 20) out;
#else
layout(line_strip, max_vertices = 4) out;
#endif

in vec3 g_world[];
in vec3 g_normal[];
flat in uint g_weld[];

// Lines lie on the surfaces they outline; pull them towards the eye by a fraction of their
// distance so the depth test does not hide them behind the faces they bound (z fighting).
// Reversed depth (Camera::projection): clip z = A z_eye + B, w = -z_eye = D, so z / w =
// -A + B / D; adding k B to clip z gives -A + B / (D / (1 + k)): the point's depth at distance
// D / (1 + k), at every distance. The fraction grows as the triangle turns away from the eye: a
// face's distance changes across one pixel by about the pixel's angle times the tangent of the
// angle between the view and its normal, which a line must clear (a flat fraction of 5e-4 left
// the lines dashed on surfaces seen at a slant from nearby; found by an exploratory session).
// The angle counts up to 78 degrees: beyond, near an outline, a pull that large lets lines of
// the far side show through.
const float kDepthBias = 5e-4;
float g_bias = kDepthBias;

// The fraction for lines on triangle (a, b, c) (g_bias).
float slope_bias(vec3 a, vec3 b, vec3 c)
{
    vec3 n = cross(b - a, c - a);
    vec3 v = u_eye.xyz - (a + b + c) / 3.0;
    float cosine = abs(dot(n, v)) / max(length(n) * length(v), 1e-30);
    float pixel = 2.0 / (u_proj[1][1] * u_viewport.y); // a pixel's angle, radians
    return kDepthBias + 1.0 * pixel * sqrt(max(1.0 - cosine * cosine, 0.0)) / max(cosine, 0.2);
}

void put(vec3 world)
{
    vec4 clip = u_view_proj * vec4(world, 1.0);
    clip.z += g_bias * u_proj[3][2];
    gl_Position = clip;
    EmitVertex();
}

void segment(vec3 a, vec3 b)
{
    put(a);
    put(b);
    EndPrimitive();
}

void loop3(vec3 a, vec3 b, vec3 c)
{
    put(a);
    put(b);
    put(c);
    put(a);
    EndPrimitive();
}

void main()
{
    g_bias = slope_bias(g_world[0], g_world[1], g_world[2]);
#ifdef PR_OVERLAY_SHELL
#ifdef PR_PRISM_WALK
    bool from_a[3]; // the walk's prism, tight top included (shell.glsl)
    load_walk_prism(uint(gl_PrimitiveIDIn), from_a);
#else
    for (int i = 0; i < 3; ++i) {
        corner_world[i] = shell_corner(g_world[i], g_normal[i], 0.0);
        corner_world[i + 3] = shell_corner(g_world[i], g_normal[i], 1.0);
    }
#endif
    loop3(corner_world[0], corner_world[1], corner_world[2]);
    loop3(corner_world[3], corner_world[4], corner_world[5]);
    for (int e = 0; e < 3; ++e) {
        int a = e, b = (e + 1) % 3;
        segment(corner_world[a], corner_world[a + 3]);
        if (diagonal_from_a(g_weld[a], g_weld[b]))
            segment(corner_world[a], corner_world[b + 3]);
        else
            segment(corner_world[b], corner_world[a + 3]);
    }
#else
    loop3(g_world[0], g_world[1], g_world[2]);
#endif
}
