// Mesh preparation: welded normals, UVs (the file's and generated ones), tangent frames, and
// the bundled meshes.
#include "core/error.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/mesh.hpp"
#include "mesh/raw_mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <unistd.h>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>

namespace fs = std::filesystem;

#include "temp_dir.hpp"

namespace {

const fs::path kMeshes = fs::path(PR_SOURCE_DIR) / "meshes";

using prtest::TempDir;

bool finite(const glm::vec3& v)
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// A polygon soup for prepare_mesh, without files.
pr::RawMesh soup(std::vector<glm::vec3> positions,
                 const std::vector<std::vector<std::uint32_t>>& faces,
                 const std::vector<std::vector<glm::vec2>>& uvs = {})
{
    pr::RawMesh m;
    m.positions = std::move(positions);
    for (std::size_t f = 0; f < faces.size(); ++f) {
        for (std::size_t i = 0; i < faces[f].size(); ++i) {
            m.corners.push_back(faces[f][i]);
            if (!uvs.empty()) m.corner_uvs.push_back(uvs[f][i]);
        }
        m.face_offsets.push_back(std::uint32_t(m.corners.size()));
        if (!uvs.empty()) m.face_has_uv.push_back(1);
    }
    return m;
}

// The vertex at `p` (the first one found).
const pr::MeshVertex& vertex_at(const pr::PreparedMesh& m, glm::vec3 p)
{
    for (const pr::MeshVertex& v : m.vertices)
        if (glm::distance(v.position, p) < 1e-6f) return v;
    ADD_FAILURE() << "no vertex at " << p.x << " " << p.y << " " << p.z;
    return m.vertices.front();
}

float handedness(const pr::MeshVertex& v)
{
    return glm::dot(glm::cross(v.normal, glm::vec3(v.tangent)), v.bitangent) < 0.0f ? -1.0f : 1.0f;
}

} // namespace

// ---- normals -------------------------------------------------------------------------------

TEST(MeshNormals, CubeSeamsDoNotSplitNormals)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "cube.obj");
    EXPECT_TRUE(m.had_uvs);
    EXPECT_TRUE(m.had_normals);
    EXPECT_EQ(m.weld_count, 8u);
    EXPECT_EQ(m.triangle_count(), 12u);
    // Every face corner is its own render vertex (UV seams, and perpendicular frames where
    // faces share a UV value), but the file's per-face normals are ignored: all copies of a
    // corner carry the welded normal.
    ASSERT_EQ(m.vertices.size(), 24u);
    std::map<std::uint32_t, glm::vec3> by_weld;
    for (const pr::MeshVertex& v : m.vertices) {
        const glm::vec3 expected = glm::normalize(glm::sign(v.position));
        EXPECT_NEAR(glm::distance(v.normal, expected), 0.0f, 1e-6f);
        const auto it = by_weld.emplace(v.weld_id, v.position).first;
        EXPECT_EQ(it->second, v.position);
    }
    EXPECT_EQ(by_weld.size(), 8u);
}

TEST(MeshNormals, AngleWeighted)
{
    // At the origin: a 90 degree corner of a triangle facing +Z (area 0.5) and a 45 degree
    // corner of a triangle facing +X (area 1.5). Angle weights give (pi/4, 0, pi/2); area or
    // uniform weights would give other directions.
    const pr::RawMesh raw =
        soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 1, 0}, {0, 3, 3}}, {{0, 1, 2}, {0, 3, 4}});
    const pr::PreparedMesh m = pr::prepare_mesh(raw, {}, "test");
    const glm::vec3 n = vertex_at(m, {0, 0, 0}).normal;
    const glm::vec3 expected =
        glm::normalize(glm::vec3(glm::pi<float>() / 4, 0, glm::pi<float>() / 2));
    EXPECT_NEAR(glm::distance(n, expected), 0.0f, 1e-5f);
    // (0, 1, 0) is shared too (two file vertices, one welded position): 45 degrees in the +Z
    // triangle, acos(-2 / sqrt(13)) in the +X one.
    const float a2 = std::acos(-2.0f / std::sqrt(13.0f));
    const glm::vec3 n1 = vertex_at(m, {0, 1, 0}).normal;
    const glm::vec3 e1 = glm::normalize(glm::vec3(a2, 0, glm::pi<float>() / 4));
    EXPECT_NEAR(glm::distance(n1, e1), 0.0f, 1e-5f);
    EXPECT_EQ(m.weld_count, 4u);
}

