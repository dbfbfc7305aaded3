// The prism that holds the eye, for views from inside the displacement shell (docs/prism.md,
// item 12): no cap faces the eye there, so the walk starts from the eye itself.
#pragma once

#include "render/shell_bounds.hpp"

#include "common/shared.h"

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/common.hpp>
#include <glm/vector_relational.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <optional>
#include <vector>

namespace pr {

struct EyeInShell {
    std::uint32_t prism; // the walk's triangle
    glm::vec3 tex;       // the eye in that prism's texture space: (u, v, height)
    bool under = false;  // under the surface there (inside a bump): the walk starts under it
};

// Boxes of the walk's prisms in blocks of kSize consecutive triangles (their full shells, which
// hold the tight ones), so that the search below looks at the triangles of a few blocks only
// (a mesh's triangles usually come in spatial order). Built once per upload.
struct PrismBlocks {
    static constexpr std::size_t kSize = 64;
    std::vector<glm::vec3> lo, hi;
};
PrismBlocks prism_blocks(const std::vector<glm::vec4>& corners, const std::vector<std::uint32_t>& indices,
                         float depth);

// The first prism of the walk's triangles `indices` that holds `eye` (world), from the shell
// corners of the renderer (ShellCorner, shell_bounds.hpp) and the depth (scene units). A prism's point of
// barycentric weights b and height h is sum b_i (bottom_i + h * depth * N_i), h from 0 to its top
// (1 with `full_shell`, else the corners' tight tops, interpolated); the eye's b and h come from
// a few Newton steps. Whether a prism holds the eye is judged on its planar faces, as the walk
// judges its exits. None when no prism holds the eye; `under` when it lies under the surface
// there (`height_at`: the height map at a uv).
template <class HeightAt>
std::optional<EyeInShell> find_eye_prism(const std::vector<glm::vec4>& corners,
                                         const std::vector<std::uint32_t>& indices, const PrismBlocks& blocks,
                                         float depth, bool full_shell, glm::vec3 eye, HeightAt height_at);

// Whether `eye` lies inside the closed surface of the walk's bottom caps (the object's body under
// its displacement shell), by the winding number of a ray's crossings (three rays vote): inside
// any of its closed pieces, nested or not. Meaningful for closed meshes only; `blocks` as for
// find_eye_prism.
bool eye_inside_body(const std::vector<glm::vec4>& corners, const std::vector<std::uint32_t>& indices,
                     const PrismBlocks& blocks, glm::vec3 eye);

// Where the eye lies in prism `a, b, c` (vertex indices into the corners): the eye's barycentric
// weights of b and c and its height, or none when Newton's steps do not settle.
std::optional<glm::vec3> prism_coordinates(const std::vector<glm::vec4>& corners, std::uint32_t a, std::uint32_t b,
                                           std::uint32_t c, float depth, glm::vec3 eye);

// Whether `eye` may lie in the prism of triangle t: inside the box of its six corners.
bool eye_near_prism(const std::vector<glm::vec4>& corners, const std::uint32_t* t, float depth, bool full_shell,
                    glm::vec3 eye);

// Whether `eye` lies inside the prism of triangle t as the walk sees it: inside its eight planar
// triangles (shell.glsl: the caps, and each side split along the diagonal that the welded ids
// choose), by their winding number about the eye.
bool eye_in_prism(const std::vector<glm::vec4>& corners, const std::uint32_t* t, float depth, bool full_shell,
                  glm::vec3 eye);

template <class HeightAt>
std::optional<EyeInShell> find_eye_prism(const std::vector<glm::vec4>& corners,
                                         const std::vector<std::uint32_t>& indices, const PrismBlocks& blocks,
                                         float depth, bool full_shell, glm::vec3 eye, HeightAt height_at)
{
    const std::size_t triangles = indices.size() / 3;
    for (std::size_t t = 0; t < triangles; ++t) {
        const std::size_t block = t / PrismBlocks::kSize;
        if (t % PrismBlocks::kSize == 0 && block < blocks.lo.size() &&
            (glm::any(glm::lessThan(eye, blocks.lo[block])) || glm::any(glm::greaterThan(eye, blocks.hi[block])))) {
            t += PrismBlocks::kSize - 1; // not in this block
            continue;
        }
        const std::uint32_t* v = &indices[3 * t];
        if (!eye_near_prism(corners, v, depth, full_shell, eye) || !eye_in_prism(corners, v, depth, full_shell, eye))
            continue;
        // Where in the prism: its barycentric weights and height, kept inside it (the planar
        // faces and the prism's own coordinates differ a little near its faces).
        const std::optional<glm::vec3> q = prism_coordinates(corners, v[0], v[1], v[2], depth, eye);
        if (!q) continue;
        glm::vec3 w(1.0f - q->x - q->y, q->x, q->y);
        w = glm::max(w, glm::vec3(0.0f));
        w /= std::max(w.x + w.y + w.z, 1e-30f);
        const ShellCorner c[3] = {shell_corner(corners, v[0]), shell_corner(corners, v[1]), shell_corner(corners, v[2])};
        const float top = full_shell ? 1.0f : w.x * c[0].top + w.y * c[1].top + w.z * c[2].top;
        float h = std::clamp(q->z, 0.0f, top);
        const glm::vec2 e_uv = w.x * c[0].uv + w.y * c[1].uv + w.z * c[2].uv;
        const float surface = height_at(e_uv);
        const bool under = h < surface;
        // The walk counts a sample within PR_PRISM_HIT_EPSILON above the surface as a hit: from an
        // eye that close (on flat ground between bumps) every ray stopped at the eye, in front of
        // the near plane, and the image was empty. The march starts twice that far off on the
        // eye's side (the hits move by at most that much of the depth).
        const float margin = 2.0f * float(PR_PRISM_HIT_EPSILON);
        if (std::abs(h - surface) < margin) h = std::clamp(under ? surface - margin : surface + margin, 0.0f, top);
        return EyeInShell{std::uint32_t(t), glm::vec3(e_uv, h), under};
    }
    return std::nullopt;
}

} // namespace pr
