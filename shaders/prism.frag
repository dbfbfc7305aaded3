// Prism silhouettes, stage 3: march the view ray through this fragment's prism, from where it
// enters (this face) to where it leaves the prism, found exactly per fragment by intersecting
// the ray with the prism's eight planar triangles (the same ones the geometry shader emits,
// rebuilt from the mesh buffers), or, with PR_PRISM_EXIT_VERTEX, from per-vertex distances to
// the prism's planes in texture space, interpolated (the seed's draft; prism.geom). A ray that leaves without meeting the height field is
// discarded: that is what makes the outline true. A hit writes its real depth.
#define PR_HIT_EPSILON 1e-4
#include "common/shared.h"
#include "common/height.glsl"
#include "common/lighting.glsl"
#include "common/counters.glsl"
#include "march/relief.glsl"
// (The embedder expands each file once, whatever the #if around it: include unconditionally.)
#include "march/cone.glsl"
#include "march/maxmip.glsl"
#include "common/shadow.glsl"
#include "prism/shell.glsl"

in vec3 v_world;
in vec3 v_tex;
#ifdef PR_PRISM_EXIT_VERTEX
in vec3 v_dir_tex;
in vec4 v_dist_sides;
in float v_dist_top;
#endif

layout(location = 0) out vec4 o_color;
// The hit is never in front of the face that was rasterized: depth only grows, which keeps
// early depth rejection against what is already drawn.
layout(depth_greater) out float gl_FragDepth;

layout(std430, binding = PR_SSBO_VERTICES) readonly buffer Vertices { float b_vertices[]; };
layout(std430, binding = PR_SSBO_INDICES) readonly buffer Indices { uint b_indices[]; };

struct BaseVertex {
    vec3 position;
    vec3 normal;
    vec2 uv;
    vec3 tangent;
    vec3 bitangent;
    uint weld;
};

BaseVertex base_vertex(uint index)
{
    uint o = index * 16u; // MeshVertex: 16 scalars (src/mesh/mesh.hpp)
    BaseVertex v;
    v.position = vec3(b_vertices[o], b_vertices[o + 1u], b_vertices[o + 2u]);
    v.normal = vec3(b_vertices[o + 3u], b_vertices[o + 4u], b_vertices[o + 5u]);
    v.uv = vec2(b_vertices[o + 6u], b_vertices[o + 7u]);
    v.tangent = vec3(b_vertices[o + 8u], b_vertices[o + 9u], b_vertices[o + 10u]);
    v.bitangent = vec3(b_vertices[o + 12u], b_vertices[o + 13u], b_vertices[o + 14u]);
    v.weld = floatBitsToUint(b_vertices[o + 15u]);
    return v;
}

