// One source of truth for attribute locations, bindings and uniform-block layouts, included by
// C++ (src/render) and by GLSL (shaders/). Blocks hold only vec4/ivec4/mat4 members so std140
// and the C++ layout agree without padding rules; a GL test checks every offset.
#pragma once
#ifdef __cplusplus
#include <glm/glm.hpp>
namespace pr::shader {
using vec4 = glm::vec4;
using ivec4 = glm::ivec4;
using mat4 = glm::mat4;
#define PR_UNIFORM_BLOCK(name, b) struct name
#else
#define PR_UNIFORM_BLOCK(name, b) layout(std140, binding = b) uniform name
#endif

// Vertex attribute locations (MeshVertex in src/mesh/mesh.hpp).
#define PR_ATTR_POSITION 0
#define PR_ATTR_NORMAL 1
#define PR_ATTR_UV 2
#define PR_ATTR_TANGENT 3
#define PR_ATTR_BITANGENT 4
#define PR_ATTR_WELD_ID 5

// Uniform-block, texture-unit and storage-buffer bindings.
#define PR_UBO_FRAME 0
#define PR_UBO_OBJECT 1
#define PR_TEX_HEIGHT 0
#define PR_TEX_COLOR 1
#define PR_TEX_CONE 2
// The prism's mesh data, read as buffer textures (texelFetch): llvmpipe fetches a texel for all
// lanes at once, where it loads a storage buffer one lane and one component at a time.
#define PR_TEX_VERTICES 3  // rgba32ui: the mesh's vertex buffer (MeshVertex, four texels each), prism only
#define PR_TEX_INDICES 4   // rgb32ui: its index buffer, one texel per triangle, prism only
#define PR_TEX_PRISMS 5    // rgba32ui, eight texels per triangle: its corners, tops, neighbours and flags
                           // (renderer.cpp, walk_triangles; shell.glsl, load_walk_prism); walk only
#define PR_TEX_CORNERS 6   // rgba32ui, three texels per vertex: vec4(bottom corner, u), vec4(unit N, v),
                           // vec4(top height, weld, 0, 0) (floats as bits); walk only
#define PR_TEX_PRISM_LIST 7 // r32ui: prisms drawn one point each (the folded ones; the second pass's, prism.geom)
#define PR_TEX_SHADOW_MAP 8 // depth32f array with comparison: the reference's shadow maps (its shadows, surface.frag)
#define PR_TEX_SHADOW_DEPTH 9 // the same maps' depths, unfiltered and not compared (a view; soft shadows' blocker search)
#define PR_TEX_PATCH 10 // r32f: the base-surface cone marchers' heights and ratios, read four at a time (march/cone.glsl)
// The reference's soft shadows: one shadow map per direction over the light's disc (hard: one).
#define PR_SHADOW_LAYERS 16
#define PR_SSBO_COUNTERS 0
// bench's histogram of height samples per fragment (counters.glsl sample_bin, renderer.hpp
// sample_bin_low): one bin a count below 2^13, then 2^10 bins an octave.
#define PR_EXACT_SAMPLE_BITS 13
#define PR_OCTAVE_SAMPLE_BITS 10
#define PR_IMAGE_TEARS 0    // r32ui, per pixel: 1 where a walk went into the object through a tear (prism walk, torn meshes)
#define PR_IMAGE_TEAR_TILES 1 // r32ui, the same per tile of PR_TEAR_TILE^2 pixels (the second pass's culling)
#define PR_TEAR_TILE 16
// A folded prism's walls are emitted (prism.geom) with this bit set in their gl_PrimitiveID: on a
// torn mesh a walk from there decides which side of the surface it starts on (prism.frag).
// Prism numbers stay below 2^30 (adjacency.hpp).
#define PR_PRISM_FOLDED_WALL_ID 0x40000000
// The walk's per-prism flags (renderer.cpp, walk_triangles): bit 0 the winding, bits 1..3 the
// sides' diagonals, and this one where a neighbour's texture frame differs from the prism's (a
// crease, a change of UV scale, a seam): the light's march in the hit's texture plane is no
// guide to the mesh there, and the walk answers (prism.frag).
#define PR_PRISM_FRAME_DIFFERS 16u
// The prism's hit tolerance: a sample at most this far above the surface (texture-space height,
// 0..1) counts as a hit, so that rays grazing a constant cap still hit despite rounding
// (march/linear.glsl). The walk from an eye starts at least twice as far from the surface
// (eye_prism.hpp).
#define PR_PRISM_HIT_EPSILON 1e-4

// Technique ids (PR_TECHNIQUE is defined to one of them per program variant).
#define PR_TECH_FLAT 0
#define PR_TECH_NORMAL 1
#define PR_TECH_OFFSET 2
#define PR_TECH_STEEP 3
#define PR_TECH_POM 4
#define PR_TECH_RELIEF 5
#define PR_TECH_REFERENCE 6 // tessellated displaced geometry, shaded like `normal`
#define PR_TECH_PRISM 7     // shell prisms from the geometry shader (prism.*)
#define PR_TECH_CONE 8      // cone step mapping (conservative cone map)
#define PR_TECH_RELAXED_CONE 9 // relaxed cone stepping

// Marchers (PR_MARCHER) inside the prism.
#define PR_MARCH_LINEAR 0 // linear search + secant (POM) interpolation
#define PR_MARCH_RELIEF 1 // linear search + binary refinement
#define PR_MARCH_CONE 2   // cone stepping (conservative cone map) + binary refinement
#define PR_MARCH_RELAXED_CONE 3 // relaxed cone stepping + binary refinement
#define PR_MARCH_MAX_MIP 4 // max-pyramid traversal + exact bilinear-patch intersection

// Self-shadowing (PR_SHADOWS, defined only when on).
#define PR_SHADOWS_NONE 0
#define PR_SHADOWS_HARD 1
#define PR_SHADOWS_SOFT 2

// Normal-from-height qualities (PR_NORMAL_QUALITY): the seed's three.
#define PR_NORMAL_GATHER 0
#define PR_NORMAL_CENTRAL 1
#define PR_NORMAL_SOBEL 2

// Bits of ObjectBlock.u_march.w.
// (1: the object has a colour texture, until the forty-second session: now PR_COLOR_TEXTURE, a
// compile-time choice, Renderer::program_for.)
#define PR_FLAG_OPEN_SHELL 2 // the mesh has boundary (or non-manifold) edges: the prism walk needs its walls and bottom

// Per frame: camera and light, world space.
PR_UNIFORM_BLOCK(FrameBlock, PR_UBO_FRAME)
{
    mat4 u_view;
    mat4 u_proj;
    mat4 u_view_proj;
    vec4 u_eye;       // xyz: eye position
    vec4 u_light_dir; // xyz: unit direction towards the light; w: tangent of its angular radius (soft shadows)
    vec4 u_viewport;  // width, height, 1/width, 1/height (pixels)
};

// Per object: transform, displacement and marching parameters.
PR_UNIFORM_BLOCK(ObjectBlock, PR_UBO_OBJECT)
{
    mat4 u_model;
    mat4 u_normal_matrix; // inverse transpose of the model's 3x3 part
    vec4 u_displace;      // x: depth (scene units), y: midlevel, z/w: height map size (texels)
    ivec4 u_march;        // x: linear steps over the full height range, y: binary steps,
                          // z: the walk's prism that holds the eye (-1: none), w: PR_FLAG_* bits
    vec4 u_material;      // ambient, diffuse, specular, shininess
    vec4 u_base_color;    // albedo when there is no colour texture (rgb), a unused
    vec4 u_eye_tex;       // xyz: the eye in that prism's texture space (u, v, height); w unused
    ivec4 u_walk;         // x: the most prisms a walk crosses before it gives up; yzw unused
    // The reference with shadows: each shadow map's projection of this object's frame (clip space,
    // depth 0..1 from the light; layer 0 alone with hard shadows), and x: how far a point is moved
    // off its triangle towards the light before the look-up, y: the depth bias (both about a
    // texel of the maps), z: the number of maps, w: the map being drawn (shadow_map.vert).
    mat4 u_shadow[PR_SHADOW_LAYERS];
    vec4 u_shadow_bias;
};

#ifdef __cplusplus
} // namespace pr::shader
#endif
