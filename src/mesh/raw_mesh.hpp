#pragma once
// Internal to the mesh module: the polygon soup that the readers produce and the preparation
// step consumes. Kept separate from OpenMesh types so that preparation (welding, normals, UVs,
// tangents) can be tested on hand-made data without writing files.
#include "mesh/mesh.hpp"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pr {

// Polygons as read from the file, no topology. Face f owns the corners
// [face_offsets[f], face_offsets[f + 1]) of `corners`, counter-clockwise as in the file.
struct RawMesh {
    std::vector<glm::vec3> positions; // relative to `origin`
    // Where a mesh far from its file's origin was recentred, in the file's coordinates (0 for
    // every other; read_raw_mesh's recentre()).
    glm::dvec3 origin{0.0};
    // The positions are the reader's 32-bit floats (binary STL and OFF, binary PLY of floats,
    // ASCII STL): far from the origin for its size such a mesh may have lost triangles to them.
    bool float_positions = false;
    std::vector<std::uint32_t> face_offsets{0};
    std::vector<std::uint32_t> corners;    // vertex index per corner
    std::vector<glm::vec2> corner_uvs;     // per corner; empty when no face has UVs
    std::vector<std::uint8_t> face_has_uv; // per face; empty when no face has UVs
    // The file gave texture coordinates, usable or not (an OBJ face with one at some corners
    // only): the warning then says they were unusable, not missing (prepare_mesh).
    bool file_had_uvs = false;
    bool had_normals = false;              // the file carried vertex or corner normals
    std::size_t collapsed_faces = 0;       // faces the reader skipped: < 3 distinct vertices

    std::size_t face_count() const { return face_offsets.size() - 1; }
};

// Reads `path` through OpenMesh (after validating what OpenMesh does not) into a RawMesh.
// Throws pr::Error(path, problem) for every failure.
RawMesh read_raw_mesh(const std::filesystem::path& path, const MeshOptions& options);

// Triangulates, welds, computes normals, UVs and tangent frames. `name` is the subject of
// errors and the prefix of warnings. Throws pr::Error(name, problem).
PreparedMesh prepare_mesh(const RawMesh& raw, const MeshOptions& options, const std::string& name);

} // namespace pr
