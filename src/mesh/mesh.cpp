#include "mesh/mesh.hpp"

#include "core/error.hpp"
#include "mesh/raw_mesh.hpp"

#include <new>
#include <stdexcept>

namespace pr {

PreparedMesh load_mesh(const std::filesystem::path& path, const MeshOptions& options)
{
    const std::string subject = path.string();
    try {
        const RawMesh raw = read_raw_mesh(path, options);
        PreparedMesh mesh = prepare_mesh(raw, options, subject);
        mesh.origin = raw.origin;
        return mesh;
    } catch (const Error&) {
        throw;
    } catch (const std::bad_alloc&) {
        // Every failure reaches the user as one line naming the file (contract).
        throw Error(subject, "not enough memory to load it");
    } catch (const std::exception& e) {
        throw Error(subject, std::string("could not be loaded: ") + e.what());
    }
}

} // namespace pr
