// The prism walk's mesh data: edge adjacency (pairs across UV seams by welded position;
// boundaries, non-manifold edges and faces of opposite orientation have none) and the tight
// shell's top heights.
#include "core/image.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"
#include "render/shell_bounds.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <filesystem>
#include <vector>

namespace {

// Vertices with the given welded ids (a UV seam: two vertices, one id) and triangles.
struct Soup {
    std::vector<pr::MeshVertex> vertices;
    std::vector<std::uint32_t> indices;
};

Soup soup(const std::vector<std::uint32_t>& welds, std::vector<std::uint32_t> indices)
{
    Soup s;
    for (std::uint32_t w : welds) {
        pr::MeshVertex v;
        v.weld_id = w;
        s.vertices.push_back(v);
    }
    s.indices = std::move(indices);
    return s;
}

std::uint32_t across(std::uint32_t triangle, std::uint32_t edge) { return triangle << 2 | edge; }

// Every pairing is mutual and joins the same two welded positions, run the other way.
void expect_consistent(const Soup& s, const pr::EdgeAdjacency& a)
{
    ASSERT_EQ(a.neighbours.size(), s.indices.size());
    const auto weld = [&](std::size_t t, std::size_t corner) { return s.vertices[s.indices[3 * t + corner % 3]].weld_id; };
    for (std::size_t i = 0; i < a.neighbours.size(); ++i) {
        const std::uint32_t n = a.neighbours[i];
        if (n == pr::kNoNeighbour) continue;
        const std::size_t t = i / 3, e = i % 3, u = n >> 2, f = n & 3;
        EXPECT_EQ(a.neighbours[3 * u + f], across(std::uint32_t(t), std::uint32_t(e))) << i;
        EXPECT_EQ(weld(u, f), weld(t, e + 1)) << i;
        EXPECT_EQ(weld(u, f + 1), weld(t, e)) << i;
    }
}

} // namespace

TEST(Adjacency, TwoTrianglesShareOneEdgeAcrossAUvSeam)
{
    // Quad 0 1 2 3 split along 0-2; the second triangle uses copies 4 (of 0) and 5 (of 2).
    const Soup s = soup({0, 1, 2, 3, 0, 2}, {0, 1, 2, 4, 5, 3});
    const pr::EdgeAdjacency a = pr::edge_adjacency(s.vertices, s.indices);
    expect_consistent(s, a);
    EXPECT_EQ(a.neighbours[2], across(1, 0)); // edge 2-0 of the first is edge 4-5 of the second
    EXPECT_EQ(a.neighbours[3], across(0, 2));
    EXPECT_EQ(a.open_edges, 4u);
}

TEST(Adjacency, ClosedMeshesHaveNoOpenEdges)
{
    for (const char* name : {"cube.obj", "uv_sphere.obj", "torus.obj", "rock.obj"}) {
        const pr::PreparedMesh m = pr::load_mesh(std::filesystem::path(PR_SOURCE_DIR) / "meshes" / name);
        const Soup s{m.vertices, m.indices};
        const pr::EdgeAdjacency a = pr::edge_adjacency(m.vertices, m.indices);
        expect_consistent(s, a);
        EXPECT_EQ(a.open_edges, 0u) << name;
    }
    const pr::PreparedMesh plane = pr::load_mesh(std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "plane.obj");
    const pr::EdgeAdjacency a = pr::edge_adjacency(plane.vertices, plane.indices);
    EXPECT_GT(a.open_edges, 0u);
    EXPECT_LT(a.open_edges, a.neighbours.size() / 4);
}

