#pragma once
// Which triangle lies across each edge: what the prism walk (shaders/prism.frag) follows from
// one prism into the next. Edges are matched by welded position ids, so UV seams, which split
// render vertices but not positions, do not cut the surface apart.
#include "mesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace pr {

// Per triangle t and edge e (corners e and (e + 1) % 3), entry 3 t + e holds
// (neighbour << 2 | neighbour's edge), or kNoNeighbour on a boundary edge, on a non-manifold one
// (shared by more than two triangles) and on one that joins faces of opposite orientation: there
// the shell has a wall of its own. A neighbour runs the shared edge the other way (its corner
// `edge` is this triangle's corner e + 1).
inline constexpr std::uint32_t kNoNeighbour = 0xffffffffu;

struct EdgeAdjacency {
    std::vector<std::uint32_t> neighbours; // 3 per triangle
    std::size_t open_edges = 0;            // entries that are kNoNeighbour
    // Paired edges whose two triangles give an end different texture coordinates (other than by
    // whole repeats of the texture): UV seams, where the displaced surface may tear.
    std::size_t seam_edges = 0;
    // Per entry, as `neighbours`: 1 on a paired edge that is such a seam (both sides' entries).
    std::vector<std::uint8_t> seam;
};

// Throws pr::Error when the mesh has 2^30 triangles or more (the packing's limit).
EdgeAdjacency edge_adjacency(const std::vector<MeshVertex>& vertices, const std::vector<std::uint32_t>& indices);

} // namespace pr
