// The prism walk's merged triangles (mesh/flat_merge.hpp): flat, evenly mapped stretches become
// fewer triangles that carry the same surface — position, uv, shell normal and tangent frame at
// every point — with the same orientation; everything else stays.
#include "mesh/flat_merge.hpp"
#include "mesh/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "temp_dir.hpp"

namespace {

namespace fs = std::filesystem;
using glm::dvec2;
using glm::dvec3;

const fs::path kMeshes = fs::path(PR_SOURCE_DIR) / "meshes";

// An n x n grid of quads over [0,1]^2, each quad split into two triangles, as an OBJ: position
// (x, height(x, z), -z) for grid point (x, z) — a floor facing +Y seen from above — and uv(x, z).
std::string grid_obj(int n, const std::function<double(double, double)>& height,
                     const std::function<dvec2(double, double)>& uv)
{
    std::ostringstream s;
    s.precision(9);
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
            const double x = double(i) / n, z = double(j) / n;
            const dvec2 t = uv(x, z);
            s << "v " << x << ' ' << height(x, z) << ' ' << -z << "\nvt " << t.x << ' ' << t.y << '\n';
        }
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = b + n + 1, d = a + n + 1;
            s << "f " << a << '/' << a << ' ' << b << '/' << b << ' ' << c << '/' << c << '\n';
            s << "f " << a << '/' << a << ' ' << c << '/' << c << ' ' << d << '/' << d << '\n';
        }
    return s.str();
}

double flat(double, double) { return 0.0; }
dvec2 plain_uv(double x, double z) { return {x, z}; }

dvec3 pos(const pr::MeshVertex& v) { return dvec3(v.position); }

double area(const pr::PreparedMesh& m, const std::vector<std::uint32_t>& tris)
{
    double a = 0.0;
    for (std::size_t t = 0; t + 2 < tris.size(); t += 3)
        a += 0.5 * glm::length(glm::cross(pos(m.vertices[tris[t + 1]]) - pos(m.vertices[tris[t]]),
                                          pos(m.vertices[tris[t + 2]]) - pos(m.vertices[tris[t]])));
    return a;
}

// What the walk interpolates at a point of a triangle.
struct Surface {
    dvec3 p, n, tangent, bitangent;
    dvec2 uv;
};

Surface interpolate(const pr::PreparedMesh& m, const std::uint32_t* tri, const dvec3& w)
{
    Surface s{};
    for (int k = 0; k < 3; ++k) {
        const pr::MeshVertex& v = m.vertices[tri[k]];
        s.p += w[k] * pos(v);
        s.n += w[k] * dvec3(v.normal);
        s.tangent += w[k] * dvec3(v.tangent);
        s.bitangent += w[k] * dvec3(v.bitangent);
        s.uv += w[k] * dvec2(v.uv);
    }
    return s;
}

// Barycentric weights of p in triangle tri when p lies on it (within `slack`), else nothing.
std::optional<dvec3> weights_on(const pr::PreparedMesh& m, const std::uint32_t* tri, const dvec3& p, double slack)
{
    const dvec3 a = pos(m.vertices[tri[0]]), b = pos(m.vertices[tri[1]]), c = pos(m.vertices[tri[2]]);
    const dvec3 n = glm::cross(b - a, c - a);
    const double nn = glm::dot(n, n);
    if (!(nn > 0.0)) return std::nullopt;
    if (std::abs(glm::dot(p - a, n)) > slack * std::sqrt(nn)) return std::nullopt;
    const double wa = glm::dot(glm::cross(c - b, p - b), n) / nn, wb = glm::dot(glm::cross(a - c, p - c), n) / nn;
    const dvec3 w(wa, wb, 1.0 - wa - wb);
    if (std::min({w.x, w.y, w.z}) < -slack) return std::nullopt;
    return w;
}