// A UV seam where the surface may tear: the two sides give an end different texture
// coordinates, other than by whole repeats (heights wrap).
TEST(Adjacency, SeamEdgesAreThoseWhoseUvsDifferBeyondWholeRepeats)
{
    Soup s = soup({0, 1, 2, 3, 0, 2}, {0, 1, 2, 4, 5, 3});
    const glm::vec2 uv[] = {{0.1f, 0.1f}, {0.4f, 0.1f}, {0.4f, 0.4f}, {0.1f, 0.4f}};
    for (int i = 0; i < 4; ++i) s.vertices[i].uv = uv[i];
    s.vertices[4].uv = uv[0];
    s.vertices[5].uv = uv[2];
    EXPECT_EQ(pr::edge_adjacency(s.vertices, s.indices).seam_edges, 0u);
    s.vertices[4].uv = uv[0] + glm::vec2(2.0f, -1.0f); // the edge shifted by whole repeats:
    s.vertices[5].uv = uv[2] + glm::vec2(2.0f, -1.0f); // the same heights all along it
    EXPECT_EQ(pr::edge_adjacency(s.vertices, s.indices).seam_edges, 0u);
    s.vertices[5].uv = uv[2] + glm::vec2(1.0f, -1.0f); // both ends whole repeats, by different shifts:
    EXPECT_EQ(pr::edge_adjacency(s.vertices, s.indices).seam_edges, 1u); // the points between are not
    s.vertices[5].uv = uv[2] + glm::vec2(2.5f, -1.0f); // one end elsewhere in the texture
    const pr::EdgeAdjacency a = pr::edge_adjacency(s.vertices, s.indices);
    EXPECT_EQ(a.seam_edges, 1u);
    // Both sides' entries of the seam are flagged (edge 2-0 of the first, 4-5 of the second), no other.
    EXPECT_EQ(a.seam, (std::vector<std::uint8_t>{0, 0, 1, 1, 0, 0}));

    const auto seams = [](const char* name) {
        const pr::PreparedMesh m = pr::load_mesh(std::filesystem::path(PR_SOURCE_DIR) / "meshes" / name);
        return pr::edge_adjacency(m.vertices, m.indices).seam_edges;
    };
    EXPECT_EQ(seams("torus.obj"), 0u);     // its seams are whole repeats of the texture
    EXPECT_EQ(seams("plane.obj"), 0u);
    EXPECT_EQ(seams("uv_sphere.obj"), 64u); // each pole's fan: one u per cap triangle (32 segments)
    EXPECT_EQ(seams("cube.obj"), 6u); // six edges whose faces run their uv differently along them
                                      // (the other six: shifted by a whole repeat)
    EXPECT_GT(seams("rock.obj"), 100u);    // the borders of its six UV islands
}

TEST(Adjacency, NonManifoldAndFlippedEdgesHaveNoNeighbour)
{
    // Three triangles on edge 0-1 (a fin): none of them pairs there.
    const Soup fin = soup({0, 1, 2, 3, 4}, {0, 1, 2, 1, 0, 3, 1, 0, 4});
    const pr::EdgeAdjacency a = pr::edge_adjacency(fin.vertices, fin.indices);
    EXPECT_EQ(a.neighbours[0], pr::kNoNeighbour);
    EXPECT_EQ(a.neighbours[3], pr::kNoNeighbour);
    EXPECT_EQ(a.neighbours[6], pr::kNoNeighbour);
    EXPECT_EQ(a.open_edges, 9u);
    // Two triangles that run their shared edge the same way (one of them flipped).
    const Soup flipped = soup({0, 1, 2, 3}, {0, 1, 2, 0, 1, 3});
    EXPECT_EQ(pr::edge_adjacency(flipped.vertices, flipped.indices).open_edges, 6u);
    // A degenerate edge (both ends one position) pairs with nothing.
    const Soup degenerate = soup({0, 0, 1, 0, 0, 2}, {0, 1, 2, 4, 3, 5});
    const pr::EdgeAdjacency d = pr::edge_adjacency(degenerate.vertices, degenerate.indices);
    EXPECT_EQ(d.neighbours[0], pr::kNoNeighbour);
    EXPECT_EQ(d.neighbours[3], pr::kNoNeighbour);
}

// The tight shell's top: at every point of every triangle the bilinear field stays below the top
// interpolated from the corners (their minimum bounds it), equal for every copy of a position.
TEST(ShellBounds, TopStaysAboveTheFieldAndAgreesAcrossSeams)
{
    const pr::HeightField h = pr::load_height("builtin:bumps@64");
    for (const char* name : {"uv_sphere.obj", "rock.obj", "plane.obj"}) {
        const pr::PreparedMesh m = pr::load_mesh(std::filesystem::path(PR_SOURCE_DIR) / "meshes" / name);
        const std::vector<float> top = pr::shell_top_heights(m.vertices, m.indices, h, h.max_value());
        ASSERT_EQ(top.size(), m.vertices.size());
        double sum = 0.0;
        for (std::size_t t = 0; t < m.indices.size(); t += 3) {
            const pr::MeshVertex *a = &m.vertices[m.indices[t]], *b = &m.vertices[m.indices[t + 1]],
                                 *c = &m.vertices[m.indices[t + 2]];
            const float lowest = std::min({top[m.indices[t]], top[m.indices[t + 1]], top[m.indices[t + 2]]});
            for (int i = 0; i <= 8; ++i)
                for (int j = 0; i + j <= 8; ++j) {
                    const float u = i / 8.0f, v = j / 8.0f;
                    const glm::vec2 uv = a->uv * (1.0f - u - v) + b->uv * u + c->uv * v;
                    ASSERT_LE(h.sample(uv), lowest + 1e-6f) << name << " triangle " << t / 3;
                }
        }
        std::vector<float> by_weld(m.weld_count, -1.0f);
        for (std::size_t i = 0; i < m.vertices.size(); ++i) {
            float& w = by_weld[m.vertices[i].weld_id];
            if (w < 0.0f) w = top[i];
            EXPECT_EQ(w, top[i]) << name << " vertex " << i;
            EXPECT_LE(top[i], 1.0f);
            sum += top[i];
        }
        if (std::string(name) == "rock.obj") EXPECT_LT(sum / double(top.size()), 0.8) << "not tight";
    }
}

