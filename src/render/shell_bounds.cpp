#include "render/shell_bounds.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

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

} // namespace

namespace {

// Raises tops (never lowers: a top may only be above the field) until along every edge the top
// differs by at most the edge's length (world units, over the depth): a cap tilted steeply from
// its base folds the shell, and walk_triangles lists it for the geometry shader, which draws all
// its faces. Where triangles are small against the height texels (the million-triangle torus of
// make_big_mesh.py), neighbouring tops differ by more than that almost everywhere, and the listed
// prisms' faces cost more than the walk itself (1.03 M fragments at 512x512 against 77 k). Jacobi
// passes over the edges, a bounded number: what is left stays listed, as before.
void limit_top_slopes(std::vector<float>& weld_top, const std::vector<MeshVertex>& vertices,
                      const std::vector<std::uint32_t>& indices, const TopSlope& slope)
{
    std::vector<glm::vec3> world(weld_top.size());
    for (const MeshVertex& v : vertices) world[v.weld_id] = glm::vec3(slope.transform * glm::vec4(v.position, 1.0f));
    struct Edge {
        std::uint32_t a, b;
        float run; // the edge's length over the depth: the most the top may change along it
    };
    std::vector<Edge> edges;
    edges.reserve(indices.size());
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = vertices[indices[t + k]].weld_id, b = vertices[indices[t + (k + 1) % 3]].weld_id;
            if (a < b) edges.push_back({a, b, glm::length(world[a] - world[b]) / slope.depth});
            else if (b < a) edges.push_back({b, a, glm::length(world[a] - world[b]) / slope.depth});
        }
    for (int pass = 0; pass < 16; ++pass) {
        bool raised = false;
        for (const Edge& e : edges) {
            float &ta = weld_top[e.a], &tb = weld_top[e.b];
            if (ta < tb - e.run) ta = tb - e.run, raised = true;
            else if (tb < ta - e.run) tb = ta - e.run, raised = true;
        }
        if (!raised) break;
    }
}

} // namespace

std::vector<float> shell_top_heights(const std::vector<MeshVertex>& vertices,
                                     const std::vector<std::uint32_t>& indices, const HeightField& height,
                                     const TopSlope& slope)
{
    const float global_max = std::clamp(height.max_value(), 0.0f, 1.0f);
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
