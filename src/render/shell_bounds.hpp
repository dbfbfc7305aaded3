#pragma once
// A tighter shell for the prism walk: at each welded position, the highest the height field gets
// over the triangles around it. The shell's top there is that height instead of 1, so rays enter
// lower and cross fewer prisms, and the field still lies under every top cap (docs/prism.md).
#include "core/image.hpp"
#include "mesh/mesh.hpp"

#include <glm/mat4x4.hpp>

#include <cstdint>
#include <vector>

namespace pr {

// Per render vertex: an upper bound, in [0, 1], of the bilinear height field over every triangle
// that shares the vertex's welded position (each triangle's bound covers the texels of its UV
// bounding box, with repeat wrap, plus the GPU's quantization of the heights), equal for every
// copy of a position, so that neighbouring prisms keep identical side faces. With `slope` (a
// depth above 0), tops are raised where needed so that along every edge they differ by at most
// the edge's world length over the depth (caps tilted no more than 45 degrees along an edge:
// steeper ones fold the shell, and the walk draws every face of a folded prism).
struct TopSlope {
    glm::mat4 transform{1.0f}; // object to world
    float depth = 0.0f;        // world units; 0: no limit
};
// `height_max`: the field's largest texel (HeightField::max_value), found once for the objects
// that share a field.
std::vector<float> shell_top_heights(const std::vector<MeshVertex>& vertices,
                                     const std::vector<std::uint32_t>& indices, const HeightField& height,
                                     float height_max, const TopSlope& slope = {});

// One vertex of the walk's shell corners, three vec4 per vertex as the renderer builds them
// (renderer.cpp, make_shell_corners; PR_TEX_CORNERS in shared.h): the bottom corner (world) and
// u, the unit normal and v, the tight top height and the welded id (bits of a float).
struct ShellCorner {
    glm::vec3 bottom;
    glm::vec3 normal;
    glm::vec2 uv;
    float top;
    std::uint32_t weld;
    // The shell's point over this vertex at height h (0 bottom, 1 the full shell's top), as
    // shell.glsl's shell_top_corner() builds it.
    glm::vec3 at(float h, float depth) const { return bottom + h * (depth * normal); }
};
ShellCorner shell_corner(const std::vector<glm::vec4>& corners, std::uint32_t vertex);

} // namespace pr
