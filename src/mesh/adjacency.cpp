#include "mesh/adjacency.hpp"
#include "mesh/dense_index.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <cmath>

namespace pr {

EdgeAdjacency edge_adjacency(const std::vector<MeshVertex>& vertices, const std::vector<std::uint32_t>& indices)
{
    const std::size_t triangles = indices.size() / 3;
    if (triangles >= (std::size_t(1) << 30))
        throw Error("mesh", "too many triangles for the prism walk's adjacency (2^30 or more)");
    EdgeAdjacency out;
    out.neighbours.assign(triangles * 3, kNoNeighbour);
    out.seam.assign(triangles * 3, 0);

    // Bucket every edge by the smaller weld id of its ends (counting sort: two passes over the
    // edges, 4 bytes per edge and per welded position), then pair edges within a bucket.
    const auto weld = [&](std::size_t corner) { return vertices[indices[corner]].weld_id; };
    const auto ends = [&](std::size_t edge) {
        const std::size_t t = edge / 3, e = edge % 3;
        const std::uint32_t a = weld(3 * t + e), b = weld(3 * t + (e + 1) % 3);
        return std::pair{std::min(a, b), std::max(a, b)};
    };
    const auto same_direction = [&](std::size_t x, std::size_t y) {
        return weld(3 * (x / 3) + x % 3) == weld(3 * (y / 3) + y % 3);
    };
    // Whether an edge's two sides give it the same texture coordinates up to one whole shift of
    // the texture (heights wrap, contract): then they agree all along it, not only at its ends.
    const auto same_uv = [&](std::size_t a0, std::size_t b0, std::size_t a1, std::size_t b1) {
        const glm::vec2 d0 = vertices[indices[a0]].uv - vertices[indices[b0]].uv;
        const glm::vec2 d1 = vertices[indices[a1]].uv - vertices[indices[b1]].uv;
        const glm::vec2 whole(std::round(d0.x), std::round(d0.y));
        const auto near = [](glm::vec2 x, glm::vec2 y) { return std::abs(x.x - y.x) <= 1e-6f && std::abs(x.y - y.y) <= 1e-6f; };
        return near(d0, whole) && near(d1, whole);
    };
    const std::uint32_t weld_count = welded_position_count(vertices);
    Buckets by_end = bucket_by_key(weld_count, triangles * 3, [&](std::size_t edge) { return ends(edge).first; });
    const std::vector<std::uint32_t>& start = by_end.start;
    std::vector<std::uint32_t>& bucket = by_end.items;
    for (std::size_t w = 0; w < weld_count; ++w) {
        const auto first = bucket.begin() + start[w], last = bucket.begin() + start[w + 1];
        std::sort(first, last, [&](std::uint32_t x, std::uint32_t y) {
            return std::pair{ends(x).second, x} < std::pair{ends(y).second, y};
        });
        for (auto it = first; it != last;) {
            auto same = it;
            while (same != last && ends(*same).second == ends(*it).second) ++same;
            // Degenerate edges (both ends one position) never pair; more than two is non-manifold;
            // two that run the same way join faces of opposite orientation, whose prisms extrude
            // to opposite sides: the walk cannot go from one into the other.
            if (same - it == 2 && ends(*it).first != ends(*it).second && !same_direction(*it, *(it + 1))) {
                const std::uint32_t x = *it, y = *(it + 1);
                out.neighbours[x] = (y / 3) << 2 | (y % 3);
                out.neighbours[y] = (x / 3) << 2 | (x % 3);
                // Corner e of x is corner e + 1 of y and the other way round.
                const std::size_t tx = 3 * (x / 3), ty = 3 * (y / 3);
                if (!same_uv(tx + x % 3, ty + (y % 3 + 1) % 3, tx + (x % 3 + 1) % 3, ty + y % 3)) {
                    out.seam[x] = out.seam[y] = 1;
                    ++out.seam_edges;
                }
            }
            it = same;
        }
    }
    out.open_edges = static_cast<std::size_t>(std::count(out.neighbours.begin(), out.neighbours.end(), kNoNeighbour));
    return out;
}

} // namespace pr
