#pragma once
// Mesh loading and preparation. This module is the only place that includes OpenMesh; what it
// returns is plain data (PreparedMesh), so nothing else depends on OpenMesh types.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

namespace pr {

// One render vertex: a unique (welded position, UV) pair, split once more where the faces
// sharing that pair have incompatible tangent frames (more than ~75 degrees apart, e.g. mirror
// seams, or a cube's faces sharing UV (1, 1) at a corner; docs/mesh-input.md). Vertices split by
// UV seams or frames keep the same `normal` and `weld_id`.
struct MeshVertex {
    glm::vec3 position{0.0f};  // object space
    // Unit, angle-weighted, welded by position (shell direction). A scene object under a shear or
    // an unequal scale holds its placed mesh's normals here, unit in world space instead
    // (place_mesh_frames): every use normalizes after the normal matrix.
    glm::vec3 normal{0.0f, 0.0f, 1.0f};
    glm::vec2 uv{0.0f};        // texture space, origin bottom-left
    // Metric tangent frame (contract): tangent.xyz = dP/du, bitangent = dP/dv, both unnormalized
    // (object units per UV unit), averaged over the faces around this (position, UV) vertex and
    // made perpendicular to `normal`. tangent.w = handedness: +1 when (T, B, N) is right-handed,
    // -1 for mirrored UVs. Degenerate UVs fall back to a finite frame, never NaN.
    glm::vec4 tangent{1.0f, 0.0f, 0.0f, 1.0f};
    glm::vec3 bitangent{0.0f, 1.0f, 0.0f};
    std::uint32_t weld_id = 0; // index of the welded position: equal for every copy of a position
};

struct MeshOptions {
    std::size_t max_triangles = 10'000'000; // after triangulation; more fails early with an error (about
                                            // 0.3 GB of peak memory per million with prism, 0.5 GB with its exact
                                            // exit: docs/robustness.md)
    // Automatic UVs for meshes without them (see docs/mesh-input.md): box projection on the
    // dominant axis of each face's welded normal; `uv_scale` UV units (texture repeats) across the
    // largest extent of the bounding box.
    float uv_scale = 2.0f;
    bool force_generated_uvs = false; // ignore the file's UVs
    // Corners that ear clipping may visit in all of a mesh's concave polygons (about 1.2 s here);
    // those left past it become fans, with a warning (mesh_prepare.cpp, docs/mesh-input.md).
    std::size_t ear_clip_work = std::size_t(1) << 30;
};

struct PreparedMesh {
    std::vector<MeshVertex> vertices;
    std::vector<std::uint32_t> indices; // triangles, counter-clockwise seen from outside
    std::uint32_t weld_count = 0;       // number of distinct welded positions
    glm::vec3 bbox_min{0.0f};
    glm::vec3 bbox_max{0.0f};
    // The file's coordinates are origin + position: a mesh far from its file's origin (geographic
    // coordinates) is kept relative to its centre, read in double (0 for every other;
    // read_raw_mesh). A scene places the mesh with transform * translate(origin).
    glm::dvec3 origin{0.0};
    bool had_uvs = false;               // false: UVs were generated
    bool had_normals = false;           // file normals are read but the shell always uses welded ones
    std::size_t dropped_triangles = 0;  // degenerate (zero area) triangles removed
    float largest_uv = 0.0f;            // the largest |u| or |v| (load_scene: its float precision)
    glm::vec2 largest_uv_axes{0.0f};    // the largest |u| and the largest |v|, apart
    bool largest_uv_generated = false;  // ... on a face whose UVs were generated (--uv-scale)
    std::size_t triangle_count() const { return indices.size() / 3; }
};

// One more than the largest welded id among `vertices`: PreparedMesh::weld_count for vertices
// that come without their PreparedMesh (read back from the GPU).
inline std::uint32_t welded_position_count(const std::vector<MeshVertex>& vertices)
{
    std::uint32_t n = 0;
    for (const MeshVertex& v : vertices) n = std::max(n, v.weld_id + 1);
    return n;
}

// The welded normals and tangent frames of `mesh` as the linear map `linear` (a scene object's
// transform) shapes it, where that is no similarity (a shear, a scale that differs by axis), as
// prepare_mesh gives them for the mesh with the map baked into its file; stored in object space so
// that the normal matrix and the model matrix give them back (every use of a normal normalizes;
// they are of unit length in world space, not in the object's). Carried by those matrices, the
// file's own are not those: a shear changes the faces' normals and the angles that weigh them, and
// the frames were made perpendicular to the file's normals. A cube's corner normal turned more
// than 90° from a face beside it, so that the walk lost a triangle of that face (IoU 0.74 against
// the reference; baked 0.997), and a milder shear drew a dark skirt along edges (the cube under
// rows [1, 1.5, 0], [0, 1, 0.7], [0, 0, 2]: IoU 0.926, baked 0.9994); found by exploratory
// sessions, fourteenth and fifty-third. Normals: each position's angle-weighted normal of its
// faces, slivers left out, as prepare_mesh's; a position whose faces cancel, or that only slivers
// touch, keeps its own. Frames: each triangle's real metric frame (linear in the positions)
// averaged with the placed corner angles and made perpendicular to the new normal; a vertex of a
// triangle without UV area (a limit frame), or whose average is no usable frame, keeps its own.
// The triangles must wind counter-clockwise seen from outside after the map (a mirroring one's
// turned first: load_scene). A similarity changes nothing.
void place_mesh_frames(PreparedMesh& mesh, const glm::dmat3& linear);

// Reads OBJ (v/vt/vn, polygons, negative indices), OFF, PLY, STL (ASCII or binary) through
// OpenMesh, validates what it returns, and prepares it. Throws pr::Error("<file>", "<problem>")
// for a missing/unreadable/malformed/empty file or one over the limits. Oddities that still
// render (non-manifold, degenerate faces dropped, generated UVs) produce pr::warn lines.
PreparedMesh load_mesh(const std::filesystem::path& path, const MeshOptions& options = {});

} // namespace pr