// Points spread over every input triangle are on some merged triangle, where that triangle gives
// the same uv, shell normal and frame; the merged triangles face the way their region did.
void expect_same_surface(const pr::PreparedMesh& m, const std::vector<std::uint32_t>& merged)
{
    const double kSlack = 1e-5;
    const dvec3 samples[] = {{1.0 / 3, 1.0 / 3, 1.0 / 3}, {0.8, 0.1, 0.1}, {0.1, 0.8, 0.1}, {0.1, 0.1, 0.8}}; // inside: a seam's two sides share its edges
    int checked = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const dvec3 a = pos(m.vertices[m.indices[t]]), b = pos(m.vertices[m.indices[t + 1]]),
                    c = pos(m.vertices[m.indices[t + 2]]);
        const dvec3 facing = glm::cross(b - a, c - a);
        for (const dvec3& w : samples) {
            const Surface want = interpolate(m, &m.indices[t], w);
            bool found = false;
            for (std::size_t u = 0; u < merged.size() && !found; u += 3) {
                const auto wu = weights_on(m, &merged[u], want.p, kSlack);
                if (!wu) continue;
                const dvec3 ua = pos(m.vertices[merged[u]]), ub = pos(m.vertices[merged[u + 1]]),
                            uc = pos(m.vertices[merged[u + 2]]);
                if (glm::dot(glm::cross(ub - ua, uc - ua), facing) <= 0.0) continue; // the other side
                const Surface got = interpolate(m, &merged[u], *wu);
                found = true;
                EXPECT_NEAR(glm::length(got.uv - want.uv), 0.0, 1e-4) << "triangle " << t / 3;
                EXPECT_NEAR(glm::length(got.n - want.n), 0.0, 1e-4) << "triangle " << t / 3;
                EXPECT_NEAR(glm::length(got.tangent - want.tangent), 0.0, 1e-4) << "triangle " << t / 3;
                EXPECT_NEAR(glm::length(got.bitangent - want.bitangent), 0.0, 1e-4) << "triangle " << t / 3;
            }
            EXPECT_TRUE(found) << "no merged triangle under a point of triangle " << t / 3;
            ++checked;
        }
    }
    EXPECT_GT(checked, 0);
}

std::set<std::uint32_t> used(const std::vector<std::uint32_t>& tris) { return {tris.begin(), tris.end()}; }

} // namespace

TEST(FlatMerge, ASubdividedFloorBecomesTwoTriangles)
{
    const pr::PreparedMesh m = pr::load_mesh(kMeshes / "plane.obj");
    ASSERT_EQ(m.triangle_count(), 512u);
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_EQ(merged.size(), 6u);
    EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9);
    expect_same_surface(m, merged);
}

// A floor tiled 10 times merges into triangles no longer than two repeats of the texture (the
// walk samples a prism's segment in full only up to that; two triangles across ten repeats left a
// wall four texels thick of a 2048-texel map between samples: IoU 0.86; found by an exploratory
// session). A triangle that was longer already stays as it was.
TEST(FlatMerge, MergedTrianglesSpanAtMostTwoRepeatsOfTheTexture)
{
    prtest::TempDir dir;
    const auto longest_uv = [](const pr::PreparedMesh& m, const std::vector<std::uint32_t>& tris) {
        double longest = 0.0;
        for (std::size_t t = 0; t < tris.size(); t += 3)
            for (int k = 0; k < 3; ++k)
                longest = std::max(longest, double(glm::length(m.vertices[tris[t + std::size_t(k)]].uv -
                                                               m.vertices[tris[t + std::size_t((k + 1) % 3)]].uv)));
        return longest;
    };
    const pr::PreparedMesh tiled =
        pr::load_mesh(dir.write("tiled.obj", grid_obj(16, flat, [](double x, double z) { return dvec2(10.0 * x, 10.0 * z); })));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(tiled.vertices, tiled.indices);
    EXPECT_LT(merged.size(), tiled.indices.size() / 4); // still merged
    EXPECT_GT(merged.size(), 6u);
    EXPECT_LE(longest_uv(tiled, merged), 2.0 + 1e-6);
    EXPECT_NEAR(area(tiled, merged), area(tiled, tiled.indices), 1e-9);
    expect_same_surface(tiled, merged);
    // Each quad across three repeats: nothing merges past what it was.
    const pr::PreparedMesh coarse =
        pr::load_mesh(dir.write("coarse.obj", grid_obj(2, flat, [](double x, double z) { return dvec2(6.0 * x, 6.0 * z); })));
    const std::vector<std::uint32_t> kept = pr::merge_flat_regions(coarse.vertices, coarse.indices);
    EXPECT_LE(longest_uv(coarse, kept), longest_uv(coarse, coarse.indices) + 1e-6);
}

