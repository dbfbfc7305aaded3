#pragma once
// Ground truth for comparisons: the contract's displaced surface as real triangles.
//   S(b) = P(b) + depth * (h(uv(b)) - midlevel) * N(b)
// with P, uv, N (not renormalized), T, B linear in the barycentrics b of each base triangle, and
// h the bilinear level-0 height (HeightField::sample, the GPU's GL_LINEAR formula).
// CPU only (no GL): the renderer uploads what this produces.
#include "core/camera.hpp"
#include "core/image.hpp"
#include "mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>

namespace pr {

struct ReferenceLevel {
    int level = 1;          // each base triangle is split into level^2 triangles
    int texel_level = 1;    // level at which every edge spans at most ~one height texel (half a
                            // texel on maps with sharp steps: kSharpStep)
    int pixel_level = 1;    // level at which every edge spans at most ~one pixel
    bool capped = false;    // lowered to stay within max_triangles
};

// How far the displaced surface may lie from the base surface along the normal: the larger end
// of depth * (h - midlevel) for h in [0, 1].
inline float displacement_reach(float depth, float midlevel)
{
    return depth * std::max(std::abs(midlevel), std::abs(1.0f - midlevel));
}

// A rise between neighbouring texels above this fraction of the heights the map spans (its
// highest less its lowest) makes a map sharp (builtin:boxes: 0.8; bricks 0.19, bumps 0.06 at
// 512²): the texel criterion then asks for edges of half a texel, since edges of one texel may
// sample a one-texel wall or spike only at its feet and draw it at half its height. (Of the
// whole height range until the forty-first session: a staircase in a sliver of a 16-bit map's
// range under a large --depth, walls a world unit tall, did not count. A map of a few levels,
// nearly flat, now does.)
inline constexpr float kSharpStep = 0.25f;

// What choose_reference_level reads of a height field (texel_steps): the largest rise between
// neighbouring texels (wrapped), and the heights it spans.
struct TexelSteps {
    float steepest = 0.0f;
    float span = 0.0f; // highest less lowest texel
};

// The finest level, automatic or given (--reference-level): one base triangle's vertices,
// (L + 1)(L + 2) / 2, stay well within 32-bit indices (8.4 million).
inline constexpr int kMaxReferenceLevel = 4096;

// The largest rise between neighbouring texels (wrapped) of a height field and the heights it
// spans, for choose_reference_level: taken once per field that objects share.
TexelSteps texel_steps(const HeightField& height);

// Chooses the uniform level: the coarser of the texel and pixel criteria (so edges are at most
// about one texel — half a texel on sharp maps — or one pixel, whichever is larger), then lowered until
// triangle_count * level^2 <= max_triangles (a scene's objects: cap_reference_levels). `transform` maps object to world (in double: the
// distances to the eye are taken in the object's frame, its translation taken out first). The pixel
// criterion measures the displaced surface's edges, not the base mesh's: each base edge grown by
// the spread of its normals over the displacement's reach and by depth times the height's rise
// along it (bounded by the map's steepest texel step), seen from the nearest of its points and
// stretched as the picture stretches it off the axis (1 / cos^2 of its angle, up to the corner's).
//
// `floor_level` (cheap_reference_level: where the whole scene's reference stays cheap) is taken
// where it is finer than both criteria allow, up to the texel level: at small sizes the pixel
// criterion asked for so coarse a reference that it, not the technique, made most of the error
// (the torus at 64x48: level 6, the prism 34 dB against it, 49 dB against level 10, 55 against
// 16; found by an exploratory session, thirty-sixth).
// `steps`: texel_steps(height).
ReferenceLevel choose_reference_level(const PreparedMesh& mesh, const glm::dmat4& transform,
                                      const HeightField& height, const TexelSteps& steps, float depth, float midlevel,
                                      const Camera& camera, int width_px, int height_px, std::size_t max_triangles,
                                      int floor_level = 1);

// A scene's levels (choose_reference_level's, each object's alone) lowered so that all its
// objects' triangles together, sum of triangles[k] * level[k]^2, stay within max_triangles: the
// finest levels first, to one cap that the objects above it share (those below keep theirs), and
// `capped` where an object's level fell under both its criteria. Returns the triangles then.
std::size_t cap_reference_levels(std::vector<ReferenceLevel>& levels, const std::vector<std::size_t>& triangles,
                                 std::size_t max_triangles);

// Triangles a reference may hold whatever the view, being cheap to build and draw (about 30 ms
// each on llvmpipe, 2 cores): the level below which no automatic level goes (where its map has
// texels to show).
inline constexpr std::size_t kCheapReferenceTriangles = std::size_t(1) << 18;

// The finest level at which a scene of `scene_triangles` base triangles stays within
// kCheapReferenceTriangles (at least 1).
int cheap_reference_level(std::size_t scene_triangles);

// Tessellates base triangles [first, last) at `level` and displaces them. Output vertices use the
// MeshVertex layout (position displaced; normal, uv, tangent, bitangent interpolated) so the
// surface shaders draw them, in object space (drawn with `transform`). `depth` is in world units,
// along world unit normals, as the prism's shell: each vertex's displacement direction is the
// object-space vector that `transform` maps to its world unit normal (under a scale the mesh's
// own unit normals would scale the displacement too), interpolated like the normals. Points on an edge are computed from that edge's two endpoints alone,
// in an order fixed by their vertex indices, so neighbours sharing the edge produce bit-identical
// positions: no cracks where UVs agree.
void tessellate_reference(const PreparedMesh& mesh, const glm::mat4& transform, const HeightField& height,
                          float depth, float midlevel, int level, std::size_t first, std::size_t last,
                          std::vector<MeshVertex>& vertices, std::vector<std::uint32_t>& indices);

// Bytes of vertex and index data per base triangle at `level` (for chunking and reporting).
std::size_t reference_bytes_per_triangle(int level);

} // namespace pr
