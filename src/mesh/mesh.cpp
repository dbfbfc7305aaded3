#include "mesh/mesh.hpp"
#include "core/error.hpp"

namespace pr {
PreparedMesh load_mesh(const std::filesystem::path& path, const MeshOptions&)
{
    throw Error(path.string(), "mesh loading not implemented yet");
}
} // namespace pr