TEST(FlatMerge, CurvedMeshesComeBackUnchanged)
{
    // (The rock's chips are flat, but no vertex inside one has the chip's normal: they are
    // small, and their mappings are the cube sphere's, not affine.)
    for (const char* name : {"torus.obj", "uv_sphere.obj", "blob.off", "cube.obj", "rock.obj"}) {
        const pr::PreparedMesh m = pr::load_mesh(kMeshes / name);
        EXPECT_EQ(pr::merge_flat_regions(m.vertices, m.indices), m.indices) << name;
    }
}

TEST(FlatMerge, KeepsTheRingOfARaisedVertex)
{
    prtest::TempDir dir;
    const auto bump = [](double x, double z) { return std::abs(x - 0.5) < 1e-9 && std::abs(z - 0.5) < 1e-9 ? 0.2 : 0.0; };
    const pr::PreparedMesh m = pr::load_mesh(dir.write("bump.obj", grid_obj(8, bump, plain_uv)));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_LT(merged.size(), m.indices.size());
    EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9);
    expect_same_surface(m, merged);
    // The raised vertex and every vertex next to it stay (their normals differ from the floor's).
    std::uint32_t top = 0;
    for (std::uint32_t i = 0; i < m.vertices.size(); ++i)
        if (m.vertices[i].position.y > 0.1f) top = i;
    const std::set<std::uint32_t> kept = used(merged);
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        if (m.indices[t] != top && m.indices[t + 1] != top && m.indices[t + 2] != top) continue;
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(kept.count(m.indices[t + std::size_t(k)])) << m.indices[t + std::size_t(k)];
    }
}

TEST(FlatMerge, KeepsUvSeamsAndMergesEachSide)
{
    // Left half mapped at u = x, right half at u = x + 0.25: the column at x = 0.5 is a seam.
    prtest::TempDir dir;
    std::string obj = grid_obj(8, flat, plain_uv);
    // Rewrite the right half's uvs per face: faces right of x = 0.5 take uv copies of their own.
    const int n = 8;
    std::ostringstream s;
    s.precision(9);
    std::istringstream in(obj);
    std::string line;
    while (std::getline(in, line))
        if (line.rfind("f ", 0) != 0) s << line << '\n';
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i)
            s << "vt " << double(i) / n + 0.25 << ' ' << double(j) / n << '\n';
    const int right = (n + 1) * (n + 1); // offset of the second uv set
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = b + n + 1, d = a + n + 1;
            const int o = i >= n / 2 ? right : 0;
            s << "f " << a << '/' << a + o << ' ' << b << '/' << b + o << ' ' << c << '/' << c + o << '\n';
            s << "f " << a << '/' << a + o << ' ' << c << '/' << c + o << ' ' << d << '/' << d + o << '\n';
        }
    const pr::PreparedMesh m = pr::load_mesh(dir.write("seam.obj", s.str()));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_LT(merged.size(), m.indices.size());
    EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9);
    expect_same_surface(m, merged);
    // Every render vertex on the seam stays, on both sides.
    const std::set<std::uint32_t> kept = used(merged);
    int seam = 0;
    for (std::uint32_t i = 0; i < m.vertices.size(); ++i) {
        if (std::abs(m.vertices[i].position.x - 0.5f) > 1e-6f) continue;
        if (!used(m.indices).count(i)) continue;
        EXPECT_TRUE(kept.count(i)) << "seam vertex " << i;
        ++seam;
    }
    EXPECT_EQ(seam, 2 * (n + 1));
}

