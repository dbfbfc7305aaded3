#pragma once
// The prism walk's own triangles (docs/prism.md, item 11): the base mesh with every flat, evenly
// textured stretch merged into fewer, larger triangles. A ray crosses the shell prism after prism,
// and each prism crossed costs a pass of the walk and of its march; a floor of 16 x 16 quads is
// one plane with one texture mapping, and its shell is exactly that of two triangles.
//
// A vertex goes only where nothing the displaced surface depends on changes: its triangles lie in
// one plane with one affine texture mapping (the same dP/du and dP/dv), every vertex around it has
// its welded normal and tangent frame, and it is the only copy of its welded position (no UV seam
// passes through it). Then P, uv, N and the frame are affine over the region it leaves, and the
// larger triangles reproduce them (within float rounding). On a boundary it goes only where the
// boundary runs straight through it. Curved meshes come back unchanged.
#include "mesh/mesh.hpp"

#include <cstdint>
#include <vector>

namespace pr {

// Triangles (3 indices each, into `vertices`) covering the same surface as `indices`, with the
// same orientation; the input itself when nothing merges. Meshes OpenMesh cannot take as a
// manifold (non-manifold edges or vertices) come back unchanged.
std::vector<std::uint32_t> merge_flat_regions(const std::vector<MeshVertex>& vertices,
                                              const std::vector<std::uint32_t>& indices);
// Whether merge_flat_regions() finds anything to try: its first look alone (per face and vertex,
// no OpenMesh), false on curved meshes. (True does not promise a merge.)
bool has_flat_stretch(const std::vector<MeshVertex>& vertices, const std::vector<std::uint32_t>& indices);

} // namespace pr