TEST(MeshNormals, UvSphereNormalIsPosition)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "uv_sphere.obj");
    for (const pr::MeshVertex& v : m.vertices)
        EXPECT_LT(glm::distance(v.normal, v.position), 0.01f)
            << v.position.x << " " << v.position.y;
}

TEST(MeshNormals, SeamCopiesShareWeldIdAndNormal)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "uv_sphere.obj");
    std::map<std::uint32_t, std::vector<const pr::MeshVertex*>> copies;
    for (const pr::MeshVertex& v : m.vertices) copies[v.weld_id].push_back(&v);
    EXPECT_EQ(copies.size(), m.weld_count);
    std::size_t split = 0;
    for (const auto& [id, list] : copies) {
        for (const pr::MeshVertex* v : list) {
            EXPECT_EQ(v->position, list.front()->position);
            EXPECT_EQ(v->normal, list.front()->normal);
        }
        split += list.size() > 1;
    }
    // the u = 0/1 seam (15 ring vertices) and the two poles (one UV per cap triangle)
    EXPECT_EQ(split, 15u + 2u);
}

TEST(MeshNormals, CancellingFacesGetAFiniteNormal)
{
    // A double-sided quad: both sides weld to the same positions and cancel.
    const pr::RawMesh raw =
        soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2, 3}, {0, 3, 2, 1}});
    const pr::PreparedMesh m = pr::prepare_mesh(raw, {}, "test");
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_TRUE(finite(v.normal));
        EXPECT_NEAR(glm::length(v.normal), 1.0f, 1e-5f);
        EXPECT_TRUE(finite(glm::vec3(v.tangent)) && finite(v.bitangent));
    }
}

// ---- UVs -------------------------------------------------------------------------------------

TEST(MeshUv, GeneratedForOffAreFiniteAndNeverMirrored)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "blob.off");
    EXPECT_FALSE(m.had_uvs);
    const pr::MeshOptions defaults;
    for (const pr::MeshVertex& v : m.vertices) {
        ASSERT_TRUE(std::isfinite(v.uv.x) && std::isfinite(v.uv.y));
        EXPECT_GE(v.uv.x, 0.0f);
        EXPECT_GE(v.uv.y, 0.0f);
        EXPECT_LE(v.uv.x, defaults.uv_scale * 1.0001f);
        EXPECT_LE(v.uv.y, defaults.uv_scale * 1.0001f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshUv, BoxProjectionSeenFromOutside)
{
    // One unit quad facing each axis direction: U must run to the right and V up as seen from
    // outside (never mirrored), with V along +Y on the four sides.
    struct Case {
        glm::vec3 normal, right, up;
    };
    const Case cases[] = {
        {{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {1, 0, 0}, {0, 0, -1}}, {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {-1, 0, 0}, {0, 1, 0}},
    };
    for (const Case& c : cases) {
        const glm::vec3 o = c.normal;
        const pr::RawMesh raw =
            soup({o, o + c.right, o + c.right + c.up, o + c.up}, {{0, 1, 2, 3}});
        pr::MeshOptions options;
        options.uv_scale = 1.0f; // one UV unit across the quad
        const pr::PreparedMesh m = pr::prepare_mesh(raw, options, "test");
        for (const pr::MeshVertex& v : m.vertices) {
            EXPECT_EQ(v.tangent.w, 1.0f);
            EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), c.right), 0.0f, 1e-5f);
            EXPECT_NEAR(glm::distance(v.bitangent, c.up), 0.0f, 1e-5f);
        }
        EXPECT_EQ(vertex_at(m, o).uv, glm::vec2(0.0f));
        EXPECT_EQ(vertex_at(m, o + c.right + c.up).uv, glm::vec2(1.0f));
    }
}

TEST(MeshUv, ForcedGeneratedUvsReplaceTheFilesAndSplitAtAxisChanges)
{
    pr::MeshOptions options;
    options.force_generated_uvs = true;
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "cube.obj", options);
    EXPECT_FALSE(m.had_uvs);
    EXPECT_EQ(m.vertices.size(), 24u); // every corner touches three projection directions
    for (const pr::MeshVertex& v : m.vertices) EXPECT_EQ(v.tangent.w, 1.0f);
}