void main()
{
    uint prim = uint(gl_PrimitiveID);
    BaseVertex bv[3];
    bool from_a[3];
    for (int i = 0; i < 3; ++i) {
        bv[i] = base_vertex(b_indices[3u * prim + uint(i)]);
        vec3 world, n;
        shell_vertex(bv[i].position, bv[i].normal, world, n);
        corner_world[i] = shell_corner(world, n, 0.0);
        corner_world[i + 3] = shell_corner(world, n, 1.0);
        corner_tex[i] = vec3(bv[i].uv, 0.0);
        corner_tex[i + 3] = vec3(bv[i].uv, 1.0);
    }
    for (int e = 0; e < 3; ++e) from_a[e] = diagonal_from_a(bv[e].weld, bv[(e + 1) % 3].weld);

    // The ray is eye + t * dir with t = 1 at this fragment (the entry).
    vec3 dir = v_world - u_eye.xyz;
    float t_exit;
    vec3 tex_exit;
#ifdef PR_PRISM_EXIT_VERTEX
    // Interpolated distances to the texture-space prism's planes (prism.geom): the nearest is
    // the exit. Moving lambda along v_dir_tex moves lambda * dir in the world (same frame).
    float lambda = max(min(min(min(v_dist_sides.x, v_dist_sides.y), min(v_dist_sides.z, v_dist_sides.w)),
                           v_dist_top), 0.0);
    t_exit = 1.0 + lambda;
    tex_exit = v_tex + lambda * v_dir_tex;
#else
    prism_exit(dir, v_tex, from_a, t_exit, tex_exit);
#endif

    // March from entry to exit in texture space, linear in t between them. Steps: --steps per
    // full height range (as the base-surface techniques, so equal --steps means equal step
    // length), and at least one sample per two texels along the uv path, so grazing rays near
    // the silhouette do not step over bumps.
    vec3 seg = tex_exit - v_tex;
    vec2 texels = seg.xy * vec2(textureSize(s_height, 0));
    int steps = int(ceil(float(u_march.x) * abs(seg.z) + 0.5 * length(texels)));
    steps = clamp(steps, 1, 4 * max(u_march.x, 1) + 64);
    // Geometry (the outline and the depth) uses height level 0, as the reference does
    // (contract); filtering it by mip level would move the surface, not just smooth its look.
    UvGrad g = UvGrad(vec2(0.0), vec2(0.0));
    MarchRay ray = MarchRay(v_tex, seg, 1.0, steps);
#if PR_MARCHER == PR_MARCH_CONE || PR_MARCHER == PR_MARCH_RELAXED_CONE
    Bracket br = march_cone(ray);
#elif PR_MARCHER == PR_MARCH_MAX_MIP
    Bracket br = march_max_mip(ray);
#else
    Bracket br = march_linear(ray, g);
#endif
    if (!br.hit) {
        count_fragment();
        discard;
    }
#if PR_MARCHER == PR_MARCH_LINEAR
    float s = interpolate_bracket(br);
#elif PR_MARCHER == PR_MARCH_CONE || PR_MARCHER == PR_MARCH_RELAXED_CONE
    float s = refine_binary_secant(ray, br, cone_refine_steps(ray, br, u_march.y), g);
#elif PR_MARCHER == PR_MARCH_MAX_MIP
    float s = br.t_below; // exact: no refinement
#else
    float s = refine_binary(ray, br, u_march.y, g);
#endif
    vec3 tex = v_tex + s * seg;
    vec3 hit = u_eye.xyz + mix(1.0, t_exit, s) * dir;

    // Frame at the hit: barycentrics of its uv in the base triangle's uv triangle.
    vec2 d1 = bv[1].uv - bv[0].uv, d2 = bv[2].uv - bv[0].uv, dp = tex.xy - bv[0].uv;
    float den = d1.x * d2.y - d1.y * d2.x;
    vec3 w = abs(den) > 1e-20
        ? vec3(0.0, (dp.x * d2.y - dp.y * d2.x) / den, (d1.x * dp.y - d1.y * dp.x) / den)
        : vec3(0.0, 1.0 / 3.0, 1.0 / 3.0);
    w.x = 1.0 - w.y - w.z;
    vec3 n = normalize(mat3(u_normal_matrix) * (bv[0].normal * w.x + bv[1].normal * w.y + bv[2].normal * w.z));
    vec3 t_axis = mat3(u_model) * (bv[0].tangent * w.x + bv[1].tangent * w.y + bv[2].tangent * w.z);
    vec3 b_axis = mat3(u_model) * (bv[0].bitangent * w.x + bv[1].bitangent * w.y + bv[2].bitangent * w.z);
    vec3 shading_n = height_normal(tex.xy, t_axis, b_axis, n, u_displace.x);
    vec3 light_dir = normalize(u_light_dir.xyz);
    float visibility = 1.0;
#ifdef PR_SHADOWS
    if (dot(shading_n, light_dir) > 0.0)
        visibility = light_visibility(tex,
                                      light_in_texture_space(t_axis, b_axis, n, u_displace.x, light_dir), g);
#endif
    count_fragment();
    o_color = vec4(shade_blinn_phong(albedo_at(tex.xy, g), shading_n, light_dir, -normalize(dir), visibility), 1.0);
    vec4 clip = u_view_proj * vec4(hit, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w * 0.5 + 0.5, gl_FragCoord.z, 1.0);
}
