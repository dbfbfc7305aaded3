#include "render/shell_bounds.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <queue>
#include <utility>

#include <glm/common.hpp>

namespace pr {
namespace {

// Maximum of the bilinear field over the UV box [lo, hi]: the texels at the corners of every
// cell the box touches (a bilinear cell never exceeds its corners).
float box_max(const HeightField& h, glm::vec2 lo, glm::vec2 hi, float global_max)
{
    const double x0 = std::floor(double(lo.x) * h.width - 0.5), x1 = std::floor(double(hi.x) * h.width - 0.5) + 1.0;
    const double y0 = std::floor(double(lo.y) * h.height - 0.5), y1 = std::floor(double(hi.y) * h.height - 0.5) + 1.0;
    if (!(x1 - x0 < h.width && y1 - y0 < h.height) || (x1 - x0 + 1.0) * (y1 - y0 + 1.0) > 4096.0)
        return global_max; // wraps around the texture, not finite, or larger than it is worth
    float m = 0.0f;
    for (auto y = static_cast<long long>(y0); y <= static_cast<long long>(y1); ++y)
        for (auto x = static_cast<long long>(x0); x <= static_cast<long long>(x1); ++x)
            m = std::max(m, h.at(static_cast<int>(((x % h.width) + h.width) % h.width),
                                 static_cast<int>(((y % h.height) + h.height) % h.height)));
    return m;
}

// Raises tops (never lowers: a top may only be above the field) until along every edge the top
// differs by at most the edge's length (world units, over the depth): a cap tilted steeply from
// its base folds the shell, and walk_triangles lists it for the geometry shader, which draws all
// its faces. Where triangles are small against the height texels (the million-triangle torus of
// make_big_mesh.py), neighbouring tops differ by more than that almost everywhere, and the listed
// prisms' faces cost more than the walk itself (1.03 M fragments at 512x512 against 77 k).
// The least such tops are top_a = max over b of (top_b - dist(a, b)), dist the shortest path
// along edges: a Dijkstra search from the highest tops down settles each position once, exactly,
// however far a tall top's influence reaches (bounded Jacobi passes, before, left the far end of a
// long slope steep).
void limit_top_slopes(std::vector<float>& weld_top, const std::vector<MeshVertex>& vertices,
                      const std::vector<std::uint32_t>& indices, const TopSlope& slope)
{
    const std::size_t n = weld_top.size();
    std::vector<glm::vec3> world(n);
    for (const MeshVertex& v : vertices) world[v.weld_id] = glm::vec3(slope.transform * glm::vec4(v.position, 1.0f));
    // Each welded edge once, in both directions (compressed rows: first[a] .. first[a + 1]).
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
    pairs.reserve(indices.size() * 2);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = vertices[indices[t + k]].weld_id, b = vertices[indices[t + (k + 1) % 3]].weld_id;
            if (a == b) continue;
            pairs.emplace_back(a, b);
            pairs.emplace_back(b, a);
        }
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    std::vector<std::size_t> first(n + 1, 0);
    for (const auto& [a, b] : pairs) ++first[a + 1];
    for (std::size_t i = 0; i < n; ++i) first[i + 1] += first[i];
    std::vector<float> run(pairs.size()); // the edge's length over the depth: the most the top may change along it
    for (std::size_t e = 0; e < pairs.size(); ++e)
        run[e] = glm::length(world[pairs[e].first] - world[pairs[e].second]) / slope.depth;

    using Entry = std::pair<float, std::uint32_t>; // (top, position): the highest first
    std::priority_queue<Entry> queue;
    for (std::uint32_t i = 0; i < n; ++i) queue.emplace(weld_top[i], i);
    while (!queue.empty()) {
        const auto [top, a] = queue.top();
        queue.pop();
        if (top < weld_top[a]) continue; // raised since it was queued
        for (std::size_t e = first[a]; e < first[a + 1]; ++e) {
            const std::uint32_t b = pairs[e].second;
            if (weld_top[b] < top - run[e]) {
                weld_top[b] = top - run[e];
                queue.emplace(weld_top[b], b);
            }
        }
    }
}

} // namespace

std::vector<float> shell_top_heights(const std::vector<MeshVertex>& vertices,
                                     const std::vector<std::uint32_t>& indices, const HeightField& height,
                                     float height_max, const TopSlope& slope)
{
    const float global_max = std::clamp(height_max, 0.0f, 1.0f);
    std::vector<float> weld_top(welded_position_count(vertices), 0.0f);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        const glm::vec2 a = vertices[indices[t]].uv, b = vertices[indices[t + 1]].uv, c = vertices[indices[t + 2]].uv;
        const float m = box_max(height, glm::min(a, glm::min(b, c)), glm::max(a, glm::max(b, c)), global_max);
        for (int k = 0; k < 3; ++k) {
            float& w = weld_top[vertices[indices[t + k]].weld_id];
            w = std::max(w, m);
        }
    }
    // The GPU reads the heights at 8 or 16 bits: allow one step of rounding up.
    const float step = height.bits > 8 ? 1.0f / 65535.0f : 1.0f / 255.0f;
    if (slope.depth > 0.0f) limit_top_slopes(weld_top, vertices, indices, slope);
    std::vector<float> top(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
        top[i] = std::min(1.0f, weld_top[vertices[i].weld_id] + step);
    return top;
}

ShellCorner shell_corner(const std::vector<glm::vec4>& corners, std::uint32_t vertex)
{
    const glm::vec4* c = &corners[3 * std::size_t(vertex)];
    return ShellCorner{glm::vec3(c[0]), glm::vec3(c[1]), glm::vec2(c[0].w, c[1].w), c[2].x,
                       std::bit_cast<std::uint32_t>(c[2].y)};
}

} // namespace pr