TEST(FlatMerge, LeavesAnUnevenMappingAlone)
{
    // uv = (x^2, z): each column of quads has a mapping of its own, so no vertex can go.
    prtest::TempDir dir;
    const pr::PreparedMesh m =
        pr::load_mesh(dir.write("uneven.obj", grid_obj(6, flat, [](double x, double z) { return dvec2(x * x, z); })));
    EXPECT_EQ(pr::merge_flat_regions(m.vertices, m.indices), m.indices);
}

TEST(FlatMerge, MergesEachWingOfAFoldAndKeepsTheCrease)
{
    // Two flat wings meeting at x = 0.5 at 90 degrees.
    prtest::TempDir dir;
    const auto fold = [](double x, double) { return x > 0.5 ? x - 0.5 : 0.0; };
    const pr::PreparedMesh m = pr::load_mesh(dir.write("fold.obj", grid_obj(8, fold, plain_uv)));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    // The crease and the columns beside it stay (their welded normals are bent, or their
    // neighbours'): 2 x 8 quads, 32 triangles; each wing beyond them is a polygon of 11 corners,
    // 9 triangles.
    EXPECT_EQ(merged.size(), 3u * (32 + 9 + 9));
    EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9);
    // Not the same uv map on the sloped wing (uv follows x, not the slope), but one affine map:
    // it merges; the crease and its neighbours (normals bent) stay.
    expect_same_surface(m, merged);
    const std::set<std::uint32_t> kept = used(merged);
    for (std::uint32_t i = 0; i < m.vertices.size(); ++i)
        if (std::abs(m.vertices[i].position.x - 0.5f) < 1e-6f) EXPECT_TRUE(kept.count(i)) << i;
}

TEST(FlatMerge, MergesAFlatPartAndLeavesTheCurvedPartAsItIs)
{
    // Flat for x <= 0.5, curved beyond: only the flat part and its rim go to OpenMesh; every
    // triangle of the curved part comes back as it was.
    prtest::TempDir dir;
    const auto bowl = [](double x, double) { return x > 0.5 ? 2.0 * (x - 0.5) * (x - 0.5) : 0.0; };
    const pr::PreparedMesh m = pr::load_mesh(dir.write("bowl.obj", grid_obj(12, bowl, plain_uv)));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_LT(merged.size(), m.indices.size() * 2 / 3);
    EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9);
    expect_same_surface(m, merged);
    std::set<std::array<std::uint32_t, 3>> out;
    for (std::size_t t = 0; t < merged.size(); t += 3) {
        std::array<std::uint32_t, 3> k{merged[t], merged[t + 1], merged[t + 2]};
        std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end()); // same winding, one start
        out.insert(k);
    }
    int curved = 0;
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        std::array<std::uint32_t, 3> k{m.indices[t], m.indices[t + 1], m.indices[t + 2]};
        if (std::min({m.vertices[k[0]].position.x, m.vertices[k[1]].position.x, m.vertices[k[2]].position.x}) < 0.55f)
            continue;
        std::rotate(k.begin(), std::min_element(k.begin(), k.end()), k.end());
        EXPECT_TRUE(out.count(k)) << "curved triangle " << t / 3;
        ++curved;
    }
    EXPECT_GT(curved, 100);
}

TEST(FlatMerge, MergesAMirroredFloorToo)
{
    // u runs against x: every tangent frame is left-handed (tangent.w = -1), and it merges alike.
    prtest::TempDir dir;
    const pr::PreparedMesh m =
        pr::load_mesh(dir.write("mirrored.obj", grid_obj(6, flat, [](double x, double z) { return dvec2(1.0 - x, z); })));
    ASSERT_EQ(m.vertices[0].tangent.w, -1.0f);
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_EQ(merged.size(), 6u);
    expect_same_surface(m, merged);
}