// A sheet whose normal lies 1° from the diagonal between +X and +Y (+Y dominant), with one
// vertex raised: the faces on one side of the bump turn a little towards +X. Box projection by
// the dominant axis alone gives them an island of their own (+X), with UV seams around it; the
// tidied charts give the whole sheet the +Y projection, seamless.
TEST(MeshUv, SmallChartsJoinTheirNeighbours)
{
    const float theta = 46.0f * glm::pi<float>() / 180.0f;
    const glm::vec3 n0(std::cos(theta), std::sin(theta), 0.0f), across(-std::sin(theta), std::cos(theta), 0.0f),
        along(0.0f, 0.0f, 1.0f);
    constexpr int kQuads = 6;
    std::vector<glm::vec3> positions;
    for (int j = 0; j <= kQuads; ++j)
        for (int i = 0; i <= kQuads; ++i) {
            glm::vec3 p = 0.2f * (float(i - kQuads / 2) * across + float(j - kQuads / 2) * along);
            if (i == kQuads / 2 && j == kQuads / 2) p += 0.05f * n0;
            positions.push_back(p);
        }
    std::vector<std::vector<std::uint32_t>> faces;
    for (int j = 0; j < kQuads; ++j)
        for (int i = 0; i < kQuads; ++i) {
            const auto at = [&](int di, int dj) { return std::uint32_t((j + dj) * (kQuads + 1) + i + di); };
            faces.push_back({at(0, 0), at(1, 0), at(1, 1)});
            faces.push_back({at(0, 0), at(1, 1), at(0, 1)});
        }
    const pr::PreparedMesh m = pr::prepare_mesh(soup(positions, faces), {}, "test");
    // The island is there by the dominant axis: some triangle's corners' welded normals sum to
    // a direction closer to +X than to +Y.
    int towards_x = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        glm::vec3 sum(0.0f);
        for (int k = 0; k < 3; ++k) sum += m.vertices[m.indices[t + std::size_t(k)]].normal;
        towards_x += std::abs(sum.x) > std::abs(sum.y);
    }
    ASSERT_GT(towards_x, 0);
    EXPECT_LT(towards_x, 16); // a small chart (under max(16, faces / 64) faces)
    // One projection for the whole sheet: +Y's (U = x, V = -z), one vertex per position.
    EXPECT_EQ(m.vertices.size(), positions.size());
    const float s = pr::MeshOptions{}.uv_scale / (m.bbox_max.z - m.bbox_min.z); // z: the largest extent
    ASSERT_GT(m.bbox_max.z - m.bbox_min.z, m.bbox_max.x - m.bbox_min.x);
    ASSERT_GT(m.bbox_max.z - m.bbox_min.z, m.bbox_max.y - m.bbox_min.y);
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_NEAR(v.uv.x, (v.position.x - m.bbox_min.x) * s, 1e-5f);
        EXPECT_NEAR(v.uv.y, (m.bbox_max.z - v.position.z) * s, 1e-5f);
    }
}

