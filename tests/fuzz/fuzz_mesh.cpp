// libFuzzer harness: bytes -> a mesh file -> pr::load_mesh (our pre-validation of OBJ/OFF/PLY/STL,
// OpenMesh's reader into our importer, then preparation: triangulation, welding, normals, UVs,
// tangents) -> pr::edge_adjacency (the prism walk's neighbours). The first byte picks the extension, the rest is the file. pr::Error is the expected
// outcome for bad input; a crash, a sanitizer report, any other exception or a hang is a finding.
#include "core/error.hpp"
#include "fuzz_common.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    if (size < 1) return 0;
    static const char* const extensions[] = {".obj", ".off", ".ply", ".stl"};
    const auto path = pr::fuzz::scratch_file(extensions[data[0] % 4]);
    pr::fuzz::write_bytes(path, data + 1, size - 1);
    pr::MeshOptions options;
    options.max_triangles = 1'000'000; // keeps the fuzzer under -rss_limit_mb; same code path
    try {
        const pr::PreparedMesh mesh = pr::load_mesh(path, options);
        // What the renderer relies on: indices in range, finite unit normals, finite frames.
        for (std::uint32_t i : mesh.indices)
            if (i >= mesh.vertices.size()) {
                std::fprintf(stderr, "index %u out of range (%zu vertices)\n", i, mesh.vertices.size());
                std::abort();
            }
        for (const pr::MeshVertex& v : mesh.vertices) {
            const float values[] = {v.position.x, v.position.y, v.position.z, v.normal.x, v.normal.y,
                                    v.normal.z,   v.uv.x,       v.uv.y,       v.tangent.x, v.tangent.y,
                                    v.tangent.z,  v.tangent.w,  v.bitangent.x, v.bitangent.y,
                                    v.bitangent.z};
            for (float x : values)
                if (!std::isfinite(x)) {
                    std::fprintf(stderr, "non-finite vertex attribute\n");
                    std::abort();
                }
        }
        // The walk's adjacency: every pairing mutual, across the same two welded positions.
        const pr::EdgeAdjacency adjacency = pr::edge_adjacency(mesh.vertices, mesh.indices);
        const auto weld = [&](std::size_t t, std::size_t corner) {
            return mesh.vertices[mesh.indices[3 * t + corner % 3]].weld_id;
        };
        for (std::size_t i = 0; i < adjacency.neighbours.size(); ++i) {
            const std::uint32_t n = adjacency.neighbours[i];
            if (n == pr::kNoNeighbour) continue;
            const std::size_t t = i / 3, e = i % 3, u = n >> 2, f = n & 3u;
            if (u >= mesh.triangle_count() || f > 2 || adjacency.neighbours[3 * u + f] != (t << 2 | e) ||
                weld(u, f) != weld(t, e + 1) || weld(u, f + 1) != weld(t, e)) {
                std::fprintf(stderr, "inconsistent adjacency at edge %zu\n", i);
                std::abort();
            }
        }
    } catch (const pr::Error&) {
        // A clear, one-line refusal: the documented outcome for bad input.
    }
    return 0;
}