TEST(FlatMerge, KeepsAFinAndTheEdgeItStandsOn)
{
    // A floor with a fin standing on one of its inner edges: three faces on that edge (in the
    // welded mesh; the fin's corners are render vertices of their own, with their own frames).
    prtest::TempDir dir;
    std::string obj = grid_obj(4, flat, plain_uv);
    // Grid vertices 7 and 8 (1-based: row 1, columns 1 and 2) share an inner edge; the fin's apex
    // is a new vertex above them.
    obj += "v 0.375 0.3 -0.25\nvt 0.5 0.5\nf 7/7 8/8 26/26\n";
    const pr::PreparedMesh m = pr::load_mesh(dir.write("fin.obj", obj));
    ASSERT_EQ(m.triangle_count(), 33u);
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_LT(merged.size(), m.indices.size());
    expect_same_surface(m, merged);
    // The edge keeps a floor triangle on each side: positions 0.25 and 0.5 along x at z = 0.25.
    const auto at = [&](std::uint32_t i, float x) {
        return std::abs(m.vertices[i].position.x - x) < 1e-6f && std::abs(m.vertices[i].position.z + 0.25f) < 1e-6f &&
               m.vertices[i].position.y == 0.0f;
    };
    int sides = 0;
    for (std::size_t t = 0; t < merged.size(); t += 3)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t a = merged[t + std::size_t(k)], b = merged[t + std::size_t((k + 1) % 3)];
            const bool floor = std::abs(m.vertices[merged[t + std::size_t((k + 2) % 3)]].position.y) < 1e-6f;
            sides += floor && ((at(a, 0.25f) && at(b, 0.5f)) || (at(a, 0.5f) && at(b, 0.25f)));
        }
    EXPECT_EQ(sides, 2);
}

TEST(FlatMerge, AGentlyCurvedFloorKeepsItsCurve)
{
    // y = a x^2 bends each edge's normal by less than the merge's tolerance, but the floor's by
    // 2a: merging must not creep along the chain of nearly equal neighbours and flatten it
    // (points of every input triangle stay on the merged ones within 1e-5).
    prtest::TempDir dir;
    const double a = 1.5e-4;
    const pr::PreparedMesh m =
        pr::load_mesh(dir.write("gentle.obj", grid_obj(40, [a](double x, double) { return a * x * x; }, plain_uv)));
    const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
    EXPECT_LT(merged.size(), m.indices.size());
    expect_same_surface(m, merged);
}

TEST(FlatMerge, PiecesMeetingAtAVertexKeepTheirRegions)
{
    // Two squares touching at one corner (a bowtie), and a T-junction (one quad beside two, the
    // middle vertex of their side on the quad's edge, not joined to it): where pieces meet at a
    // vertex it has two boundary gaps, and moving it along a boundary run of one piece that is
    // collinear with the other's cut a triangle out of a square (prism IoU 0.60; 0.88).
    prtest::TempDir dir;
    const std::string bowtie = "v -1 0 1\nv 0 0 1\nv 0 0 0\nv -1 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\n"
                               "vt 0 0\nvt 0.5 0\nvt 0.5 0.5\nvt 0 0.5\nvt 1 0.5\nvt 1 1\nvt 0.5 1\n"
                               "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 3/3 5/5 6/6\nf 3/3 6/6 7/7\n";
    const std::string t_junction = "v -1 0 1\nv 0 0 1\nv 0 0 -1\nv -1 0 -1\nv 1 0 1\nv 1 0 0\nv 0 0 0\nv 1 0 -1\n"
                                   "vt 0 0\nvt 0.5 0\nvt 0.5 1\nvt 0 1\nvt 1 0\nvt 1 0.5\nvt 0.5 0.5\nvt 1 1\n"
                                   "f 1/1 2/2 3/3\nf 1/1 3/3 4/4\nf 2/2 5/5 6/6\nf 2/2 6/6 7/7\nf 7/7 6/6 8/8\nf 7/7 8/8 3/3\n";
    for (const auto& [name, obj] : {std::pair{"bowtie.obj", bowtie}, std::pair{"t_junction.obj", t_junction}}) {
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, obj));
        const std::vector<std::uint32_t> merged = pr::merge_flat_regions(m.vertices, m.indices);
        EXPECT_NEAR(area(m, merged), area(m, m.indices), 1e-9) << name;
        expect_same_surface(m, merged);
    }
}