// On the bundled blob (no UVs), the charts' ragged edges and islands are tidied: fewer seams
// (470 edges by the dominant axis alone), and every triangle projected along one of the six box
// directions no more than 60° from its corners' summed welded normals (at most 2× stretch).
TEST(MeshUv, GeneratedChartsOfTheBlobAreTidy)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "blob.off");
    const pr::EdgeAdjacency adjacency = pr::edge_adjacency(m.vertices, m.indices);
    EXPECT_LE(adjacency.seam_edges, 340u);
    EXPECT_GT(adjacency.seam_edges, 0u);
    const glm::vec3 extent = m.bbox_max - m.bbox_min;
    const float s = pr::MeshOptions{}.uv_scale / std::max({extent.x, extent.y, extent.z});
    // Box directions (docs/mesh-input.md): the axis, and U and V as signed coordinates.
    struct Box {
        glm::vec3 axis;
        int u, v;
        float su, sv;
    };
    const Box boxes[6] = {{{1, 0, 0}, 2, 1, -1, 1}, {{-1, 0, 0}, 2, 1, 1, 1}, {{0, 1, 0}, 0, 2, 1, -1},
                          {{0, -1, 0}, 0, 2, 1, 1}, {{0, 0, 1}, 0, 1, 1, 1},  {{0, 0, -1}, 0, 1, -1, 1}};
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const pr::MeshVertex &a = m.vertices[m.indices[t]], &b = m.vertices[m.indices[t + 1]],
                             &c = m.vertices[m.indices[t + 2]];
        const glm::vec3 n = glm::normalize(a.normal + b.normal + c.normal);
        int found = 0;
        for (const Box& box : boxes) {
            const auto fits = [&](const pr::MeshVertex& p, const pr::MeshVertex& q) {
                const glm::vec3 e = q.position - p.position;
                const glm::vec2 d = q.uv - p.uv;
                return std::abs(d.x - box.su * e[box.u] * s) < 1e-4f && std::abs(d.y - box.sv * e[box.v] * s) < 1e-4f;
            };
            if (!fits(a, b) || !fits(a, c)) continue;
            ++found;
            EXPECT_GE(glm::dot(n, box.axis), 0.5f - 1e-4f) << "triangle " << t / 3;
        }
        EXPECT_EQ(found, 1) << "triangle " << t / 3 << ": not one box projection";
    }
}

// ---- tangents --------------------------------------------------------------------------------

TEST(MeshTangent, PlaneTangentIsScaledX)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "plane.obj");
    // 2 x 2 units with UV 0..1: 2 units per UV unit; U = +X, V = -Z, normal +Y.
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_NEAR(glm::distance(v.normal, glm::vec3(0, 1, 0)), 0.0f, 1e-6f);
        EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), glm::vec3(2, 0, 0)), 0.0f, 1e-4f);
        EXPECT_NEAR(glm::distance(v.bitangent, glm::vec3(0, 0, -2)), 0.0f, 1e-4f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshTangent, MirroredUvsGiveNegativeHandedness)
{
    TempDir dir;
    // U runs towards -X: mirrored as seen from +Z.
    const pr::PreparedMesh m = pr::load_mesh(
        dir.write("m.obj", "v 0 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nvt 1 0\nvt 0 0\nvt 0 1\nvt 1 1\n"
                           "f 1/1 2/2 3/3 4/4\n"));
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_EQ(v.tangent.w, -1.0f);
        EXPECT_EQ(handedness(v), -1.0f);
        EXPECT_NEAR(glm::distance(glm::vec3(v.tangent), glm::vec3(-3, 0, 0)), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::distance(v.bitangent, glm::vec3(0, 1, 0)), 0.0f, 1e-5f);
    }
}

TEST(MeshTangent, MirrorSeamSplitsVertices)
{
    // Two quads side by side, the right one's UVs mirrored about their shared edge, so the
    // edge's vertices have the same UV on both sides: they must not share a tangent.
    const pr::RawMesh raw =
        soup({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}},
             {{0, 1, 2, 3}, {1, 4, 5, 2}},
             {{{0, 0}, {1, 0}, {1, 1}, {0, 1}}, {{1, 0}, {0, 0}, {0, 1}, {1, 1}}});
    const pr::PreparedMesh m = pr::prepare_mesh(raw, {}, "test");
    EXPECT_EQ(m.vertices.size(), 8u);
    EXPECT_EQ(m.weld_count, 6u);
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_NEAR(glm::length(glm::vec3(v.tangent)), 1.0f, 1e-5f);
        EXPECT_EQ(handedness(v), v.tangent.w);
    }
    int mirrored = 0;
    for (const pr::MeshVertex& v : m.vertices) mirrored += v.tangent.w < 0.0f;
    EXPECT_EQ(mirrored, 4);
}