// With a slope limit the tops only rise, stay equal across copies of a position, and along every
// edge differ by at most the edge's world length over the depth; on a mesh of triangles small
// against the texels (the UV sphere with a fine map and a deep shell) the limit raises some tops.
TEST(ShellBounds, SlopeLimitRaisesTopsUntilNoEdgeIsSteep)
{
    const pr::HeightField h = pr::load_height("builtin:noise@256");
    const pr::PreparedMesh m = pr::load_mesh(std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "uv_sphere.obj");
    const glm::mat4 transform = glm::scale(glm::mat4(1.0f), glm::vec3(2.0f));
    const float depth = 0.5f;
    const std::vector<float> plain = pr::shell_top_heights(m.vertices, m.indices, h, h.max_value());
    const std::vector<float> limited = pr::shell_top_heights(m.vertices, m.indices, h, h.max_value(), pr::TopSlope{transform, depth});
    ASSERT_EQ(limited.size(), plain.size());
    std::size_t raised = 0;
    for (std::size_t i = 0; i < plain.size(); ++i) {
        EXPECT_GE(limited[i], plain[i]);
        EXPECT_LE(limited[i], 1.0f);
        raised += limited[i] > plain[i];
    }
    EXPECT_GT(raised, 0u);
    for (std::size_t t = 0; t < m.indices.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = m.indices[t + std::size_t(k)], b = m.indices[t + std::size_t((k + 1) % 3)];
            const float run = glm::length(glm::vec3(transform * glm::vec4(m.vertices[a].position, 1.0f)) -
                                          glm::vec3(transform * glm::vec4(m.vertices[b].position, 1.0f))) / depth;
            EXPECT_LE(std::abs(limited[a] - limited[b]), run + 2e-5f) << "edge of triangle " << t / 3;
        }
}

// The limit reaches as far as a tall top's slope does, in one go: a strip of 200 columns, 0.01
// apart at depth 1, flat but for a spike in the last column's texels, its triangles listed from
// the first column to the spike, so that the raise travels against their order (the bounded
// Jacobi passes before carried it about one column a pass: 83 columns of the slope, 99-181, were
// left at the field's height). Each top is the least that keeps the slope: the spike's less 0.01 a
// column of the way (plus the rounding step every top has).
TEST(ShellBounds, SlopeLimitReachesAlongALongStrip)
{
    constexpr int columns = 200;
    pr::HeightField h;
    h.width = 2 * columns;
    h.height = 4;
    h.name = "spike at the end";
    h.texels.assign(std::size_t(h.width) * std::size_t(h.height), 0.0f);
    for (int y = 0; y < h.height; ++y) h.texels[std::size_t(y + 1) * std::size_t(h.width) - 1] = 1.0f;
    Soup s;
    for (int i = 0; i < columns; ++i)
        for (int j = 0; j < 2; ++j) {
            pr::MeshVertex v;
            v.position = glm::vec3(0.01f * float(i), 0.01f * float(j), 0.0f);
            v.uv = glm::vec2((float(i) + 0.5f) / float(columns), 0.25f + 0.5f * float(j));
            v.weld_id = std::uint32_t(2 * i + j);
            s.vertices.push_back(v);
        }
    for (int i = 0; i + 1 < columns; ++i) {
        const std::uint32_t a = std::uint32_t(2 * i), b = a + 1, c = a + 2, d = a + 3;
        s.indices.insert(s.indices.end(), {a, c, d, a, d, b});
    }
    const std::vector<float> plain = pr::shell_top_heights(s.vertices, s.indices, h, h.max_value());
    const std::vector<float> top = pr::shell_top_heights(s.vertices, s.indices, h, h.max_value(), pr::TopSlope{glm::mat4(1.0f), 1.0f});
    ASSERT_EQ(top.size(), s.vertices.size());
    const float rounding = plain[0]; // the flat field's top: 0 plus one step of 8-bit rounding
    ASSERT_LT(rounding, 0.01f);
    // The field's own tops, column by column (the spike's reach the last few columns).
    std::vector<float> field(columns);
    for (int i = 0; i < columns; ++i)
        field[std::size_t(i)] = plain[std::size_t(2 * i)] >= 1.0f ? 1.0f : plain[std::size_t(2 * i)] - rounding;
    ASSERT_EQ(field[columns - 1], 1.0f);
    ASSERT_LT(field[columns / 2], 0.01f);
    for (int i = 0; i < columns; ++i) {
        float least = 0.0f;
        for (int c = 0; c < columns; ++c) least = std::max(least, field[std::size_t(c)] - 0.01f * float(std::abs(i - c)));
        for (int j = 0; j < 2; ++j)
            EXPECT_NEAR(top[std::size_t(2 * i + j)], std::min(least + rounding, 1.0f), 1e-4f) << "column " << i;
    }
}