TEST(MeshTangent, DegenerateUvsGiveAFiniteOrthogonalFrame)
{
    // All three UVs equal: no dP/du can be derived.
    const pr::RawMesh raw = soup({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}},
                                 {{{0.5f, 0.5f}, {0.5f, 0.5f}, {0.5f, 0.5f}}});
    const pr::PreparedMesh m = pr::prepare_mesh(raw, {}, "test");
    ASSERT_EQ(m.vertices.size(), 3u);
    for (const pr::MeshVertex& v : m.vertices) {
        const glm::vec3 t(v.tangent);
        ASSERT_TRUE(finite(t) && finite(v.bitangent));
        EXPECT_GT(glm::length(t), 0.0f);
        EXPECT_GT(glm::length(v.bitangent), 0.0f);
        EXPECT_NEAR(glm::dot(t, v.normal), 0.0f, 1e-5f);
        EXPECT_NEAR(glm::dot(v.bitangent, v.normal), 0.0f, 1e-5f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

TEST(MeshTangent, FramesArePerpendicularToTheWeldedNormal)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "torus.obj");
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_NEAR(glm::dot(glm::vec3(v.tangent), v.normal), 0.0f, 1e-4f);
        EXPECT_NEAR(glm::dot(v.bitangent, v.normal), 0.0f, 1e-4f);
        EXPECT_EQ(v.tangent.w, 1.0f);
    }
}

// ---- the bundled meshes --------------------------------------------------------------------

TEST(MeshBundled, EveryMeshLoadsCleanly)
{
    std::size_t count = 0;
    for (const auto& entry : fs::directory_iterator(kMeshes)) {
        const std::string ext = entry.path().extension().string();
        if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl") continue;
        SCOPED_TRACE(entry.path().string());
        ++count;
        EXPECT_LT(fs::file_size(entry.path()), 1u << 20);
        const pr::PreparedMesh m = pr::load_mesh(entry.path());
        EXPECT_EQ(m.dropped_triangles, 0u);
        ASSERT_FALSE(m.indices.empty());
        for (std::uint32_t i : m.indices) ASSERT_LT(i, m.vertices.size());
        for (const pr::MeshVertex& v : m.vertices) {
            ASSERT_TRUE(finite(v.position) && finite(v.normal) && finite(glm::vec3(v.tangent)) &&
                        finite(v.bitangent));
            ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
            ASSERT_LT(v.weld_id, m.weld_count);
            // Made without mirrored UVs.
            EXPECT_EQ(v.tangent.w, 1.0f);
        }
        // Consistently oriented: each directed edge between welded positions is used once;
        // the closed ones also use each edge in both directions.
        std::set<std::pair<std::uint32_t, std::uint32_t>> edges;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            for (int k = 0; k < 3; ++k) {
                const std::uint32_t a = m.vertices[m.indices[3 * t + k]].weld_id;
                const std::uint32_t b = m.vertices[m.indices[3 * t + (k + 1) % 3]].weld_id;
                EXPECT_TRUE(edges.emplace(a, b).second);
            }
        }
        if (entry.path().filename() != "plane.obj") {
            for (const auto& [a, b] : edges) EXPECT_TRUE(edges.count({b, a}) == 1);
        }
        // Faces point away from the origin, the centre of these star-shaped shapes (the torus
        // aside).
        if (entry.path().filename() != "plane.obj" && entry.path().filename() != "torus.obj") {
            const glm::vec3 centre(0.0f);
            for (std::size_t t = 0; t < m.triangle_count(); ++t) {
                const glm::vec3 a = m.vertices[m.indices[3 * t]].position;
                const glm::vec3 b = m.vertices[m.indices[3 * t + 1]].position;
                const glm::vec3 c = m.vertices[m.indices[3 * t + 2]].position;
                EXPECT_GT(glm::dot(glm::cross(b - a, c - a), (a + b + c) / 3.0f - centre), 0.0f);
            }
        }
    }
    EXPECT_GE(count, 6u);
}

TEST(MeshBundled, RockIsAModelWithRealUvs)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "rock.obj");
    EXPECT_TRUE(m.had_uvs);
    EXPECT_GE(m.triangle_count(), 5000u);
    EXPECT_LE(m.triangle_count(), 10000u);
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_GE(v.uv.x, 0.0f);
        EXPECT_LE(v.uv.x, 1.0f);
        EXPECT_GE(v.uv.y, 0.0f);
        EXPECT_LE(v.uv.y, 1.0f);
    }
}

TEST(MeshBundled, TorusQuadsAreTriangulated)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "torus.obj");
    EXPECT_EQ(m.triangle_count(), 48u * 24u * 2u);
    EXPECT_EQ(m.weld_count, 48u * 24u);
    EXPECT_NEAR(m.bbox_max.x, 1.35f, 1e-5f);
    EXPECT_NEAR(m.bbox_max.y, 0.35f, 1e-3f);
}
