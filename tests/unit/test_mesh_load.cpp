// Mesh reading: every format and variant, and every way a file can be wrong.
#include "core/error.hpp"
#include "mesh/mesh.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <unistd.h>
#include <vector>

#include <glm/geometric.hpp>

namespace fs = std::filesystem;

#include "error_of.hpp"
#include "temp_dir.hpp"

namespace {

// The loads that guard against work growing with the square of a face's corners or of the faces
// on an edge (in release builds 0.25 s and 0.3 s now, 21 s and 6 s before) allow ten times their
// bound under AddressSanitizer, which slows them about tenfold.
#ifdef __SANITIZE_ADDRESS__
constexpr double kSlower = 10.0;
#else
constexpr double kSlower = 1.0;
#endif

using prtest::TempDir;


template <class T>
void put(std::vector<char>& out, T value)
{
    char b[sizeof(T)];
    std::memcpy(b, &value, sizeof(T));
    out.insert(out.end(), b, b + sizeof(T));
}

bool finite(const glm::vec3& v)
{
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

// Everything a consumer relies on, for any loaded mesh.
void expect_sane(const pr::PreparedMesh& m)
{
    ASSERT_FALSE(m.indices.empty());
    ASSERT_EQ(m.indices.size() % 3, 0u);
    for (std::uint32_t i : m.indices) ASSERT_LT(i, m.vertices.size());
    for (const pr::MeshVertex& v : m.vertices) {
        ASSERT_TRUE(finite(v.position));
        ASSERT_TRUE(finite(v.normal));
        ASSERT_NEAR(glm::length(v.normal), 1.0f, 1e-4f);
        ASSERT_TRUE(std::isfinite(v.uv.x) && std::isfinite(v.uv.y));
        ASSERT_TRUE(finite(glm::vec3(v.tangent)));
        ASSERT_TRUE(finite(v.bitangent));
        ASSERT_GT(glm::length(glm::vec3(v.tangent)), 0.0f);
        ASSERT_GT(glm::length(v.bitangent), 0.0f);
        ASSERT_TRUE(v.tangent.w == 1.0f || v.tangent.w == -1.0f);
        ASSERT_LT(v.weld_id, m.weld_count);
    }
}

// Geometric normal of triangle t.
glm::vec3 face_normal(const pr::PreparedMesh& m, std::size_t t)
{
    const glm::vec3 a = m.vertices[m.indices[3 * t]].position;
    const glm::vec3 b = m.vertices[m.indices[3 * t + 1]].position;
    const glm::vec3 c = m.vertices[m.indices[3 * t + 2]].position;
    return glm::cross(b - a, c - a);
}

// The centre of triangle t.
glm::vec3 triangle_centre(const pr::PreparedMesh& m, std::size_t t)
{
    return (m.vertices[m.indices[3 * t]].position + m.vertices[m.indices[3 * t + 1]].position +
            m.vertices[m.indices[3 * t + 2]].position) /
           3.0f;
}

// Loads and returns the error it throws; fails the test if there is none.
pr::Error load_error(const fs::path& path, const pr::MeshOptions& options = {})
{
    try {
        pr::load_mesh(path, options);
    } catch (const pr::Error& e) {
        return e;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "not a pr::Error: " << e.what();
        return pr::Error(path.string(), "wrong exception type");
    }
    ADD_FAILURE() << "no error for " << path;
    return pr::Error(path.string(), "no error");
}

#define EXPECT_ERROR_MENTIONS(err, path, text)                                                     \
    do {                                                                                           \
        const pr::Error e_ = (err);                                                                \
        EXPECT_EQ(e_.subject(), (path).string());                                                  \
        EXPECT_NE(e_.problem().find(text), std::string::npos) << "problem: " << e_.problem();      \
    } while (0)

const char* kQuadObj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";

} // namespace

// ---- formats ---------------------------------------------------------------------------------

TEST(MeshLoad, ObjWithoutUvsOrNormals)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(dir.write("q.obj", kQuadObj));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.weld_count, 4u);
    EXPECT_FALSE(m.had_uvs);
    EXPECT_FALSE(m.had_normals);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) EXPECT_GT(face_normal(m, t).z, 0.0f);
    EXPECT_EQ(m.bbox_min, glm::vec3(0.0f));
    EXPECT_EQ(m.bbox_max, glm::vec3(1.0f, 1.0f, 0.0f));
}

TEST(MeshLoad, ObjWithUvsAndNormals)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(
        dir.write("q.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 0.5 0\nvt 0.5 0.25\n"
                           "vt 0 0.25\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"));
    expect_sane(m);
    EXPECT_TRUE(m.had_uvs);
    EXPECT_TRUE(m.had_normals);
    ASSERT_EQ(m.vertices.size(), 4u);
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_FLOAT_EQ(v.uv.x, v.position.x * 0.5f);
        EXPECT_FLOAT_EQ(v.uv.y, v.position.y * 0.25f);
        EXPECT_EQ(v.normal, glm::vec3(0, 0, 1));
    }
}

TEST(MeshLoad, ObjNegativeIndicesEqualPositiveOnes)
{
    TempDir dir;
    const pr::PreparedMesh a = pr::load_mesh(
        dir.write("a.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n"));
    const pr::PreparedMesh b = pr::load_mesh(dir.write(
        "b.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf -3/-3 -2/-2 -1/-1\n"));
    ASSERT_EQ(a.vertices.size(), b.vertices.size());
    ASSERT_EQ(a.indices, b.indices);
    for (std::size_t i = 0; i < a.vertices.size(); ++i) {
        EXPECT_EQ(a.vertices[i].position, b.vertices[i].position);
        EXPECT_EQ(a.vertices[i].uv, b.vertices[i].uv);
    }
    EXPECT_TRUE(b.had_uvs);
}

TEST(MeshLoad, ObjPolygonsAreTriangulatedCounterClockwise)
{
    TempDir dir;
    // A hexagon and an L-shaped (concave) hexagon: a fan from the first corner would put a
    // triangle outside the L.
    const pr::PreparedMesh hex = pr::load_mesh(dir.write(
        "hex.obj",
        "v 2 0 0\nv 1 1.7 0\nv -1 1.7 0\nv -2 0 0\nv -1 -1.7 0\nv 1 -1.7 0\nf 1 2 3 4 5 6\n"));
    EXPECT_EQ(hex.triangle_count(), 4u);
    const pr::PreparedMesh l = pr::load_mesh(dir.write(
        "l.obj", "v 0 2 0\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nf 1 2 3 4 5 6\n"));
    expect_sane(l);
    ASSERT_EQ(l.triangle_count(), 4u);
    float area = 0.0f;
    for (std::size_t t = 0; t < l.triangle_count(); ++t) {
        const glm::vec3 n = face_normal(l, t);
        EXPECT_GT(n.z, 0.0f) << "triangle " << t;
        area += 0.5f * n.z;
    }
    EXPECT_NEAR(area, 3.0f, 1e-5f); // the L's area; overlapping or outside triangles change it
}

// A backslash at a line's end continues it ("malformed face corner '\\'" before); lines after a
// joined one keep their numbers in messages.
TEST(MeshLoad, ObjLineContinuationsAreJoined)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(
        dir.write("c.obj", "v 0 0 0\nv 1 0 \\\n 0\nv 1 1 0\r\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                           "vt 0 1\nf 1/1 2/2 \\\r\n3/3 \\\n4/4\n"));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 2u);
    EXPECT_TRUE(m.had_uvs);
    for (const pr::MeshVertex& v : m.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
    EXPECT_EQ(prtest::error_of([&] {
                  pr::load_mesh(dir.write("e.obj", "v 0 0 0\nv 1 \\\n0 0\nv 0 1 0\nf 1 2 \\\n9\n"));
              }).problem(),
              "line 5: vertex index 9 is out of range (the file has 3 vertices)");
}

// A face that repeats a corner: OpenMesh's reader keeps the first of each vertex and passes all
// the corners' texture coordinates, which then matched no corner (the file's UVs were lost:
// "no texture coordinates"). The face keeps its corners, and a polygon that touches itself at a
// repeated corner (two loops through one vertex) is triangulated loop by loop, inside its outline
// (the ear test skips corners that coincide, so the fan of what was left crossed between loops).
TEST(MeshLoad, ObjFacesRepeatingACornerKeepTheirUvsAndOutline)
{
    TempDir dir;
    const pr::PreparedMesh closed = pr::load_mesh(
        dir.write("closed.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                "vt 0 1\nf 1/1 2/2 3/3 4/4 1/1\n"));
    expect_sane(closed);
    EXPECT_TRUE(closed.had_uvs);
    EXPECT_EQ(closed.triangle_count(), 2u);
    for (const pr::MeshVertex& v : closed.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));

    // Two triangles meeting at vertex 3 (1, 1), as one polygon: 1 2 3 4 5 3.
    const std::string bowtie = "v 0 0 0\nv 2 0 0\nv 1 1 0\nv 2 2 0\nv 0 2 0\n";
    for (const std::string& face : {"f 1 2 3 4 5 3\n", "f 3 4 5 3 1 2\n", "f 2 3 4 5 3 1\n"}) {
        const pr::PreparedMesh m = pr::load_mesh(dir.write("bowtie.obj", bowtie + face));
        expect_sane(m);
        float area = 0.0f;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const glm::vec3 n = face_normal(m, t);
            EXPECT_GT(n.z, 0.0f) << face << "triangle " << t;
            area += 0.5f * std::abs(n.z);
        }
        EXPECT_NEAR(area, 2.0f, 1e-5f) << face; // the two lobes; a triangle outside adds to it
        EXPECT_EQ(m.triangle_count(), 2u) << face;
    }
    // Each lobe has a corner of its own at the shared point, with its texture coordinate: the
    // loop closed there keeps the earlier visit's (u + v = 1 here), the rest of the outline the
    // later one's (2). The loop cutting of the nineteenth session gave both the earlier corner,
    // until a review found it.
    for (const std::string& face : {"f 1/1 2/2 3/3 4/4 5/5 3/6\n", "f 3/3 4/4 5/5 3/6 1/1 2/2\n"}) {
        const pr::PreparedMesh m = pr::load_mesh(dir.write(
            "bowtie_uv.obj", bowtie + "vt 0 0\nvt 1 0\nvt 0.5 0.5\nvt 1 1\nvt 0 1\nvt 1 1\n" + face));
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const pr::MeshVertex* c[3] = {&m.vertices[m.indices[3 * t]], &m.vertices[m.indices[3 * t + 1]],
                                          &m.vertices[m.indices[3 * t + 2]]};
            const bool upper = c[0]->position.y + c[1]->position.y + c[2]->position.y > 3.0f;
            for (const pr::MeshVertex* v : c)
                if (v->position == glm::vec3(1.0f, 1.0f, 0.0f))
                    EXPECT_FLOAT_EQ(v->uv.x + v->uv.y, upper ? 1.0f : 2.0f) << face << "triangle " << t;
        }
    }
    // A keyhole (a 4 x 4 square with a 2 x 2 hole, joined by a bridge from corner 1 to corner 5)
    // passes twice through two points too, but its second loop is the hole: not cut, clipped as
    // one polygon.
    const pr::PreparedMesh keyhole = pr::load_mesh(
        dir.write("keyhole.obj", "v 0 0 0\nv 4 0 0\nv 4 4 0\nv 0 4 0\nv 1 1 0\nv 1 3 0\nv 3 3 0\n"
                                 "v 3 1 0\nf 1 2 3 4 1 5 6 7 8 5\n"));
    float area = 0.0f;
    for (std::size_t t = 0; t < keyhole.triangle_count(); ++t) {
        const glm::vec3 n = face_normal(keyhole, t);
        EXPECT_GT(n.z, 0.0f) << "keyhole triangle " << t;
        area += 0.5f * std::abs(n.z);
    }
    EXPECT_NEAR(area, 12.0f, 1e-5f);
}

// Polygons of more than 64 corners were all fans, which put a concave one's triangles outside
// its outline (a 1000-corner star: overlapping triangles of both windings). They are clipped up
// to 4096 corners; a concave polygon past that is a fan with a warning, a convex one its fan.
TEST(MeshLoad, LargeConcavePolygonsAreClipped)
{
    TempDir dir;
    auto star = [](int n) {
        std::string text;
        std::vector<glm::dvec2> q;
        for (int i = 0; i < n; ++i) {
            const double r = i % 2 == 0 ? 1.0 : 0.5, a = 2.0 * 3.14159265358979 * i / n;
            q.emplace_back(r * std::cos(a), r * std::sin(a));
            text += "v " + std::to_string(q.back().x) + " " + std::to_string(q.back().y) + " 0\n";
        }
        text += "f";
        for (int i = 0; i < n; ++i) text += " " + std::to_string(i + 1);
        return text + "\n";
    };
    auto covered = [](const pr::PreparedMesh& m, int& negative) {
        double area = 0.0;
        negative = 0;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const float z = face_normal(m, t).z;
            area += 0.5 * std::abs(double(z));
            negative += z < 0.0f;
        }
        return area;
    };
    // The star's own area: n triangles (centre, outer, inner corner), each r1 r2 sin(2 pi / n) / 2.
    const int n = 1000;
    const double star_area = n * 0.5 * 1.0 * 0.5 * std::sin(2.0 * 3.14159265358979 / n);
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("star.obj", star(n)));
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(said.find("fan"), std::string::npos) << said;
    int negative = 0;
    EXPECT_NEAR(covered(m, negative), star_area, 1e-3 * star_area);
    EXPECT_EQ(negative, 0);
    EXPECT_EQ(m.triangle_count(), std::size_t(n - 2));

    // The budget bounds the time, not only the size: a spiral strip of 4096 corners (each ear test
    // finds one of few ears; it took 9 s) is fanned with the warning once the budget is spent.
    std::string spiral;
    const int turns = 2048;
    for (int side = 0; side < 2; ++side)
        for (int k = 0; k < turns; ++k) {
            const int i = side == 0 ? k : turns - 1 - k;
            const double a = 0.1 * i, r = 1.0 + 0.05 * a - (side == 0 ? 0.0 : 0.02);
            spiral += "v " + std::to_string(r * std::cos(a)) + " " + std::to_string(r * std::sin(a)) + " 0\n";
        }
    spiral += "f";
    for (int i = 0; i < 2 * turns; ++i) spiral += " " + std::to_string(i + 1);
    // (Not timed: that the budget ran out is what the warning says, 0.8 s into it here.)
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("spiral.obj", spiral + "\n"));
    EXPECT_NE(::testing::internal::GetCapturedStderr().find("1 concave polygon too large to clip"), std::string::npos);

    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("big.obj", star(5000)));
    EXPECT_NE(::testing::internal::GetCapturedStderr().find(
                  "1 concave polygon too large to clip (more than 4096 corners, or past the time "
                  "budget) triangulated as a fan, which may cover area outside its outline"),
              std::string::npos);
}

// Small concave polygons are charged to the clipping budget too: before, polygons of up to 64
// corners were clipped whatever the mesh held of them (up to 64^3 visits each, and 160,000 of
// them fit under the triangle limit). Strictly convex ones cost nothing.
TEST(MeshLoad, SmallConcavePolygonsShareTheClippingBudget)
{
    TempDir dir;
    // 40 L-shaped hexagons (concave), then a square.
    std::string text;
    int base = 1;
    for (int k = 0; k < 40; ++k) {
        const double x = 3.0 * k;
        for (const auto& [px, py] : {std::pair{0.0, 0.0}, {2.0, 0.0}, {2.0, 1.0}, {1.0, 1.0}, {1.0, 2.0}, {0.0, 2.0}})
            text += "v " + std::to_string(x + px) + " " + std::to_string(py) + " 0\n";
        text += "f";
        for (int i = 0; i < 6; ++i) text += " " + std::to_string(base + i);
        text += "\n";
        base += 6;
    }
    text += "v 0 5 0\nv 1 5 0\nv 1 6 0\nv 0 6 0\nf " + std::to_string(base) + " " + std::to_string(base + 1) + " " +
            std::to_string(base + 2) + " " + std::to_string(base + 3) + "\n";
    const fs::path file = dir.write("ls.obj", text);
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh whole = pr::load_mesh(file);
    EXPECT_EQ(::testing::internal::GetCapturedStderr().find("fan"), std::string::npos);
    EXPECT_EQ(whole.triangle_count(), 40u * 4u + 2u);
    pr::MeshOptions tight;
    tight.ear_clip_work = 200; // a few hexagons' worth
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh cut = pr::load_mesh(file, tight);
    const std::string said = ::testing::internal::GetCapturedStderr();
    const std::size_t at = said.find(" concave polygons too large to clip");
    ASSERT_NE(at, std::string::npos) << said;
    const int fanned = std::stoi(said.substr(said.rfind(' ', at - 1) + 1));
    EXPECT_GT(fanned, 10) << said;
    EXPECT_LT(fanned, 40) << said;
    EXPECT_EQ(cut.triangle_count(), 40u * 4u + 2u);
    // A budget of nothing still fans a square without a word (convex: no clipping).
    tight.ear_clip_work = 0;
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("square.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"), tight);
    EXPECT_EQ(::testing::internal::GetCapturedStderr().find("fan"), std::string::npos);
}

// A convex polygon with a flat corner (a point on a side) is clipped, not fanned from its first
// corner: that fan's first triangle had no area and was dropped, and the sides through the flat
// corner were no longer shared with the neighbour's (an open edge where the mesh was closed).
// An outline that crosses itself has no inside to keep to: what it is triangulated into may cover
// area outside its lobes, and loading says so (forty-first session: a bow tie drew three quarters
// of its square without a word; found by an exploratory session). Simple concave outlines do not.
TEST(MeshLoad, PolygonsCrossingThemselvesAreSaid)
{
    TempDir dir;
    const auto warning = [&](const std::string& name, const std::string& obj) {
        ::testing::internal::CaptureStderr();
        pr::load_mesh(dir.write(name, obj));
        return ::testing::internal::GetCapturedStderr();
    };
    const std::string square = "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\n";
    // Lobes of equal area (no net area: no plane), of unequal area (0.4 and 6.4: ear clipping's
    // triangles add up to more than the outline's net area), and a pentagram (its middle counted
    // twice by the outline).
    const std::string tie = warning("tie.obj", square + "f 1 2 4 3\n");
    EXPECT_NE(tie.find("tie.obj: 1 polygon's outline crosses itself (a bow tie?)"), std::string::npos);
    // Its own triangles, folded onto each other by its triangulation, are not a two-sided sheet
    // (said so too until the forty-ninth session; found by an exploratory session).
    EXPECT_EQ(tie.find("back to back"), std::string::npos) << tie;
    EXPECT_NE(warning("uneven.obj", "v 0 0 0\nv 4 4 0\nv 4 0 0\nv 0 1 0\nf 1 2 3 4\n")
                  .find("uneven.obj: 1 polygon's outline crosses itself"),
              std::string::npos);
    std::string star;
    for (int k = 0; k < 5; ++k)
        star += "v " + std::to_string(std::cos(1.2566371 * k)) + " " + std::to_string(std::sin(1.2566371 * k)) + " 0\n";
    EXPECT_NE(warning("star.obj", star + "f 1 3 5 2 4\nf 1 2 3 4 5\n").find("star.obj: 1 polygon's outline crosses itself"),
              std::string::npos);
    // Simple ones, concave or with a straight run of corners: nothing said.
    for (const auto& [name, obj] : {std::pair<std::string, std::string>{"quad.obj", square + "f 1 2 3 4\n"},
                                    {"l.obj", "v 0 2 0\nv 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nf 1 2 3 4 5 6\n"},
                                    {"dart.obj", "v 0 0 0\nv 2 1 0\nv 0 2 0\nv 1 1 0\nf 1 2 3 4\n"},
                                    {"run.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\nv 3 1 0\nv 0 1 0\nf 1 2 3 4 5 6\n"}})
        EXPECT_EQ(warning(name, obj).find("crosses itself"), std::string::npos) << name;
}

TEST(MeshLoad, FlatCornerIsNotAFansFirstTriangle)
{
    TempDir dir;
    // A rectangle whose bottom side runs through 69 corners (exactly on the line: whole numbers),
    // 73 corners in all: past 64, where a convex-looking polygon was fanned from corner 0.
    std::string text;
    const int bottom = 70;
    for (int i = 0; i <= bottom; ++i) text += "v " + std::to_string(i) + " 0 0\n";
    text += "v " + std::to_string(bottom) + " 1 0\nv 0 1 0\nf";
    const int n = bottom + 3;
    for (int i = 0; i < n; ++i) text += " " + std::to_string(i + 1);
    const pr::PreparedMesh m = pr::load_mesh(dir.write("flat.obj", text + "\n"));
    EXPECT_EQ(m.dropped_triangles, 0u);
    EXPECT_EQ(m.triangle_count(), std::size_t(n - 2));
    double area = 0.0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) area += 0.5 * double(face_normal(m, t).z);
    EXPECT_NEAR(area, double(bottom), 1e-3);
}

TEST(MeshLoad, ObjMixedFacesWithAndWithoutUvs)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "m.obj",
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\nf 1 3 4\n"));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 2u);
    EXPECT_FALSE(m.had_uvs); // some UVs had to be generated
}

TEST(MeshLoad, OffAsciiWithPolygons)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "m.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 2 0\n4 0 1 2 3\n3 3 2 4\n"));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 3u);
    EXPECT_EQ(m.weld_count, 5u);
    EXPECT_FALSE(m.had_uvs);
}

TEST(MeshLoad, OffWithTextureCoordinatesAndNormals)
{
    TempDir dir;
    const pr::PreparedMesh st = pr::load_mesh(
        dir.write("st.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n3 0 1 2\n"));
    EXPECT_TRUE(st.had_uvs);
    for (const pr::MeshVertex& v : st.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
    const pr::PreparedMesh n = pr::load_mesh(
        dir.write("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"));
    EXPECT_TRUE(n.had_normals);
    EXPECT_FALSE(n.had_uvs);
}

// A binary file named .obj (an image renamed) said "contains no faces".
TEST(MeshErrors, BinaryDataNamedObjIsSaid)
{
    TempDir dir;
    const std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
    const fs::path p = dir.write("image.obj", png + std::string(64, 'x'));
    EXPECT_ERROR_MENTIONS(load_error(p), p, "holds binary data, not OBJ text (another kind of file named .obj?)");
    // UTF-16 text, with its byte-order mark or without, is said as such.
    std::string utf16 = "\xFF\xFE";
    for (char c : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) utf16 += std::string{c, '\0'};
    for (const char* name : {"u.obj", "u.off"}) {
        const fs::path u = dir.write(name, utf16);
        EXPECT_ERROR_MENTIONS(load_error(u), u, "is UTF-16 text; the reader takes ASCII or UTF-8: save it as UTF-8");
    }
    const fs::path bare = dir.write("b.obj", utf16.substr(2));
    EXPECT_ERROR_MENTIONS(load_error(bare), bare, "is UTF-16 text");
    // Big-endian without the mark (it was read as another kind of file; fifty-first session).
    std::string big;
    for (char c : std::string("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")) big += std::string{'\0', c};
    for (const char* name : {"be.off", "be.obj", "be.ply"}) {
        const fs::path be = dir.write(name, big);
        EXPECT_ERROR_MENTIONS(load_error(be), be, "is UTF-16 text; the reader takes ASCII or UTF-8: save it as UTF-8");
    }
}

// Geomview's OFF allows '#' comments anywhere: they were refused with messages that blamed
// something else ("the counts must be on the line after 'OFF'" for `OFF # cube`; found by an
// exploratory session, thirty-third). Read past now, in every variant's values; in a binary OFF
// only the header line is text.
TEST(MeshLoad, OffCommentsAreReadPast)
{
    TempDir dir;
    const auto same = [](const pr::PreparedMesh& a, const pr::PreparedMesh& b) {
        ASSERT_EQ(a.vertices.size(), b.vertices.size());
        ASSERT_EQ(a.triangle_count(), b.triangle_count());
        for (std::size_t i = 0; i < a.vertices.size(); ++i) {
            EXPECT_EQ(a.vertices[i].position, b.vertices[i].position);
            EXPECT_EQ(a.vertices[i].uv, b.vertices[i].uv);
        }
    };
    const std::string plain = "STCOFF\n4 2 0\n0 0 0 1 0 0 0 0\n1 0 0 0 1 0 1 0\n1 1 0 0 0 1 1 1\n"
                              "0 1 0 1 1 1 0 1\n3 0 1 2\n3 0 2 3\n";
    const std::string commented = "STCOFF # a square\n# counts next\n4 2 0 # no edges\n0 0 0 1 0 0 0 0\t# red\n"
                                  "  # between vertices\n1 0 0 0 1 0 1 0 #green\n1 1 0 0 0 1 1 1\n"
                                  "0 1 0 1 1 1 0 1 # white\n3 0 1 2 # first\n#\n3 0 2 3\n# end\n";
    const pr::PreparedMesh a = pr::load_mesh(dir.write("plain.off", plain));
    EXPECT_TRUE(a.had_uvs);
    same(a, pr::load_mesh(dir.write("commented.off", commented)));
    // Errors still name the file's own line (line 7 is the fourth vertex's).
    EXPECT_ERROR_MENTIONS(load_error(dir.write("bad.off", "OFF # x\n# y\n4 1 0\n0 0 0\n1 0 0 # z\n1 1 0\nq 1 0\n3 0 1 2\n")),
                          dir.path() / "bad.off", "line 7: vertex position is not three finite numbers");
    EXPECT_ERROR_MENTIONS(load_error(dir.write("first.off", "# made by hand\nOFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")),
                          dir.path() / "first.off", "line 1 is blank or a comment: the OFF header line must be the file's first");
    // Classic Mac line ends are said as such, a comment or not (the comment ran to the file's end).
    EXPECT_ERROR_MENTIONS(load_error(dir.write("mac.off", "OFF # mac\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r")),
                          dir.path() / "mac.off", "uses CR line ends (classic Mac OS)");
    // Binary: a comment after the header; the data's '#' bytes (0x23) are values.
    std::vector<char> b;
    const std::string head = "OFF BINARY # three corners\n";
    b.insert(b.end(), head.begin(), head.end());
    for (std::int32_t i : {3, 1, 0}) put(b, i);
    const float hashes = std::bit_cast<float>(std::uint32_t(0x3f802323)); // 1.00107…, bytes 23 23 80 3f
    for (float f : {0.f, 0.f, 0.f, hashes, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, f);
    for (std::int32_t i : {3, 0, 1, 2}) put(b, i);
    const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes("b.off", b));
    ASSERT_EQ(m.triangle_count(), 1u);
    float x_max = 0.0f;
    for (const pr::MeshVertex& v : m.vertices) x_max = std::max(x_max, v.position.x);
    EXPECT_EQ(x_max, hashes);
}

TEST(MeshLoad, OffBinary)
{
    TempDir dir;
    std::vector<char> b;
    const std::string head = "OFF BINARY\n";
    b.insert(b.end(), head.begin(), head.end());
    put<std::int32_t>(b, 3);
    put<std::int32_t>(b, 1);
    put<std::int32_t>(b, 0);
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, f);
    for (std::int32_t i : {3, 0, 1, 2}) put(b, i);
    const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes("m.off", b));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 1u);
}

// OpenMesh reads an ASCII OFF vertex's normal from the stream, past the line's end, and its
// colour and texture coordinate from the rest of the line: a NOFF line without its normal shifted
// every value after it ("face 0 has an out-of-range vertex index 32519"), an STOFF line without
// its t read an undefined one. Each is refused with its line.
TEST(MeshLoad, OffVertexLinesMissingValuesAreRefused)
{
    TempDir dir;
    const std::string faces = "3 0 1 2\n";
    auto message = [&](const std::string& name, const std::string& text) {
        return prtest::error_of([&] { pr::load_mesh(dir.write(name, text + faces)); }).problem();
    };
    EXPECT_EQ(message("n.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0\n0 1 0 0 0 1\n"),
              "line 4: a NOFF vertex needs x y z nx ny nz (3 values here)");
    EXPECT_EQ(message("st.off", "STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 1 0\n0 1 0 0\n"),
              "line 5: a STOFF vertex needs x y z s t (4 values here)");
    // More values than s t without a colour: OpenMesh took the first two ((0.9, s), silently).
    EXPECT_EQ(message("st3.off", "STOFF\n3 1 0\n0 0 0 0.9 0 0\n1 0 0 0.9 1 0\n0 1 0 0.9 0 1\n"),
              "line 3: a STOFF vertex needs x y z s t (6 values here; a colour before s t needs a C in the header: "
              "STCOFF)");
    EXPECT_EQ(message("stn3.off", "STNOFF\n3 1 0\n0 0 0 0 0 1 0.9 0 0\n1 0 0 0 0 1 0.9 1 0\n0 1 0 0 0 1 0.9 0 1\n"),
              "line 3: a STNOFF vertex needs x y z nx ny nz s t (9 values here; a colour before s t needs a C in the "
              "header: STCNOFF)");
    // With a colour (0, 1, 3 or 4 numbers) before s t: 2, 3, 5 or 6 values after x y z.
    EXPECT_EQ(message("stc.off", "STCOFF\n3 1 0\n0 0 0 0 0\n1 0 0 9 1 0\n0 1 0 1 1 0 1\n"),
              "line 5: a STCOFF vertex needs x y z [colour: 0, 1, 3 or 4 numbers] s t (7 values "
              "here)");
    const pr::PreparedMesh ok = pr::load_mesh(dir.write(
        "ok.off", "STCNOFF\n3 1 0\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 9 1 0\n0 1 0 0 0 1 1 1 1 0 1\n" +
                      faces));
    EXPECT_TRUE(ok.had_uvs);
    for (const pr::MeshVertex& v : ok.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
    // Words where numbers are read (found by a review: an undefined UV, a garbage index).
    EXPECT_EQ(message("sta.off", "STOFF\n3 1 0\n0 0 0 a b\n1 0 0 1 0\n0 1 0 0 1\n"),
              "line 3: a STOFF vertex needs x y z s t, with numbers ('a' here)");
    EXPECT_EQ(message("nx.off", "NOFF\n3 1 0\n0 0 0 0 0 x\n1 0 0 0 0 1\n0 1 0 0 0 1\n"),
              "line 3: a NOFF vertex needs x y z nx ny nz, with numbers ('x' here)");
    // OpenMesh tells a colour's integers from floats by its first value's point and reads the rest
    // alike: `1 0 0 0.5` left ".5" for s, and (0.5, 0.2) was read for (0.2, 0.8), silently (found
    // by an exploratory session, fifty-first). The colour is blanked for it; a word in a colour
    // is refused, as it left the texture coordinate undefined.
    const pr::PreparedMesh mixed = pr::load_mesh(dir.write(
        "mixed.off", "STCOFF\n3 1 0\n0 0 0 1 0 0 0.5 0 0\n1 0 0 1 0 0.5 1 0\n0 1 0 1 0.5 0 0 1\n" + faces));
    for (const pr::MeshVertex& v : mixed.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
    EXPECT_EQ(message("word.off", "STCOFF\n3 1 0\n0 0 0 1 x 0 0 0\n1 0 0 1 0\n0 1 0 0 1\n"),
              "line 3: a STCOFF vertex needs x y z [colour: 0, 1, 3 or 4 numbers] s t, with numbers ('x' here)");
    EXPECT_EQ(message("cword.off", "COFF\n3 1 0\n0 0 0 1 0 nan\n1 0 0\n0 1 0\n"),
              "line 3: a COFF vertex needs x y z [colour: 0, 1, 3 or 4 numbers], with numbers ('nan' here)");
    // OpenMesh counts a line's colour values by single spaces: tabs and double spaces read the
    // colour as the texture coordinate ((255, 0) for (0, 0)).
    const pr::PreparedMesh spaced = pr::load_mesh(dir.write(
        "spaced.off", "STCOFF\n3 1 0\n0 0 0\t255 0 0\t0 0\n1 0 0  255  0 0  1 0\n0 1 0 255 0 0 0 1\n" + faces));
    for (const pr::MeshVertex& v : spaced.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
}

// Binary OFF variants: a vertex is 3 floats, 3 more with N, 2 more with ST; the size check counts
// them (a truncated NOFF BINARY passed it and OpenMesh read past the end). Binary colours are
// refused: OpenMesh skips face colours it was not asked for and misreads every face after.
TEST(MeshLoad, OffBinaryVariants)
{
    TempDir dir;
    auto binary = [](const std::string& head, const std::vector<float>& values) {
        std::vector<char> b(head.begin(), head.end());
        for (std::int32_t i : {3, 1, 0}) put<std::int32_t>(b, i);
        for (float f : values) put(b, f);
        for (std::int32_t i : {3, 0, 1, 2}) put<std::int32_t>(b, i);
        return b;
    };
    const pr::PreparedMesh n = pr::load_mesh(dir.write_bytes(
        "n.off", binary("NOFF BINARY\n", {0, 0, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1})));
    expect_sane(n);
    EXPECT_EQ(n.triangle_count(), 1u);
    EXPECT_EQ(n.bbox_max, glm::vec3(1, 1, 0));
    const pr::PreparedMesh st = pr::load_mesh(dir.write_bytes(
        "st.off", binary("STOFF BINARY\n", {0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1})));
    EXPECT_TRUE(st.had_uvs);
    for (const pr::MeshVertex& v : st.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
    EXPECT_TRUE(prtest::contains(
        prtest::error_of([&] {
            pr::load_mesh(dir.write_bytes("short.off",
                                          binary("NOFF BINARY\n", {0, 0, 0, 1, 0, 0, 0, 1, 0})));
        }).problem(),
        "more than a file of"));
    EXPECT_EQ(prtest::error_of([&] {
                  pr::load_mesh(dir.write_bytes(
                      "c.off", binary("COFF BINARY\n", {0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0,
                                                          1, 0, 0, 0, 0})));
              }).problem(),
              "binary COFF (colours) is not supported; use the ASCII variant or OFF BINARY");
}

// Binary OFF as Geomview defines it: big-endian words, and after each face's indices a colour
// count and that many floats. It was refused ("header claims 67108864 vertices …", the counts
// read little-endian), and the colour counts misread ("face 1 has fewer than 3 vertices").
TEST(MeshLoad, OffBinaryGeomviewLayouts)
{
    TempDir dir;
    // A square of two faces (a triangle and a quad's worth: 3 and 4 corners), with s t.
    const std::vector<float> vertices = {0, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1, 1, 0, 1, 1, 0, 1, 0, 0, 1};
    const std::vector<std::vector<std::int32_t>> faces = {{0, 1, 2}, {0, 2, 3}};
    auto file = [&](bool big, bool colour_counts) {
        std::vector<char> b;
        const std::string head = "STOFF BINARY\n";
        b.insert(b.end(), head.begin(), head.end());
        auto word = [&](auto value) {
            std::vector<char> w;
            put(w, value);
            if (big) std::reverse(w.begin(), w.end());
            b.insert(b.end(), w.begin(), w.end());
        };
        for (std::int32_t i : {4, 2, 0}) word(i);
        for (float f : vertices) word(f);
        for (std::size_t f = 0; f < faces.size(); ++f) {
            word(std::int32_t(faces[f].size()));
            for (std::int32_t i : faces[f]) word(i);
            if (!colour_counts) continue;
            word(std::int32_t(f == 0 ? 0 : 3)); // the second face with an RGB colour
            if (f == 1)
                for (float c : {0.5f, 0.25f, 1.0f}) word(c);
        }
        return b;
    };
    const pr::PreparedMesh plain = pr::load_mesh(dir.write_bytes("le.off", file(false, false)));
    for (const auto& [big, counts] : {std::pair{false, true}, {true, false}, {true, true}}) {
        const std::string name = std::string(big ? "be" : "le") + (counts ? "_counts" : "") + ".off";
        const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes(name, file(big, counts)));
        ASSERT_EQ(m.triangle_count(), 2u) << name;
        ASSERT_EQ(m.vertices.size(), plain.vertices.size()) << name;
        EXPECT_TRUE(m.had_uvs) << name;
        for (std::size_t i = 0; i < m.vertices.size(); ++i) {
            EXPECT_EQ(m.vertices[i].position, plain.vertices[i].position) << name;
            EXPECT_EQ(m.vertices[i].uv, plain.vertices[i].uv) << name;
        }
        EXPECT_EQ(m.indices, plain.indices) << name;
    }
    // A big-endian file cut short, or with bytes after its last face, is refused as one whose
    // faces do not fit (it said "header claims 67108864 vertices …", the counts read the other way).
    std::vector<char> cut = file(true, true);
    cut.resize(cut.size() - 6);
    std::vector<char> padded = file(true, true);
    padded.insert(padded.end(), 8, '\0');
    for (const auto& [name, bytes] : {std::pair{"cut.off", cut}, {"padded.off", padded}})
        EXPECT_TRUE(prtest::contains(prtest::error_of([&] { pr::load_mesh(dir.write_bytes(name, bytes)); }).problem(),
                                     "big-endian binary OFF (Geomview's layout) whose faces do not end where the file does"))
            << name;
}

TEST(MeshLoad, PlyAsciiWithUvsAndNormals)
{
    TempDir dir;
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "m.ply",
        "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty float x\n"
        "property float y\nproperty float z\nproperty float nx\nproperty float ny\n"
        "property float nz\nproperty float u\nproperty float v\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n"
        "0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n"));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 2u);
    EXPECT_TRUE(m.had_uvs);
    EXPECT_TRUE(m.had_normals);
    for (const pr::MeshVertex& v : m.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
}

// Texture coordinates under two names or half of one: OpenMesh's reader takes u and s as the first
// coordinate, v and t as the second, the later over the earlier, and one without the other as a
// pair with 0 (found by an exploratory session, forty-first: both pairs read the last silently,
// u alone read as (u, 0)). A whole pair is read, u v first, and half a pair not at all (said).
TEST(MeshLoad, PlyTextureCoordinatesAreReadAsWholePairs)
{
    TempDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string tail = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    // Each vertex: x y z, then its named values: the named pair (the true one) is x y, the
    // others 0.3.
    const auto load = [&](const std::vector<std::string>& names, std::string& err) {
        std::string text = head;
        for (const std::string& n : names) text += "property float " + n + "\n";
        text += tail;
        const float xyz[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
        for (const auto& v : xyz) {
            text += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " + std::to_string(v[2]);
            for (const std::string& n : names)
                text += " " + (n == names[0] ? std::to_string(v[0]) : (n == names[1] ? std::to_string(v[1]) : "0.3"));
            text += "\n";
        }
        text += "3 0 1 2\n";
        ::testing::internal::CaptureStderr();
        // (A file of its own each: a warning is said once per line.)
        std::string file;
        for (const std::string& n : names) file += n;
        pr::PreparedMesh m = pr::load_mesh(dir.write(file + ".uv.ply", text));
        err = ::testing::internal::GetCapturedStderr();
        return m;
    };
    std::string err;
    // A whole pair, and the other names left unread: u v before s t, whatever their order.
    for (const std::vector<std::string>& names : std::vector<std::vector<std::string>>{
             {"u", "v", "s", "t"}, {"u", "v", "t", "s"}, {"s", "t", "u"}, {"u", "v", "s"}, {"u", "t"}}) {
        const pr::PreparedMesh m = load(names, err);
        SCOPED_TRACE(names[0] + names[1] + (names.size() > 2 ? names[2] : ""));
        EXPECT_TRUE(m.had_uvs);
        for (const pr::MeshVertex& v : m.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position));
        if (names.size() > 2)
            EXPECT_NE(err.find(".uv.ply: vertex properties " + names[0] + " " + names[1] + " and "), std::string::npos)
                << err;
        else
            EXPECT_EQ(err.find("texture coordinates"), std::string::npos) << err;
    }
    // Half a pair: not read, UVs generated.
    for (const std::vector<std::string>& names :
         std::vector<std::vector<std::string>>{{"u", "q"}, {"t", "q"}, {"u", "s"}}) {
        const pr::PreparedMesh m = load(names, err);
        SCOPED_TRACE(names[0] + names[1]);
        EXPECT_FALSE(m.had_uvs);
        EXPECT_NE(err.find(" without " + std::string(names[0] == "t" ? "u or s" : "v or t") +
                           ": not read as texture coordinates"),
                  std::string::npos)
            << err;
    }
}

TEST(MeshLoad, PlyBinaryLittleEndian)
{
    TempDir dir;
    std::vector<char> b;
    const std::string head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    b.insert(b.end(), head.begin(), head.end());
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, f);
    put<std::uint8_t>(b, 3);
    for (std::int32_t i : {0, 1, 2}) put(b, i);
    const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes("m.ply", b));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_GT(face_normal(m, 0).z, 0.0f);
}

TEST(MeshLoad, PlyBinaryBigEndian)
{
    TempDir dir;
    std::vector<char> b;
    const std::string head =
        "ply\nformat binary_big_endian 1.0\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    b.insert(b.end(), head.begin(), head.end());
    auto put_be = [&b](const void* p) {
        const char* c = static_cast<const char*>(p);
        for (int i = 3; i >= 0; --i) b.push_back(c[i]);
    };
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put_be(&f);
    put<std::uint8_t>(b, 3);
    for (std::int32_t i : {0, 1, 2}) put_be(&i);
    const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes("m.ply", b));
    expect_sane(m);
    EXPECT_EQ(m.bbox_max, glm::vec3(1.0f, 1.0f, 0.0f));
}

namespace {

// A regular octahedron as a triangle soup, outward and counter-clockwise.
const float kOcta[8][9] = {
    {1, 0, 0, 0, 1, 0, 0, 0, 1},    {0, 1, 0, -1, 0, 0, 0, 0, 1},  {-1, 0, 0, 0, -1, 0, 0, 0, 1},
    {0, -1, 0, 1, 0, 0, 0, 0, 1},   {0, 1, 0, 1, 0, 0, 0, 0, -1},  {-1, 0, 0, 0, 1, 0, 0, 0, -1},
    {0, -1, 0, -1, 0, 0, 0, 0, -1}, {1, 0, 0, 0, -1, 0, 0, 0, -1},
};

std::string octa_stl_ascii()
{
    std::string s = "solid octa\n";
    for (const auto& t : kOcta) {
        s += "  facet normal 0 0 0\n    outer loop\n";
        for (int k = 0; k < 3; ++k)
            s += "      vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) +
                 " " + std::to_string(t[3 * k + 2]) + "\n";
        s += "    endloop\n  endfacet\n";
    }
    return s + "endsolid octa\n";
}

std::vector<char> octa_stl_binary(std::uint32_t claimed = 8, const char* header = "binary octa")
{
    std::vector<char> b(80, ' ');
    std::memcpy(b.data(), header, std::strlen(header));
    put(b, claimed);
    for (const auto& t : kOcta) {
        for (int k = 0; k < 3; ++k) put(b, 0.0f);
        for (float f : t) put(b, f);
        put<std::uint16_t>(b, 0);
    }
    return b;
}

void expect_smooth_octahedron(const pr::PreparedMesh& m)
{
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 8u);
    // STL shares no vertices; welding by position is what joins the triangles.
    EXPECT_EQ(m.weld_count, 6u);
    for (const pr::MeshVertex& v : m.vertices) {
        EXPECT_NEAR(glm::distance(v.normal, v.position), 0.0f, 1e-5f);
    }
}

} // namespace

TEST(MeshLoad, StlAsciiIsWelded)
{
    TempDir dir;
    expect_smooth_octahedron(pr::load_mesh(dir.write("o.stl", octa_stl_ascii())));
}

// Some CAD exporters write ASCII STL in capitals ("SOLID", "FACET NORMAL", "OUTER LOOP",
// "VERTEX"), which OpenMesh reads; it was refused ("does not start with 'solid'").
TEST(MeshLoad, StlAsciiInCapitals)
{
    TempDir dir;
    std::string upper = octa_stl_ascii();
    for (char& c : upper) c = char(std::toupper(static_cast<unsigned char>(c)));
    expect_smooth_octahedron(pr::load_mesh(dir.write("O.STL", upper)));
    expect_smooth_octahedron(pr::load_mesh(dir.write("bom.stl", "\xEF\xBB\xBF" + upper)));
}

TEST(MeshLoad, StlBinaryIsWelded)
{
    TempDir dir;
    expect_smooth_octahedron(pr::load_mesh(dir.write_bytes("o.stl", octa_stl_binary())));
    // A binary header that happens to start with "solid" is still binary (size matches).
    expect_smooth_octahedron(
        pr::load_mesh(dir.write_bytes("s.stl", octa_stl_binary(8, "solid by exporter"))));
}

// Cut short, a binary STL whose header starts with "solid" was taken for ASCII and said "contains
// no faces" (found by an exploratory session).
TEST(MeshErrors, BinaryStlStartingWithSolidCutShortSaysSo)
{
    TempDir dir;
    std::vector<char> b = octa_stl_binary(8, "solid by exporter");
    b.resize(b.size() - 10);
    const fs::path p = dir.write_bytes("s.stl", b);
    EXPECT_ERROR_MENTIONS(load_error(p), p,
                          "starts with 'solid' but holds binary data: a binary STL whose header claims 8 triangles "
                          "(484 bytes), but the file has 474");
}

TEST(MeshLoad, ExtensionIsCaseInsensitive)
{
    TempDir dir;
    EXPECT_EQ(pr::load_mesh(dir.write("Q.OBJ", kQuadObj)).triangle_count(), 2u);
}

TEST(MeshLoad, NonManifoldEdgeKeepsEveryFace)
{
    TempDir dir;
    // Three triangles on one edge: OpenMesh's own mesh would reject or split the third.
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "fin.obj",
        "v 0 0 0\nv 1 0 0\nv 0.5 1 0\nv 0.5 -1 0\nv 0.5 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("non-manifold"), std::string::npos) << warnings;
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 3u);
    EXPECT_EQ(m.weld_count, 5u);
}

TEST(MeshLoad, WarnsAboutInconsistentOrientationAndGeneratedUvs)
{
    TempDir dir;
    // The second triangle runs along the shared edge 1-2 in the same direction as the first.
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(
        dir.write("flip.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 -1 0\nf 1 2 3\nf 1 2 4\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("1 face wound against its neighbours (the welded normals cancel there) turned so "
                            "that each piece winds one way (a closed one outward, or inward as a cavity)"),
              std::string::npos)
        << warnings;
    EXPECT_NE(warnings.find("generated box-projected UVs"), std::string::npos) << warnings;
    EXPECT_EQ(warnings.find("prismrelief: warning: " + (dir.path() / "flip.obj").string()), 0u);
    expect_sane(m);
    // Turned: both now face one way, and the welded normals agree with them.
    EXPECT_GT(face_normal(m, 0).z * face_normal(m, 1).z, 0.0f);
    for (const pr::MeshVertex& v : m.vertices) EXPECT_NEAR(std::abs(v.normal.z), 1.0f, 1e-6f);
}

// Faces wound against their neighbours are turned, piece by piece, to the winding of most of the
// piece's area (a grid with every third quad reversed drew its welded normals cancelling, and the
// walk lost whole triangles: IoU 0.78); a piece that cannot be wound one way keeps its winding.
TEST(MeshLoad, FacesWoundAgainstTheirNeighboursAreTurned)
{
    TempDir dir;
    std::string grid;
    const int n = 6;
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) grid += "v " + std::to_string(i) + " 0 " + std::to_string(-j) + "\n";
    int reversed = 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            const int a = j * (n + 1) + i + 1, b = a + 1, c = a + n + 2, d = a + n + 1;
            const bool flip = (j * n + i) % 3 == 0;
            reversed += flip;
            grid += flip ? "f " + std::to_string(a) + " " + std::to_string(d) + " " + std::to_string(c) + " " + std::to_string(b) + "\n"
                         : "f " + std::to_string(a) + " " + std::to_string(b) + " " + std::to_string(c) + " " + std::to_string(d) + "\n";
        }
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("grid.obj", grid));
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find(std::to_string(reversed) + " faces wound against their neighbours"), std::string::npos) << said;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) EXPECT_GT(face_normal(m, t).y, 0.0f) << t;
    for (const pr::MeshVertex& v : m.vertices) EXPECT_NEAR(v.normal.y, 1.0f, 1e-6f);

    // Two closed pieces: a large tetrahedron wound outward and a small one with three of its four
    // faces wound inward (most of its area). A closed piece winds outward whatever most of its
    // area does: by area the small one turned inward, and the mesh's positive total volume did
    // not reverse it back (found by a review).
    const std::string tets = "v 0 0 0\nv 4 0 0\nv 0 4 0\nv 0 0 4\n"
                             "v 10 0 0\nv 11 0 0\nv 10 1 0\nv 10 0 1\n"
                             "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                             "f 5 7 6\nf 5 8 6\nf 5 7 8\nf 6 8 7\n";
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh two = pr::load_mesh(dir.write("tets.obj", tets));
    const std::string said_tets = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said_tets.find("3 faces wound against their neighbours"), std::string::npos) << said_tets;
    for (const bool small : {false, true}) {
        double volume = 0.0;
        for (std::size_t t = 0; t < two.triangle_count(); ++t) {
            const glm::vec3 a = two.vertices[two.indices[3 * t]].position;
            if ((a.x >= 10.0f) != small) continue;
            const glm::vec3 b = two.vertices[two.indices[3 * t + 1]].position;
            const glm::vec3 c = two.vertices[two.indices[3 * t + 2]].position;
            volume += double(glm::dot(a, glm::cross(b, c))) / 6.0;
        }
        EXPECT_NEAR(volume, small ? 1.0 / 6.0 : 64.0 / 6.0, 1e-4) << (small ? "small" : "large");
    }

    // A Moebius strip of 12 quads: no winding suits every face; kept as in the file.
    std::string strip;
    const int q = 12;
    for (int k = 0; k < q; ++k)
        for (const int side : {-1, 1}) {
            const double a = 2.0 * 3.14159265358979 * k / q, w = 0.3 * side;
            const double r = 1.0 + w * std::cos(a / 2);
            strip += "v " + std::to_string(r * std::cos(a)) + " " + std::to_string(w * std::sin(a / 2)) + " " +
                     std::to_string(r * std::sin(a)) + "\n";
        }
    for (int k = 0; k < q; ++k) {
        const int a0 = 2 * k + 1, a1 = 2 * k + 2;
        // The last quad joins the strip's ends with the sides exchanged (the half twist).
        const int b0 = k + 1 < q ? 2 * k + 3 : 2, b1 = k + 1 < q ? 2 * k + 4 : 1;
        strip += "f " + std::to_string(a0) + " " + std::to_string(b0) + " " + std::to_string(b1) + " " + std::to_string(a1) + "\n";
    }
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("moebius.obj", strip));
    const std::string said_strip = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said_strip.find("1 piece cannot be wound one way (a Moebius strip?): kept as in the file"),
              std::string::npos)
        << said_strip;
}

// A closed tetrahedron wound clockwise seen from outside (negative volume): reversed with a
// warning, so that its faces and welded normals point out; wound the usual way, no warning.
TEST(MeshLoad, ClosedMeshWoundInwardIsReversed)
{
    TempDir dir;
    const std::string points = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    for (const bool inward : {true, false}) {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write(
            "tet.obj", points + (inward ? "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n" : "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n")));
        const std::string warnings = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(warnings.find("wind clockwise seen from outside") != std::string::npos, inward) << warnings;
        expect_sane(m);
        const glm::vec3 centre(0.25f);
        for (std::size_t t = 0; t < m.triangle_count(); ++t)
            EXPECT_GT(glm::dot(face_normal(m, t), m.vertices[m.indices[3 * t]].position - centre), 0.0f) << t;
        for (const pr::MeshVertex& v : m.vertices) EXPECT_GT(glm::dot(v.normal, v.position - centre), 0.0f);
    }
}

namespace {

// Each face turned towards `centre` (the faces' normals and the welded normals point away from it).
void expect_outward(const pr::PreparedMesh& m, glm::vec3 centre)
{
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        EXPECT_GT(glm::dot(face_normal(m, t), m.vertices[m.indices[3 * t]].position - centre), 0.0f) << t;
    for (const pr::MeshVertex& v : m.vertices) EXPECT_GT(glm::dot(v.normal, v.position - centre), 0.0f);
}

const char* kTetPoints = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
const char* kTetInward = "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";

} // namespace

// A face listed twice with the same winding is a repeat, not a flip: said so, and dropped (it
// was "4 edges join faces of opposite orientation" and a non-manifold edge, and kept).
TEST(MeshLoad, RepeatedFaceIsDroppedAndNotCalledAFlip)
{
    TempDir dir;
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("dup.obj", std::string(kQuadObj) + "f 1 2 3 4\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("dropped 1 face that repeats another face"), std::string::npos) << warnings;
    EXPECT_EQ(warnings.find("opposite orientation"), std::string::npos) << warnings;
    EXPECT_EQ(warnings.find("non-manifold"), std::string::npos) << warnings;
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 2u);
}

// A two-sided sheet (a quad and its reversed copy): the copy is dropped and the first side's
// normal kept (the two sides cancelled, and the fallback direction, from the box's centre, lay in
// the sheet: the displacement slid sideways and no technique showed relief).
TEST(MeshLoad, TwoSidedSheetKeepsItsFirstSide)
{
    TempDir dir;
    for (const bool front_first : {true, false}) {
        const std::string faces = front_first ? "f 1 2 3 4\nf 4 3 2 1\n" : "f 2 1 4 3\nf 1 2 3 4\n";
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write(front_first ? "two_a.obj" : "two_b.obj",
                                                           "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + faces));
        const std::string warnings = ::testing::internal::GetCapturedStderr();
        EXPECT_NE(warnings.find("1 face repeats another face with the opposite winding"), std::string::npos)
            << warnings;
        EXPECT_EQ(warnings.find("no defined normal"), std::string::npos) << warnings;
        expect_sane(m);
        EXPECT_EQ(m.triangle_count(), 2u);
        for (const pr::MeshVertex& v : m.vertices)
            EXPECT_EQ(v.normal, glm::vec3(0, 0, front_first ? 1.0f : -1.0f));
    }
}

// One stray repeated face no longer keeps a closed mesh wound inward from being reversed (it
// made three faces on each of its edges: not reversed, every bump a dimple, and no word of it).
TEST(MeshLoad, ClosedMeshWoundInwardWithARepeatedFaceIsReversed)
{
    TempDir dir;
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m =
        pr::load_mesh(dir.write("tet.obj", std::string(kTetPoints) + kTetInward + "f 1 4 2\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("wind clockwise seen from outside"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("reversed"), std::string::npos) << warnings;
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 4u);
    expect_outward(m, glm::vec3(0.25f));
}

// Two closed tetrahedra wound inward that share an edge (four faces on it, two each way: closed
// and consistently oriented, but not manifold) are reversed too, as one closed mesh (half of each
// one's faces lie on that edge: too many for a closed piece of its own).
TEST(MeshLoad, ClosedPiecesWoundInwardTouchingAtAnEdgeAreReversed)
{
    TempDir dir;
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "tets.obj", std::string(kTetPoints) + "v 0 -1 0\nv 0 0 -1\n" + kTetInward +
                        "f 1 2 5\nf 1 6 2\nf 1 5 6\nf 2 6 5\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("wind clockwise seen from outside"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("1 edge is shared by more than two faces"), std::string::npos) << warnings;
    expect_sane(m);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const glm::vec3 a = m.vertices[m.indices[3 * t]].position;
        const glm::vec3 sum = a + m.vertices[m.indices[3 * t + 1]].position + m.vertices[m.indices[3 * t + 2]].position;
        const glm::vec3 centre = sum.y + sum.z > 0.0f ? glm::vec3(0.25f) : glm::vec3(0.25f, -0.25f, -0.25f);
        EXPECT_GT(glm::dot(face_normal(m, t), a - centre), 0.0f) << t;
    }
}

// An octahedron wound inward with a face missing: open, so it keeps its winding (a bowl may be
// meant either way), but it says that it looks inside out, and how much of it.
TEST(MeshLoad, OpenMeshWoundInwardIsNotReversedButSaidSo)
{
    TempDir dir;
    const std::string points = "v 1 0 0\nv -1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nv 0 0 -1\n";
    // Outward: 1 3 5, 3 2 5, 2 4 5, 4 1 5, 3 1 6, 2 3 6, 4 2 6, 1 4 6; reversed, the last left out.
    const std::string inward = "f 1 5 3\nf 3 5 2\nf 2 5 4\nf 4 5 1\nf 3 6 1\nf 2 6 3\nf 4 6 2\n";
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("oct.obj", points + inward));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("appear to wind clockwise seen from outside"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("7 of 7 faces"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("3 open edges"), std::string::npos) << warnings;
    EXPECT_NE(warnings.find("not reversed"), std::string::npos) << warnings;
    expect_sane(m);
    for (std::size_t t = 0; t < m.triangle_count(); ++t)
        EXPECT_LT(glm::dot(face_normal(m, t), m.vertices[m.indices[3 * t]].position), 0.0f) << t;
    // An open mesh wound outward, a flat one, or a half wound inward (a bowl, which may be meant
    // either way: its opening is half its faces' area) say nothing of the kind.
    int k = 0;
    for (const std::string& file : {points + "f 1 3 5\nf 3 2 5\nf 2 4 5\nf 4 1 5\n", std::string(kQuadObj),
                                    points + "f 1 5 3\nf 3 5 2\nf 2 5 4\nf 4 5 1\n"}) {
        ::testing::internal::CaptureStderr();
        pr::load_mesh(dir.write("open" + std::to_string(k++) + ".obj", file));
        const std::string w = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(w.find("clockwise"), std::string::npos) << w;
    }
}

TEST(MeshLoad, DegenerateTrianglesAndIsolatedVerticesAreDropped)
{
    TempDir dir;
    // vertex 5 is isolated; face 2 is collinear (zero area); face 3 repeats a vertex.
    const pr::PreparedMesh m = pr::load_mesh(dir.write(
        "d.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nv 9 9 9\nf 1 2 3\nf 1 2 4\nf 1 1 3\n"));
    expect_sane(m);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.dropped_triangles, 2u);
    EXPECT_EQ(m.vertices.size(), 3u);
    EXPECT_EQ(m.weld_count, 3u);
    EXPECT_EQ(m.bbox_max, glm::vec3(1.0f, 1.0f, 0.0f)); // the isolated vertex is not part of it
}

TEST(MeshLoad, DuplicatePositionsAreWelded)
{
    TempDir dir;
    // Two triangles that do not share indices but share positions (as STL-like exports do).
    const pr::PreparedMesh m = pr::load_mesh(
        dir.write("w.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -0 0 0\n"
                           "f 7 2 3\nf 4 5 6\n"));
    EXPECT_EQ(m.weld_count, 4u);
    EXPECT_EQ(m.vertices.size(), 4u);
}

// ---- errors ----------------------------------------------------------------------------------

TEST(MeshErrors, MissingFile)
{
    TempDir dir;
    const fs::path p = dir.path() / "missing.obj";
    EXPECT_ERROR_MENTIONS(load_error(p), p, "does not exist");
}

TEST(MeshErrors, FolderInsteadOfFile)
{
    TempDir dir;
    const fs::path p = dir.path() / "folder.obj";
    fs::create_directories(p);
    EXPECT_ERROR_MENTIONS(load_error(p), p, "folder");
}

TEST(MeshErrors, UnknownExtensionListsSupportedFormats)
{
    TempDir dir;
    const fs::path p = dir.write("m.3ds", "x");
    const pr::Error e = load_error(p);
    EXPECT_ERROR_MENTIONS(e, p, "unknown mesh format");
    for (const char* ext : {".obj", ".off", ".ply", ".stl"})
        EXPECT_NE(e.problem().find(ext), std::string::npos);
    const fs::path none = dir.write("noext", "x");
    EXPECT_ERROR_MENTIONS(load_error(none), none, "unknown mesh format");
}

TEST(MeshErrors, EmptyFiles)
{
    TempDir dir;
    for (const char* name : {"e.obj", "e.off", "e.ply", "e.stl"}) {
        const fs::path p = dir.write(name, "");
        EXPECT_ERROR_MENTIONS(load_error(p), p, "empty");
    }
    const fs::path only_vertices = dir.write("v.obj", "# nothing but vertices\nv 0 0 0\nv 1 0 0\n");
    EXPECT_ERROR_MENTIONS(load_error(only_vertices), only_vertices, "no faces");
    const fs::path off = dir.write("z.off", "OFF\n0 0 0\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "no faces");
    const fs::path stl = dir.write("z.stl", "solid empty\nendsolid empty\n");
    EXPECT_ERROR_MENTIONS(load_error(stl), stl, "no faces");
}

TEST(MeshErrors, ObjIndexOutOfRange)
{
    TempDir dir;
    const fs::path p = dir.write("r.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 9\n");
    const pr::Error e = load_error(p);
    EXPECT_ERROR_MENTIONS(e, p, "out of range");
    EXPECT_NE(e.problem().find("line 5"), std::string::npos) << e.problem();
    const fs::path neg = dir.write("n.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");
    EXPECT_ERROR_MENTIONS(load_error(neg), neg, "out of range");
    const fs::path zero = dir.write("z.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(zero), zero, "line 4: face corner '0' has an index 0 (OBJ counts from 1, or from -1 back)");
    const fs::path vt = dir.write("t.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/2\n");
    EXPECT_ERROR_MENTIONS(load_error(vt), vt, "texture coordinate index 2 is out of range");
}

TEST(MeshErrors, ObjMalformedLines)
{
    TempDir dir;
    const fs::path two = dir.write("two.obj", "v 0 0 0\nv 1 0 0\nf 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(two), two, "at least 3 vertices");
    const fs::path junk = dir.write("junk.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x\n");
    EXPECT_ERROR_MENTIONS(load_error(junk), junk, "malformed face corner 'x'");
    const fs::path shortv = dir.write("short.obj", "v 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_ERROR_MENTIONS(load_error(shortv), shortv, "line 1");
}

TEST(MeshErrors, NonFiniteCoordinates)
{
    TempDir dir;
    const fs::path obj = dir.write("n.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_ERROR_MENTIONS(load_error(obj), obj,
                          "line 2: vertex position is not three finite numbers");
    const fs::path inf = dir.write("i.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_ERROR_MENTIONS(load_error(inf), inf, "finite");
    const fs::path off = dir.write("n.off", "OFF\n3 1 0\n0 0 0\ninf 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "line 4");
    const fs::path ply = dir.write(
        "n.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                 "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                 "end_header\n0 0 0\n1 NaN 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(ply), ply, "not a finite number");
    const fs::path stla =
        dir.write("n.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                           "vertex nan 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n");
    EXPECT_ERROR_MENTIONS(load_error(stla), stla, "line 5");

    std::vector<char> b = octa_stl_binary();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    std::memcpy(b.data() + 84 + 50 * 3 + 12 + 4, &nan, 4);
    const fs::path stlb = dir.write_bytes("b.stl", b);
    EXPECT_ERROR_MENTIONS(load_error(stlb), stlb, "triangle 3");

    std::vector<char> pb;
    const std::string head =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
        "property float x\nproperty float y\nproperty float z\nelement face 1\n"
        "property list uchar int vertex_indices\nend_header\n";
    pb.insert(pb.end(), head.begin(), head.end());
    for (float f : {0.f, 0.f, 0.f, 1.f, nan, 0.f, 0.f, 1.f, 0.f}) put(pb, f);
    put<std::uint8_t>(pb, 3);
    for (std::int32_t i : {0, 1, 2}) put(pb, i);
    const fs::path plyb = dir.write_bytes("b.ply", pb);
    EXPECT_ERROR_MENTIONS(load_error(plyb), plyb,
                          "vertex 1 has a coordinate that is not a finite number");
}

TEST(MeshErrors, OffFaceIndexOutOfRange)
{
    TempDir dir;
    const fs::path p = dir.write("r.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 7\n");
    EXPECT_ERROR_MENTIONS(load_error(p), p, "face 1 has an out-of-range vertex index");
    const fs::path few = dir.write("f.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    EXPECT_ERROR_MENTIONS(load_error(few), few, "fewer than 3 vertices");
    // Fewer faces than the header says (padded so that the size check passes).
    const fs::path trunc = dir.write("t.off", "OFF\n3 3 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"
                                              "                              \n");
    EXPECT_ERROR_MENTIONS(load_error(trunc), trunc, "file ends after 1 of 3 faces");
    // A vertex count one too large reads the face as a vertex (its values past x y z ignored):
    // the cut is said with that hint (an exploratory session, forty-ninth).
    const fs::path more = dir.write("m.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(more), more,
                          "file ends after 0 of 1 faces (does the header count more vertices or faces than the file "
                          "holds? a vertex count one too large reads a face as a vertex)");
}

// Values past a plain OFF vertex's x y z (a colour without C in the header) are ignored, as the
// reader ignores them, and said once with the first line (silent until the forty-ninth session;
// found by an exploratory session).
TEST(MeshLoad, OffVertexValuesPastItsLayoutAreSaid)
{
    TempDir dir;
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m =
        pr::load_mesh(dir.write("g.off", "OFF\n3 1 0\n0 0 0\n1 0 0 7\n1 1 0 0.5 0.5 0.5\n3 0 1 2\n"));
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_NE(said.find("g.off: line 4: a vertex line holds values past the x y z of an OFF vertex (and 1 more such "
                        "lines): ignored (a colour needs a C in the header, a texture coordinate ST)"),
              std::string::npos)
        << said;
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("c.off", "COFF\n3 1 0\n0 0 0 1 0 0\n1 0 0 0 1 0\n1 1 0 0 0 1\n3 0 1 2\n"));
    EXPECT_EQ(::testing::internal::GetCapturedStderr().find("values past"), std::string::npos);
}

TEST(MeshErrors, PlyFaceIndexOutOfRange)
{
    TempDir dir;
    // An ASCII PLY of `vertices` (as the header counts them) with `index` its face list's type and
    // `body` the lines after its header.
    const auto ply = [&](const std::string& name, int vertices, const std::string& index, const std::string& body) {
        return dir.write(name, "ply\nformat ascii 1.0\nelement vertex " + std::to_string(vertices) +
                                   "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\n"
                                   "property list uchar " + index + " vertex_indices\nend_header\n" + body);
    };
    const fs::path p = ply("r.ply", 3, "int", "0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
    EXPECT_ERROR_MENTIONS(load_error(p), p, "line 13: face 0 has an out-of-range vertex index 5 (the file has 3 vertices)");
    // As written, not as the reader's 32 bits wrapped it ("-1"; forty-first session).
    const fs::path wrap = ply("w.ply", 3, "uint", "0 0 0\n1 0 0\n0 1 0\n3 4294967296 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(wrap), wrap, "line 13: face 0 has an out-of-range vertex index 4294967296");
    // A header counting a vertex more than the file holds: the face's line where the last is due
    // (forty-first session: said only that its values were wrong).
    const fs::path more = ply("m.ply", 4, "int", "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(more), more,
                          "line 13: vertex line has 4 values; its 3 properties call for 3 (a face's line, in a "
                          "vertex's place: the header counts 4 vertices, too many?)");
}

TEST(MeshErrors, AbsurdHeadersFailFast)
{
    TempDir dir;
    const auto start = std::chrono::steady_clock::now();
    const fs::path off = dir.write("big.off", "OFF\n2000000000 1 0\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "more than a file of");
    const fs::path off2 =
        dir.write("big2.off", "OFF\n3 2000000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(off2), off2, "more than a file of");
    const fs::path ply = dir.write(
        "big.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
                   "property float x\nproperty float y\nproperty float z\nelement face 1\n"
                   "property list uchar int vertex_indices\nend_header\n");
    EXPECT_ERROR_MENTIONS(load_error(ply), ply, "more than a file of");
    std::vector<char> stl = octa_stl_binary(100000000);
    const fs::path stlb = dir.write_bytes("big.stl", stl);
    EXPECT_ERROR_MENTIONS(load_error(stlb), stlb, "neither ASCII STL");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 2.0);
}

TEST(MeshErrors, OverTheTriangleLimit)
{
    TempDir dir;
    pr::MeshOptions options;
    options.max_triangles = 1;
    const fs::path p = dir.write("q.obj", kQuadObj);
    EXPECT_ERROR_MENTIONS(load_error(p, options), p, "limit is 1");
    const fs::path off = dir.write("q.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
    EXPECT_ERROR_MENTIONS(load_error(off, options), off, "limit is 1");
    // ASCII STL is counted as its facets come and stops past the limit: "more than" (it said
    // "has 2 triangles" of an octahedron's 8).
    const fs::path stl = dir.write("o.stl", octa_stl_ascii());
    EXPECT_ERROR_MENTIONS(load_error(stl, options), stl, "has more than 1 triangles (facets); the limit is 1");
}

TEST(MeshErrors, OnlyDegenerateFaces)
{
    TempDir dir;
    const fs::path p = dir.write("d.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    EXPECT_ERROR_MENTIONS(load_error(p), p, "degenerate");
}

TEST(MeshErrors, NotTheFormatItsNameSays)
{
    TempDir dir;
    const fs::path off = dir.write("x.off", "this is not an OFF file\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "OFF header");
    const fs::path ply = dir.write("x.ply", "solid x\n");
    EXPECT_ERROR_MENTIONS(load_error(ply), ply, "'ply'");
    const fs::path stl = dir.write("x.stl", "v 0 0 0\n");
    EXPECT_ERROR_MENTIONS(load_error(stl), stl, "neither ASCII STL");
}

// An OFF counts line without the edge count ("4 2"): OpenMesh took the first vertex's x for it and
// shifted every later value (a wrong shape, exit 0, and a warning of a repeated face).
TEST(MeshLoad, OffWithoutAnEdgeCount)
{
    TempDir dir;
    const char* body = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
    const pr::PreparedMesh two = pr::load_mesh(dir.write("two.off", std::string("OFF\n4 2\n") + body));
    const pr::PreparedMesh three = pr::load_mesh(dir.write("three.off", std::string("OFF\n4 2 0\n") + body));
    expect_sane(two);
    ASSERT_EQ(two.triangle_count(), 2u);
    EXPECT_EQ(two.bbox_min, three.bbox_min);
    EXPECT_EQ(two.bbox_max, three.bbox_max);
    EXPECT_EQ(two.indices.size(), three.indices.size());
}

// PLY layouts OpenMesh 9.0 misread without a word (the triangle (0,1,2) drawn as (3,0,1) or
// (1,3,0)) are refused, naming the property.
TEST(MeshLoad, PlyLayoutsTheReaderMisreadsAreRefused)
{
    TempDir dir;
    const std::string vertices = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n";
    const std::string data = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    const pr::Error flags = prtest::error_of([&] {
        pr::load_mesh(dir.write("flags.ply", "ply\nformat ascii 1.0\n" + vertices +
                                                 "element face 1\nproperty uchar flags\nproperty list uchar int "
                                                 "vertex_indices\nend_header\n" + data + "3 3 0 1 2\n"));
    });
    EXPECT_TRUE(prtest::contains(flags.what(), "PLY face property 'flags' comes before vertex_indices")) << flags.what();
    const pr::Error edge = prtest::error_of([&] {
        pr::load_mesh(dir.write("edge.ply", "ply\nformat ascii 1.0\n" + vertices +
                                                "element edge 1\nproperty list uchar int verts\nelement face 1\n"
                                                "property list uchar int vertex_indices\nend_header\n" + data +
                                                "2 3 1\n3 0 1 2\n"));
    });
    EXPECT_TRUE(prtest::contains(edge.what(), "PLY element 'edge' has a list property 'verts'")) << edge.what();
}

// A property declared twice in an element, or a second vertex or face element, is named (OpenMesh's
// reader failed on both without saying why: "could not be read as ply (the reader reported a
// failure)"; found by an exploratory session, forty-seventh).
TEST(MeshLoad, PlyHeadersDeclaringSomethingTwiceAreNamed)
{
    TempDir dir;
    const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
    const std::string face = "element face 1\nproperty list uchar int vertex_indices\n";
    const std::string data = "0 0 0\n1 0 0\n0 1 0\n";
    const fs::path property = dir.write("property.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                                                            "property float x\n" + face + "end_header\n" + data +
                                                            "3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(property), property, "line 7: element 'vertex' declares property 'x' twice");
    const fs::path vertex = dir.write("vertex.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                                                        "element vertex 3\n" + xyz + face + "end_header\n" + data +
                                                        data + "3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(vertex), vertex, "line 7: element 'vertex' declared twice");
    const fs::path faces = dir.write("faces.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz + face + face +
                                                      "end_header\n" + data + "3 0 1 2\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(faces), faces, "line 9: element 'face' declared twice");
    // A property of the same name in two elements is no repetition.
    const pr::PreparedMesh m = pr::load_mesh(dir.write("apart.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + xyz +
                                                                        "property uchar flags\n" + face +
                                                                        "property uchar flags\nend_header\n"
                                                                        "0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 2 1\n"));
    EXPECT_EQ(m.triangle_count(), 1u);
}

// PLY has one version, 1.0 (written "1" by some): a header that says another is refused with its
// line (it was taken without a word), and so is a second format line.
TEST(MeshLoad, PlyFormatLineOfAnotherVersionOrASecondOneIsRefused)
{
    TempDir dir;
    const std::string rest = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    const fs::path two = dir.write("two.ply", "ply\nformat ascii 2.0\n" + rest);
    EXPECT_ERROR_MENTIONS(load_error(two), two, "line 2: PLY version '2.0' is not 1.0, the only one there is");
    for (const char* version : {"1.0", "1", "1.00"}) {
        const pr::PreparedMesh m = pr::load_mesh(dir.write("one.ply", std::string("ply\nformat ascii ") + version + "\n" + rest));
        EXPECT_EQ(m.triangle_count(), 1u) << version;
    }
    // A second format line was half read (its version checked, its type dropped).
    const fs::path second = dir.write("second.ply", "ply\nformat ascii 1.0\nformat binary_little_endian 1.0\n" + rest);
    EXPECT_ERROR_MENTIONS(load_error(second), second, "line 3: a second format line (a header has one, right after 'ply')");
}

// An OBJ face with a vt at some corners only gets generated UVs, and the warning says so for the
// file's one face (docs/mesh-input.md said it read "no texture coordinates").
TEST(MeshLoad, ObjFaceWithoutAVtAtACornerIsSaid)
{
    TempDir dir;
    const fs::path p = dir.write("partial.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n"
                                                "f 1/1 2 3/3 4/3\n");
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(p);
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("its face has no usable texture coordinates (one at every corner); generated "
                            "box-projected UVs"),
              std::string::npos)
        << warnings;
    EXPECT_FALSE(m.had_uvs);
    EXPECT_EQ(m.triangle_count(), 2u);
}

// A UTF-8 byte-order mark before any text format, and comments after an OBJ line's values, are
// read past (they were refused: "does not start with 'ply'", "malformed face corner '#'", ...).
TEST(MeshLoad, ByteOrderMarksAndTrailingCommentsAreReadPast)
{
    TempDir dir;
    const std::string bom = "\xEF\xBB\xBF";
    const char* square = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    for (const auto& [name, text] :
         std::vector<std::pair<std::string, std::string>>{
             {"bom.obj", bom + "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n"},
             {"comments.obj", "v 0 0 0 # origin\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4 # a quad\n"},
             {"bom.off", bom + "OFF\n4 1 0\n" + square + "4 0 1 2 3\n"},
             {"bom.ply", bom + "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                               "end_header\n" + square + "4 0 1 2 3\n"},
             {"bom.stl", bom + "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
                               "endloop\nendfacet\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 1 0\n"
                               "vertex 0 1 0\nendloop\nendfacet\nendsolid s\n"}}) {
        SCOPED_TRACE(name);
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, text));
        expect_sane(m);
        EXPECT_EQ(m.triangle_count(), 2u);
        EXPECT_EQ(m.bbox_max, glm::vec3(1.0f, 1.0f, 0.0f));
    }
}

// OpenMesh reads ASCII PLY values, not lines: a stray value on a face line ("3 0 1 2 3") made the
// next face (0,2,4) read as (3,0,2), exit 0. Each face line must hold exactly its values.
TEST(MeshLoad, PlyFaceLineWithAStrayValueIsRefused)
{
    TempDir dir;
    const pr::Error e = prtest::error_of([&] {
        pr::load_mesh(dir.write("stray.ply", "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\n"
                                             "property float y\nproperty float z\nelement face 2\n"
                                             "property list uchar int vertex_indices\nend_header\n"
                                             "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0.5 0.5 0\n3 0 1 2 3\n3 0 2 4\n"));
    });
    EXPECT_TRUE(prtest::contains(e.what(), "line 15: face line has 5 values")) << e.what();
}

// Several closed pieces in one mesh (multi-body STL exports mix windings): one wound inward that
// lies inside no other is turned outward; one with faces against their neighbours is wound
// outward, or inward where it lies inside an odd number of others (a hollow solid's cavity).
// Before, only the whole mesh was reversed, by its total volume: a cube wound inward beside a
// sphere wound outward stayed inward (or, the larger one, turned the other inward).
TEST(MeshLoad, ClosedPiecesAreWoundOutwardOrAsCavities)
{
    TempDir dir;
    // An axis-aligned cube from lo to hi, wound outward or inward, its corners numbered from base.
    const auto cube = [](glm::vec3 lo, glm::vec3 hi, bool inward, int base, std::string& v, std::string& f,
                         bool one_face_against = false) {
        for (int i = 0; i < 8; ++i)
            v += "v " + std::to_string(i & 1 ? hi.x : lo.x) + " " + std::to_string(i & 2 ? hi.y : lo.y) + " " +
                 std::to_string(i & 4 ? hi.z : lo.z) + "\n";
        const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
        for (const auto& q : quads) {
            const bool against = one_face_against && &q == &quads[0];
            f += "f";
            for (int k = 0; k < 4; ++k) f += " " + std::to_string(base + q[inward != against ? 3 - k : k] + 1);
            f += "\n";
        }
    };
    // Every triangle's normal against the direction from `centre` of its own cube (the nearer).
    const auto expect_winding = [](const pr::PreparedMesh& m, glm::vec3 centre_a, glm::vec3 centre_b, bool b_inward,
                                   const char* what) {
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const glm::vec3 mid = triangle_centre(m, t);
            const bool on_b = glm::length(mid - centre_b) < glm::length(mid - centre_a) ||
                              glm::all(glm::lessThan(glm::abs(mid - centre_b), glm::vec3(0.21f)));
            const float out = glm::dot(face_normal(m, t), mid - (on_b ? centre_b : centre_a));
            EXPECT_TRUE(on_b && b_inward ? out < 0.0f : out > 0.0f) << what << " triangle " << t;
        }
    };
    const glm::vec3 c0(0.5f), c1(3.5f, 0.5f, 0.5f);
    struct Case {
        const char* name;
        bool first_inward, second_inward, nested, second_one_face_against;
        const char* said; // nullptr: no word
        bool second_ends_inward;
    };
    const char* turned = "1 of its 2 closed pieces wound inward, and inside no other piece, turned outward";
    const Case cases[] = {
        {"side by side, the small one inward", false, true, false, false, turned, false},
        {"side by side, the large one inward", true, false, false, false, turned, false},
        {"a hollow solid", false, true, true, false, nullptr, true},
        // Wound one way throughout and nested: the file's winding is kept (a body inside a
        // transparent one is as likely as a cavity).
        {"a body inside another", false, false, true, false, nullptr, false},
        // With a face against its neighbours, the piece must be wound anew: nested once, inward.
        {"a hollow solid with a face of its cavity turned", false, true, true, true,
         "1 face wound against its neighbours", true},
        {"a body inside another with one face turned", false, false, true, true, "5 faces wound against their neighbours",
         true},
    };
    // Pieces that touch or run through another are not nested in it (found by a review: one
    // triangle's centre alone decided). A table's leg under its top, its first face in the plane
    // of the top's underside, one of its faces against its neighbours: wound outward, not as a
    // cavity. A bar through a box, wound inward: turned outward, and the box kept.
    {
        std::string v, f;
        cube(glm::vec3(0.0f, 1.0f, 0.0f), glm::vec3(2.0f, 1.2f, 2.0f), false, 0, v, f);
        std::string lv, lf;
        cube(glm::vec3(0.1f, 0.0f, 0.1f), glm::vec3(0.3f, 1.0f, 0.3f), false, 8, lv, lf, true);
        // (Its top face, y = 1, first: the quads' order puts {2, 6, 7, 3} fourth.)
        const auto lines = [](const std::string& text) {
            std::vector<std::string> out;
            for (std::size_t at = 0, next; at < text.size(); at = next + 1) {
                next = text.find('\n', at);
                out.push_back(text.substr(at, next - at + 1));
            }
            return out;
        };
        std::vector<std::string> leg = lines(lf);
        std::rotate(leg.begin(), leg.begin() + 3, leg.end());
        std::string legf;
        for (const std::string& l : leg) legf += l;
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("table.obj", v + lv + f + legf));
        ::testing::internal::GetCapturedStderr();
        expect_winding(m, glm::vec3(1.0f, 1.1f, 1.0f), glm::vec3(0.2f, 0.5f, 0.2f), false, "a table's leg");
    }
    {
        std::string v, f;
        cube(glm::vec3(0.0f), glm::vec3(1.0f), false, 0, v, f);
        cube(glm::vec3(-0.5f, 0.4f, 0.4f), glm::vec3(1.5f, 0.6f, 0.6f), true, 8, v, f);
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("bar.obj", v + f));
        const std::string said = ::testing::internal::GetCapturedStderr();
        EXPECT_NE(said.find("1 of its 2 closed pieces wound inward, and inside no other piece, turned outward"),
                  std::string::npos)
            << said;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            const glm::vec3 mid = triangle_centre(m, t);
            const bool bar = std::abs(mid.y - 0.5f) <= 0.1001f && std::abs(mid.z - 0.5f) <= 0.1001f;
            EXPECT_GT(glm::dot(face_normal(m, t), mid - glm::vec3(0.5f)), 0.0f) << (bar ? "bar " : "box ") << t;
        }
    }
    // A closed body wound inward beside an open sheet: the sheet kept the whole mesh from counting
    // as closed, so the body was reversed neither by itself nor with the mesh (a review).
    {
        std::string v, f;
        cube(glm::vec3(0.0f), glm::vec3(1.0f), true, 0, v, f);
        v += "v 3 0 0\nv 4 0 0\nv 4 0 1\nv 3 0 1\n";
        f += "f 9 12 11 10\n";
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("cube_and_sheet.obj", v + f));
        const std::string said = ::testing::internal::GetCapturedStderr();
        EXPECT_NE(said.find("1 of its 1 closed pieces wound inward, and inside no other piece, turned outward"),
                  std::string::npos)
            << said;
        for (std::size_t t = 0; t < m.triangle_count(); ++t) {
            if (m.vertices[m.indices[3 * t]].position.x > 2.0f) continue; // the sheet
            const glm::vec3 mid = triangle_centre(m, t);
            EXPECT_GT(glm::dot(face_normal(m, t), mid - glm::vec3(0.5f)), 0.0f) << "cube " << t;
        }
    }
    int file = 0; // (a warning said once for a file is not said again: a name per case)
    for (const Case& c : cases) {
        std::string v, f;
        cube(glm::vec3(0.0f), glm::vec3(1.0f), c.first_inward, 0, v, f);
        if (c.nested)
            cube(glm::vec3(0.3f), glm::vec3(0.7f), c.second_inward, 8, v, f, c.second_one_face_against);
        else
            cube(glm::vec3(3.3f, 0.3f, 0.3f), glm::vec3(3.7f, 0.7f, 0.7f), c.second_inward, 8, v, f,
                 c.second_one_face_against);
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("cubes" + std::to_string(file++) + ".obj", v + f));
        const std::string said = ::testing::internal::GetCapturedStderr();
        if (c.said) EXPECT_NE(said.find(c.said), std::string::npos) << c.name << ": " << said;
        else EXPECT_EQ(said.find("turned"), std::string::npos) << c.name << ": " << said;
        expect_winding(m, c0, c.nested ? c0 : c1, c.second_ends_inward, c.name);
    }
}

// Found by an exploratory session (seventeenth session): inputs each reader took wrong at exit 0,
// or refused though valid.
TEST(MeshLoad, StlSolidNamesAreNotFacets)
{
    // OpenMesh takes any line containing "outer" for a facet's start: `solid Router_bracket` read
    // the next three lines as vertices ("line 2: expected 'vertex x y z'"). The names are blanked.
    TempDir dir;
    std::string named = octa_stl_ascii();
    named.replace(named.find("solid octa"), 10, "solid Router_bracket OUTER");
    named.replace(named.rfind("endsolid octa"), 13, "endsolid outer_shell");
    expect_smooth_octahedron(pr::load_mesh(dir.write("r.stl", named)));
}

// Words after an "endsolid" and before any "solid" are in no solid: skipped, as OpenMesh skips
// them, but said (they went without a word; found by an exploratory session, forty-ninth). A
// second solid after the first is read, and says nothing.
TEST(MeshLoad, StlWordsAfterEndsolidAreSaid)
{
    TempDir dir;
    const std::string octa = octa_stl_ascii();
    ::testing::internal::CaptureStderr();
    expect_smooth_octahedron(pr::load_mesh(dir.write("t.stl", octa + "1 2 3\ngarbage\n")));
    const std::string said = ::testing::internal::GetCapturedStderr();
    const std::size_t lines = std::size_t(std::count(octa.begin(), octa.end(), '\n'));
    EXPECT_NE(said.find("t.stl: line " + std::to_string(lines + 1) +
                        ": '1' comes after an 'endsolid', outside any solid: the words there are ignored"),
              std::string::npos)
        << said;
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("two.stl", octa + octa));
    EXPECT_EQ(::testing::internal::GetCapturedStderr().find("outside any solid"), std::string::npos);
}

// A facet that ends after fewer than three vertices says so (it read "expected 'vertex x y z'
// with finite numbers" on its endloop line; an exploratory session, forty-ninth).
TEST(MeshErrors, StlFacetWithTwoVerticesIsSaid)
{
    TempDir dir;
    const fs::path p = dir.write("two.stl", "solid a\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                            "endloop\nendfacet\nendsolid a\n");
    EXPECT_ERROR_MENTIONS(load_error(p), p, "line 6: 'endloop' after 2 vertices (STL facets are triangles: three)");
}

TEST(MeshErrors, StlFacetWithFourVerticesIsRefused)
{
    // The reader took three and dropped the fourth: a quad became a triangle, exit 0.
    TempDir dir;
    std::string four = octa_stl_ascii();
    const std::size_t end = four.find("    endloop");
    four.insert(end, "      vertex 2 2 2\n");
    const fs::path p = dir.write("q.stl", four);
    EXPECT_ERROR_MENTIONS(load_error(p), p, "line 7: a vertex beyond the three after 'outer loop' (STL facets are triangles)");
}

// An ASCII STL cut short: inside a facet after its third vertex, or inside "endfacet", it was
// read without a word, the facets after the cut gone (found by an exploratory session,
// thirty-third). Cut between two facets, only the missing "endsolid" says so: a warning.
TEST(MeshErrors, StlCutShortIsSaid)
{
    TempDir dir;
    const std::string whole = octa_stl_ascii();
    const std::size_t third = whole.find("    endloop", whole.find("facet", whole.find("endfacet")));
    const fs::path in_facet = dir.write("a.stl", whole.substr(0, third));
    EXPECT_ERROR_MENTIONS(load_error(in_facet), in_facet, "file ends inside a facet (no 'endloop')");
    const std::size_t endfacet = whole.find("  endfacet", third);
    const fs::path in_word = dir.write("b.stl", whole.substr(0, endfacet + 4) + "\n");
    EXPECT_ERROR_MENTIONS(load_error(in_word), in_word, "line 15: expected 'endfacet', found 'en' (the file is cut short?)");
    std::string swapped = whole;
    swapped.replace(swapped.find("  endfacet"), 10, "  endloop ");
    const fs::path twice = dir.write("c.stl", swapped);
    EXPECT_ERROR_MENTIONS(load_error(twice), twice, "line 8: expected 'endfacet', found 'endloop'");
    const fs::path between = dir.write("d.stl", whole.substr(0, whole.find("  facet", third)));
    ::testing::internal::CaptureStderr();
    EXPECT_EQ(pr::load_mesh(between).triangle_count(), 2u);
    EXPECT_NE(::testing::internal::GetCapturedStderr().find("no 'endsolid' after its last facet: the file may be cut short (2 facets read)"),
              std::string::npos);
    ::testing::internal::CaptureStderr(); // the whole file: no such word
    EXPECT_EQ(pr::load_mesh(dir.write("e.stl", whole)).triangle_count(), 8u);
    EXPECT_EQ(::testing::internal::GetCapturedStderr().find("endsolid"), std::string::npos);
    // The words are read across lines ("endloop endfacet" on one), and a facet without
    // "endloop" but closed by "endfacet" is taken, as OpenMesh's reader takes it.
    std::string joined = whole, bare = whole;
    for (std::size_t at; (at = joined.find("endloop\n  endfacet")) != std::string::npos;)
        joined.replace(at, 18, "ENDLOOP ENDFACET");
    for (std::size_t at; (at = bare.find("    endloop\n")) != std::string::npos;) bare.erase(at, 12);
    EXPECT_EQ(pr::load_mesh(dir.write("f.stl", joined)).triangle_count(), 8u);
    EXPECT_EQ(pr::load_mesh(dir.write("g.stl", bare)).triangle_count(), 8u);
}

TEST(MeshErrors, HexadecimalNumbersAreRefused)
{
    // strtod takes 0x1p0 for 1; OpenMesh's stream reads 0: the apex of this tetrahedron came out
    // at z = 0, flat, exit 0.
    TempDir dir;
    const fs::path off = dir.write("h.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 0x1p0\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "line 6:");
    const fs::path stl = dir.write("h.stl", "solid h\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                            "vertex 0 1 0x1p0\nendloop\nendfacet\nendsolid h\n");
    EXPECT_ERROR_MENTIONS(load_error(stl), stl, "line 6: expected 'vertex x y z' with finite numbers");
}

TEST(MeshLoad, LongNumbersAreRead)
{
    // A 64-byte buffer refused valid numbers of 64 characters or more ("not a finite number").
    TempDir dir;
    const std::string one = "1." + std::string(70, '0');
    const pr::PreparedMesh m = pr::load_mesh(dir.write("l.obj", "v 0 0 0\nv " + one + " 0 0\nv 0 1 0\nf 1 2 3\n"));
    EXPECT_EQ(m.bbox_max, glm::vec3(1.0f, 1.0f, 0.0f));
}

TEST(MeshErrors, BinaryOffWhoseFacesDoNotFitIsRefused)
{
    // Cut short inside its last face, or a face claiming more corners than follow: OpenMesh drew
    // what it could read (a triangle of the quad), exit 0.
    TempDir dir;
    std::vector<char> b;
    const std::string head = "OFF BINARY\n";
    b.insert(b.end(), head.begin(), head.end());
    for (std::int32_t i : {4, 1, 0}) put(b, i);
    for (float f : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 1.f, 1.f, 0.f, 0.f, 1.f, 0.f}) put(b, f);
    for (std::int32_t i : {4, 0, 1, 2, 3}) put(b, i);
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("ok.off", b)).triangle_count(), 2u);
    const std::string problem = "binary OFF whose faces do not end where the file does";
    for (const std::size_t cut : {1u, 3u, 4u}) {
        const fs::path p = dir.write_bytes("cut.off", std::vector<char>(b.begin(), b.end() - std::ptrdiff_t(cut)));
        EXPECT_ERROR_MENTIONS(load_error(p), p, problem);
    }
    std::vector<char> five = b;
    const std::int32_t corners = 5;
    std::memcpy(five.data() + five.size() - 20, &corners, 4);
    const fs::path p = dir.write_bytes("five.off", five);
    EXPECT_ERROR_MENTIONS(load_error(p), p, problem);
}

TEST(MeshErrors, PlyFaceIndicesMustBeWholeNumbers)
{
    // Counted, never parsed: "0x2", "1e1", "2.9" and "-1" were read as what the stream made of
    // them, a face of other vertices, exit 0.
    TempDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                             "end_header\n0 0 0\n1 0 0\n0 1 0\n";
    for (const std::string index : {"0x2", "1e1", "2.9", "-1"}) {
        const fs::path p = dir.write("i.ply", head + "3 0 1 " + index + "\n");
        EXPECT_ERROR_MENTIONS(load_error(p), p, "line 13: face index '" + index + "' is not a whole number from 0");
    }
    EXPECT_EQ(pr::load_mesh(dir.write("ok.ply", head + "3 0 1 2\n")).triangle_count(), 1u);
}

TEST(MeshErrors, PlyCornerCountTypesTheReaderCannotTakeAreNamed)
{
    // OpenMesh 9.0 reads a face's corner count as uchar, uint8, uint16 or int only; the others
    // failed with "the reader reported a failure".
    TempDir dir;
    const auto ply = [](const std::string& count) {
        return "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
               "element face 1\nproperty list " + count + " int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    };
    for (const std::string count : {"uchar", "uint8", "uint16", "int"})
        EXPECT_EQ(pr::load_mesh(dir.write("ok.ply", ply(count))).triangle_count(), 1u) << count;
    // Their synonyms and the types of the same size are renamed to those (thirty-third session:
    // they were refused, ushort and int32 alike).
    for (const std::string count : {"ushort", "uint", "int32", "uint32", "short", "int16", "char", "int8"})
        EXPECT_EQ(pr::load_mesh(dir.write("ok.ply", ply(count))).triangle_count(), 1u) << count;
    const fs::path p = dir.write("c.ply", ply("float"));
    EXPECT_ERROR_MENTIONS(load_error(p), p, "PLY face list 'vertex_indices' counts its entries in a float"
                                            ", which the reader cannot take (an integer type)");
    // Binary: the same bytes read under the renamed type.
    for (const auto& [count, bytes] : std::vector<std::pair<std::string, int>>{{"ushort", 2}, {"uint", 4}, {"char", 1}}) {
        std::vector<char> b;
        const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                 "property float z\nelement face 1\nproperty list " + count + " int vertex_indices\nend_header\n";
        b.assign(head.begin(), head.end());
        for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, v);
        b.push_back(3);
        for (int k = 1; k < bytes; ++k) b.push_back(0);
        for (const std::int32_t i : {0, 1, 2}) put(b, i);
        EXPECT_EQ(pr::load_mesh(dir.write_bytes("b.ply", b)).triangle_count(), 1u) << count;
    }
}

// Colours of any type, which nothing here uses, are skipped as unknown properties: the reader
// read a binary double colour as an integer it could not convert (a line on stderr per value,
// then "face 0 has fewer than 3 vertices"), and an ASCII one into an integer, which "255.0" or
// "0.5" misaligned. Float vertex indices in a binary PLY are named (found by an exploratory
// session, thirty-eighth).
TEST(MeshLoad, PlyColoursOfAnyTypeAreSkipped)
{
    TempDir dir;
    const std::string vertex_props = "property float x\nproperty float y\nproperty float z\n";
    for (const bool big : {false, true}) {
        std::vector<char> b;
        const std::string head = std::string("ply\nformat ") + (big ? "binary_big_endian" : "binary_little_endian") +
                                 " 1.0\nelement vertex 3\n" + vertex_props +
                                 "property double red\nproperty float64 diffuse_green\nproperty double alpha\n"
                                 "element face 1\nproperty list uchar int vertex_indices\nproperty double red\nend_header\n";
        b.assign(head.begin(), head.end());
        const auto put_any = [&b, big](auto value) {
            const char* c = reinterpret_cast<const char*>(&value);
            for (std::size_t i = 0; i < sizeof(value); ++i) b.push_back(c[big ? sizeof(value) - 1 - i : i]);
        };
        const float xyz[9] = {0.f, 0.f, 0.f, 2.f, 0.f, 0.f, 0.f, 3.f, 0.f};
        for (int v = 0; v < 3; ++v) {
            for (int k = 0; k < 3; ++k) put_any(xyz[3 * v + k]);
            for (const double c : {0.25, 0.5, 1.0}) put_any(c);
        }
        b.push_back(3);
        for (const std::int32_t i : {0, 1, 2}) put_any(i);
        put_any(0.75);
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write_bytes("c.ply", b));
        EXPECT_EQ(::testing::internal::GetCapturedStderr().find("conversion"), std::string::npos) << big; // (the reader's)
        EXPECT_EQ(m.triangle_count(), 1u) << big;
        EXPECT_EQ(m.bbox_max, glm::vec3(2.0f, 3.0f, 0.0f)) << big;
    }
    const pr::PreparedMesh a = pr::load_mesh(dir.write(
        "a.ply", "ply\nformat ascii 1.0\nelement vertex 3\n" + vertex_props +
                     "property uchar red\nproperty double green\nelement face 1\nproperty list uchar int vertex_indices\n"
                     "property uchar blue\nend_header\n0 0 0 255.0 0.5\n2 0 0 0 0.25\n0 3 0 1 1\n3 0 1 2 7.5\n"));
    EXPECT_EQ(a.triangle_count(), 1u);
    EXPECT_EQ(a.bbox_max, glm::vec3(2.0f, 3.0f, 0.0f));
    for (const std::string type : {"float", "double"}) {
        const std::string head = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + vertex_props +
                                 "element face 1\nproperty list uchar " + type + " vertex_indices\nend_header\n";
        std::vector<char> b(head.begin(), head.end());
        for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(b, v);
        b.push_back(3);
        for (const float i : {0.f, 1.f, 2.f}) type == "float" ? put(b, i) : put(b, double(i));
        const fs::path p = dir.write_bytes("i.ply", b);
        ::testing::internal::CaptureStderr();
        EXPECT_ERROR_MENTIONS(load_error(p), p, "binary PLY face list 'vertex_indices' holds " + type +
                                                    " values, which the reader cannot take as vertex indices (an integer type)");
        EXPECT_EQ(::testing::internal::GetCapturedStderr().find("conversion"), std::string::npos);
    }
}

// Binary PLY as exporters write it: white space at a header line's end (after end_header it put
// the body a byte off; after the face list the reader failed without a word); positions in
// shorts, which the reader cannot convert (a line of noise per value, then a wrong error); a body
// cut short or a header count too large (found by an exploratory session, thirty-third).
TEST(MeshErrors, BinaryPlyHeadersAndBodiesAreReadOrNamed)
{
    TempDir dir;
    const auto file = [](const std::string& head, int vertices, int faces, const std::string& extra = "") {
        std::vector<char> b(head.begin(), head.end());
        const float v[12] = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
        for (int i = 0; i < 3 * vertices; ++i) put(b, v[i % 12]);
        const std::int32_t f[2][3] = {{0, 1, 2}, {0, 2, 3}};
        for (int i = 0; i < faces; ++i) {
            b.push_back(3);
            for (const std::int32_t k : f[i % 2]) put(b, k);
        }
        b.insert(b.end(), extra.begin(), extra.end());
        return b;
    };
    const auto head = [](const std::string& x_type, int vertices, int faces, const std::string& list_end,
                         const std::string& end_end, const std::string& more = "") {
        return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(vertices) + "\nproperty " +
               x_type + " x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
               "\nproperty list uchar int vertex_indices" + list_end + "\n" + more + "end_header" + end_end + "\n";
    };
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("ws.ply", file(head("float", 4, 2, " ", " \t"), 4, 2))).triangle_count(), 2u);
    ::testing::internal::CaptureStderr();
    const fs::path shorts = dir.write_bytes("s.ply", file(head("short", 4, 2, "", ""), 4, 2));
    EXPECT_ERROR_MENTIONS(load_error(shorts), shorts,
                          "binary PLY vertex property 'x' is a short, which the reader cannot take (positions, normals "
                          "and texture coordinates: float or double; ASCII PLY takes any)");
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), ""); // (no line of the reader's)
    const fs::path cut = dir.write_bytes("cut.ply", file(head("float", 4, 2, "", ""), 4, 1));
    EXPECT_ERROR_MENTIONS(load_error(cut), cut, "binary PLY ends inside its face 1 of 2 (cut short, or a count too large?)");
    const fs::path more = dir.write_bytes("more.ply", file(head("float", 5, 2, "", ""), 4, 2));
    EXPECT_ERROR_MENTIONS(load_error(more), more,
                          "face 0 has fewer than 3 vertices (it lists 0); the body reads whole with 4 vertices: does the header "
                          "count 1 more than the file holds?");
    // A face of fewer than 3 vertices that the file itself holds is said without that question: no
    // smaller vertex count reads the body whole (it was asked of every such face).
    const fs::path short_face = dir.write_bytes(
        "two.ply", file(head("float", 4, 2, "", ""), 4, 1, std::string("\x02\x00\x00\x00\x00\x02\x00\x00\x00", 9)));
    EXPECT_EQ(load_error(short_face).problem(), "face 1 has fewer than 3 vertices (it lists 2)");
    const fs::path edges = dir.write_bytes(
        "e.ply", file(head("float", 4, 2, "", "", "element edge 2\nproperty int vertex1\nproperty int vertex2\n"), 4, 2));
    EXPECT_ERROR_MENTIONS(load_error(edges), edges,
                          "binary PLY ends inside its edge element: 2 of 8 bytes each need 16, and 0 are left");
    const fs::path strips = dir.write("t.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement tristrips 1\nproperty list int int vertex_indices\n"
                                               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(strips), strips, "has triangle strips (element 'tristrips') and no face element");
    // end_header indented, or with another line end than the line before it: the reader took the
    // body a byte or two off ("face 0 has fewer than 3 vertices"; found by a review). Comment,
    // obj_info and blank lines are dropped from the header the reader sees: right before
    // end_header they put the body off too, and were refused until the thirty-fourth session,
    // with files the reader read right among them (an obj_info line last, a comment last in a
    // CR LF header; found by a review).
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("ind.ply", file(head("float", 4, 2, "", "", "") , 4, 2))).triangle_count(), 2u);
    {
        std::string h = head("float", 4, 2, "", "");
        h.replace(h.find("end_header"), 10, "  end_header");
        EXPECT_EQ(pr::load_mesh(dir.write_bytes("ind2.ply", file(h, 4, 2))).triangle_count(), 2u);
        std::string crlf = head("float", 4, 2, "", "");
        crlf.replace(crlf.find("end_header\n"), 11, "end_header\r\n");
        EXPECT_EQ(pr::load_mesh(dir.write_bytes("mix.ply", file(crlf, 4, 2))).triangle_count(), 2u);
    }
    for (const std::string& before :
         {std::string("comment made by hand\n"), std::string("\n"), std::string("obj_info generated by tool 1.2\n"),
          std::string("obj_info see comment x\n"), std::string("obj_info element face many\n"),
          std::string("comment a\n\n  \nobj_info b\ncomment c\n"), std::string("element edge 0\v\n"),
          std::string("element edge 0\f \n")}) {
        const fs::path c = dir.write_bytes("c.ply", file(head("float", 4, 2, "", "", before), 4, 2));
        EXPECT_EQ(pr::load_mesh(c).triangle_count(), 2u) << before;
    }
    {
        std::string crlf = head("float", 4, 2, "", "", "comment made by tool\n");
        for (std::size_t at = crlf.find('\n'); at != std::string::npos; at = crlf.find('\n', at + 2)) crlf.insert(at, "\r");
        EXPECT_EQ(pr::load_mesh(dir.write_bytes("crlf.ply", file(crlf, 4, 2))).triangle_count(), 2u);
        // A comment right after "ply" too (refused: "expected the format line right after 'ply'"; a review).
        std::string first = head("float", 4, 2, "", "");
        first.insert(4, "comment by hand\nobj_info tool\n");
        EXPECT_EQ(pr::load_mesh(dir.write_bytes("first.ply", file(first, 4, 2))).triangle_count(), 2u);
    }
    // An empty element's list counted in another integer type is renamed too; a float count is named.
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("el.ply", file(head("float", 4, 2, "", "",
                                                                "element edge 0\nproperty list ushort int verts\n"), 4, 2)))
                  .triangle_count(),
              2u);
    const fs::path fc = dir.write_bytes("fc.ply", file(head("float", 4, 2, "", "", "element edge 0\nproperty list float int verts\n"), 4, 2));
    EXPECT_ERROR_MENTIONS(load_error(fc), fc, "PLY edge list 'verts' counts its entries in a float, which the reader cannot take");
    // An empty element with a list besides the faces holds nothing to misread: taken.
    EXPECT_EQ(pr::load_mesh(dir.write("f.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                               "element tristrips 0\nproperty list int int vertex_indices\nend_header\n"
                                               "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"))
                  .triangle_count(),
              1u);
}

// Two pieces touching at a point (a pinch vertex) are said: the welded normal there averages
// them and the prism's shell folds about it (two cones touching at the apex lost a third of one
// near it without a word; found by an exploratory session, thirty-fourth). One closed piece is not.
TEST(MeshLoad, PiecesTouchingAtAPointAreSaid)
{
    TempDir dir;
    const std::string tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("one.obj", tetra));
    std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(said.find("fans of faces"), std::string::npos) << said;
    // The second tetrahedron mirrored through the first's corner 1 (the origin).
    const std::string two = tetra + "v -1 0 0\nv 0 -1 0\nv 0 0 -1\nf 1 6 7\nf 1 5 6\nf 1 7 5\nf 5 7 6\n";
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("two.obj", two));
    said = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("1 vertex joins fans of faces that share no edge (non-manifold: pieces touching at a point"),
              std::string::npos)
        << said;
}

// A quad drawn as both of its triangulations: its edges run the same way in two triangles wound
// the same way round one plane, which the orientation pass took for faces turned over. It turned
// two of them: their normals cancelled ("4 positions have no defined normal") and the prism lost
// 40 % of the surface (IoU 0.62, now 0.9993; found by an exploratory session).
TEST(MeshLoad, OverlappingFacesWoundAlikeAreNotTurned)
{
    TempDir dir;
    for (const std::string faces : {"f 1 2 3\nf 1 3 4\nf 2 3 4\nf 1 2 4\n", "f 1 2 3 4\nf 1 2 4\n"}) {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("o.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n" + faces));
        const std::string warnings = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(warnings.find("wound against"), std::string::npos) << warnings;
        EXPECT_EQ(warnings.find("no defined normal"), std::string::npos) << warnings;
        EXPECT_NE(warnings.find("edges join faces that lie over one another"), std::string::npos) << warnings;
        for (const pr::MeshVertex& v : m.vertices) EXPECT_NEAR(glm::distance(v.normal, glm::vec3(0, 0, 1)), 0.0f, 1e-6f);
    }
    // A face turned over beside its neighbour is still turned.
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh turned = pr::load_mesh(dir.write("t.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 4 3\n"));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(warnings.find("wound against"), std::string::npos) << warnings;
    for (const pr::MeshVertex& v : turned.vertices) EXPECT_NEAR(std::abs(v.normal.z), 1.0f, 1e-6f);
}

// Positions far from the file's origin (geographic coordinates) are read in double where the scan
// reads them (ASCII OBJ, OFF, PLY) and kept relative to the mesh's centre (PreparedMesh::origin):
// OpenMesh's floats are 0.5 apart at 5e6, which turned a small tetrahedron into a sliver or
// nothing. A mesh near its origin keeps the reader's floats and origin 0.
TEST(MeshLoad, FarPositionsAreKeptRelativeToTheMeshsCentre)
{
    TempDir dir;
    const glm::dvec3 at(5000000.3, -3000000.7, 1000.1);
    const double corner[4][3] = {{0, 0, 0}, {0.25, 0, 0}, {0, 0.25, 0}, {0, 0, 0.25}};
    const auto files = [&](const glm::dvec3& offset) {
        std::string v, plain;
        char text[128];
        for (const auto& c : corner) {
            std::snprintf(text, sizeof text, "%.4f %.4f %.4f\n", offset.x + c[0], offset.y + c[1], offset.z + c[2]);
            v += std::string("v ") + text;
            plain += text;
        }
        const std::string faces = "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
        return std::vector<std::pair<std::string, std::string>>{
            {"t.obj", v + "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n"},
            {"t.off", "OFF\n4 4 0\n" + plain + faces},
            {"t.ply", "ply\nformat ascii 1.0\nelement vertex 4\nproperty double y_extra\nproperty double x\n"
                      "property double y\nproperty double z\nelement face 4\nproperty list uchar int vertex_indices\n"
                      "end_header\n" + [&] {
                          std::string lines;
                          std::istringstream in(plain);
                          for (std::string line; std::getline(in, line);) lines += "7 " + line + "\n";
                          return lines;
                      }() + faces},
        };
    };
    // Binary PLY, both byte orders: doubles, read by the scan from where the vertices start (after
    // an element of its own), other properties of other types around them.
    const auto binary_ply = [&](const glm::dvec3& offset, bool big) {
        std::string text = std::string("ply\nformat binary_") + (big ? "big" : "little") +
                           "_endian 1.0\nelement extra 2\nproperty short a\nproperty float b\nelement vertex 4\n"
                           "property uchar flag\nproperty double x\nproperty int q\nproperty double y\nproperty double z\n"
                           "element face 4\nproperty list uchar int vertex_indices\nend_header\n";
        const auto put = [&](const void* data, size_t size) {
            std::string bytes(static_cast<const char*>(data), size);
            if (big != (std::endian::native == std::endian::big)) std::reverse(bytes.begin(), bytes.end());
            text += bytes;
        };
        for (int i = 0; i < 2; ++i) {
            const std::int16_t a = -7;
            const float b = 3.5f;
            put(&a, 2);
            put(&b, 4);
        }
        for (const auto& c : corner) {
            const std::uint8_t flag = 1;
            const std::int32_t q = 123456;
            const double x = offset.x + c[0], y = offset.y + c[1], z = offset.z + c[2];
            put(&flag, 1);
            put(&x, 8);
            put(&q, 4);
            put(&y, 8);
            put(&z, 8);
        }
        for (const std::array<std::int32_t, 3>& f : {std::array<std::int32_t, 3>{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}}) {
            text += char(3);
            for (const std::int32_t k : f) put(&k, 4);
        }
        return text;
    };
    auto far_files = files(at);
    far_files.emplace_back("le.ply", binary_ply(at, false));
    far_files.emplace_back("be.ply", binary_ply(at, true));
    for (const auto& [name, text] : far_files) {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, text));
        const std::string warnings = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(m.triangle_count(), 4u) << name << warnings;
        EXPECT_EQ(m.dropped_triangles, 0u) << name;
        EXPECT_NEAR(glm::distance(m.origin, at + glm::dvec3(0.125)), 0.0, 1e-9) << name;
        EXPECT_NEAR(glm::distance(glm::dvec3(m.bbox_min), glm::dvec3(-0.125)), 0.0, 1e-6) << name;
        EXPECT_NEAR(glm::distance(glm::dvec3(m.bbox_max), glm::dvec3(0.125)), 0.0, 1e-6) << name;
    }
    // An unused vertex at the file's origin (a marker) does not count: the box is the faces'.
    {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write("marker.obj", files(at)[0].second + "v 0 0 0\n"));
        ::testing::internal::GetCapturedStderr();
        EXPECT_NEAR(glm::distance(m.origin, at + glm::dvec3(0.125)), 0.0, 1e-9);
        EXPECT_EQ(m.dropped_triangles, 0u);
    }
    auto near_files = files(glm::dvec3(0.5, -0.25, 0.75)); // within 4 extents
    near_files.emplace_back("le.ply", binary_ply(glm::dvec3(0.5, -0.25, 0.75), false));
    for (const auto& [name, text] : near_files) {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, text));
        ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(m.origin, glm::dvec3(0.0)) << name;
        EXPECT_EQ(m.bbox_min, glm::vec3(0.5f, -0.25f, 0.75f)) << name;
    }
}

// A far mesh in a file of floats (binary STL) is recentred too, exactly: its floats are all there
// is, and drawn relative to its centre they are not rounded once more against the far translation.
TEST(MeshLoad, FarFloatPositionsAreKeptRelativeToTheMeshsCentre)
{
    TempDir dir;
    const float corner[4][3] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}}; // floats 0.5 apart at 5e6
    const int faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
    std::string stl(80, ' ');
    const std::uint32_t count = 4;
    stl.append(reinterpret_cast<const char*>(&count), 4);
    for (const auto& f : faces) {
        const float normal[3] = {0, 0, 0};
        stl.append(reinterpret_cast<const char*>(normal), 12);
        for (const int k : f) {
            const float p[3] = {5000000.0f + corner[k][0], -3000000.0f + corner[k][1], 1000.0f + corner[k][2]};
            stl.append(reinterpret_cast<const char*>(p), 12);
        }
        stl.append(2, '\0');
    }
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("far.stl", stl));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(m.triangle_count(), 4u) << warnings;
    EXPECT_EQ(m.origin, glm::dvec3(5000002.0, -2999998.0, 1002.0));
    EXPECT_EQ(m.bbox_min, glm::vec3(-2.0f));
    EXPECT_EQ(m.bbox_max, glm::vec3(2.0f));
}

// A strictly convex polygon of 8 or more corners is cut by rounds of ears, every other corner at a
// time, not as the fan from its first corner: the fan put all its triangles, slivers, around one
// corner, and a ray near it crossed them one by one in the prism's walk (a 2000-gon: 217 ms a
// frame at 128², now 15 ms; found by an exploratory session). The same area, one orientation,
// and no corner in more than a few triangles per round.
TEST(MeshLoad, LargeConvexPolygonsAreNotFans)
{
    TempDir dir;
    const int n = 1000;
    std::string obj;
    char line[96];
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.14159265358979323846 * i / n;
        std::snprintf(line, sizeof line, "v %.9f %.9f 0\nvt %.9f %.9f\n", std::cos(a), std::sin(a), 0.5 + 0.5 * std::cos(a),
                      0.5 + 0.5 * std::sin(a));
        obj += line;
    }
    obj += "f";
    for (int i = 1; i <= n; ++i) obj += " " + std::to_string(i) + "/" + std::to_string(i);
    obj += "\n";
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("disc.obj", obj));
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(warnings, "");
    ASSERT_EQ(m.triangle_count(), std::size_t(n - 2));
    double area = 0.0;
    std::vector<int> around(m.weld_count, 0);
    for (std::size_t t = 0; t < m.indices.size(); t += 3) {
        const glm::dvec3 a(m.vertices[m.indices[t]].position), b(m.vertices[m.indices[t + 1]].position),
            c(m.vertices[m.indices[t + 2]].position);
        const double z = glm::cross(b - a, c - a).z;
        EXPECT_GT(z, 0.0) << t / 3;
        area += 0.5 * z;
        for (int k = 0; k < 3; ++k) ++around[m.vertices[m.indices[t + std::size_t(k)]].weld_id];
    }
    EXPECT_NEAR(area, 0.5 * n * std::sin(2.0 * 3.14159265358979323846 / n), 1e-6);
    EXPECT_LE(*std::max_element(around.begin(), around.end()), 24); // the fan: 998
}

// Degenerate triangles of a mesh far from the origin for its size, in a file of floats: the
// warning says why (a binary or ASCII STL in geographic coordinates lost half a torus's triangles
// with no word of the cause; found by an exploratory session).
TEST(MeshLoad, DegenerateTrianglesFromCoarseFloatsSaySo)
{
    TempDir dir;
    const std::string stl = "solid far\n"
                            "facet normal 0 0 1\nouter loop\nvertex 10000000 0 0\nvertex 10000002 0 0\nvertex 10000000 2 0\nendloop\nendfacet\n"
                            "facet normal 0 0 1\nouter loop\nvertex 10000000 3 0\nvertex 10000000.3 3 0\nvertex 10000000 4 0\nendloop\nendfacet\n"
                            "endsolid far\n";
    // The same two triangles in a binary PLY of floats, which the scan reads too (exactly: they are
    // floats), and says so as well.
    std::string ply = "ply\nformat binary_little_endian 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n";
    const float corners[6][3] = {{10000000, 0, 0}, {10000002, 0, 0}, {10000000, 2, 0},
                                 {10000000, 3, 0}, {10000000.3f, 3, 0}, {10000000, 4, 0}};
    ply.append(reinterpret_cast<const char*>(corners), sizeof corners);
    for (const std::int32_t f : {0, 3}) {
        const std::int32_t corner[3] = {f, f + 1, f + 2};
        ply += char(3);
        ply.append(reinterpret_cast<const char*>(corner), sizeof corner);
    }
    for (const auto& [name, text] : {std::pair<std::string, std::string>{"far.stl", stl}, {"far.ply", ply}}) {
        ::testing::internal::CaptureStderr();
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, text));
        const std::string warnings = ::testing::internal::GetCapturedStderr();
        EXPECT_EQ(m.dropped_triangles, 1u) << name;
        EXPECT_NE(warnings.find("dropped 1 degenerate (zero-area) triangle (its coordinates are far from the origin for "
                                "its size, beyond what its file's 32-bit floats keep"),
                  std::string::npos)
            << name << ": " << warnings;
    }
}

TEST(MeshErrors, PlyFacesBeforeVerticesAreNamed)
{
    TempDir dir;
    const fs::path p = dir.write("fv.ply", "ply\nformat ascii 1.0\nelement face 1\nproperty list uchar int vertex_indices\n"
                                           "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                                           "end_header\n3 0 1 2\n0 0 0\n1 0 0\n0 1 0\n");
    EXPECT_ERROR_MENTIONS(load_error(p), p, "PLY element 'face' comes before 'vertex', which the reader cannot take");
}

// One OBJ face listing a triangle's corners 30,000 times: its outline is cut into its loops in one
// walk, and the copies of the triangle are dropped as repeated faces are (before: 21 s to load,
// every edge shared by 30,000 coincident triangles, and the prism timed out; found by an
// exploratory session). Each copy used to pass for a convex polygon's ear too, in both windings.
TEST(MeshLoad, TriangleRepeatedInOneFaceIsDroppedQuickly)
{
    TempDir dir;
    std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf";
    for (int i = 0; i < 30000; ++i) text += " 1 2 3";
    const fs::path p = dir.write("rep.obj", text + "\n");
    const auto start = std::chrono::steady_clock::now();
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(p);
    const std::string said = ::testing::internal::GetCapturedStderr();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_GT(face_normal(m, 0).z, 0.0f);
    EXPECT_NE(said.find("dropped 29999 triangles that repeat another of the same face (1 face whose outline runs over "
                        "itself; the first is kept)"),
              std::string::npos)
        << said;
    EXPECT_EQ(said.find("more than two faces"), std::string::npos) << said;
    EXPECT_LT(seconds, 3.0 * kSlower);

    // A concave hexagon (an L) listed 20,000 times: clipped once per loop, each copy dropped.
    std::string l = "v 0 0 0\nv 2 0 0\nv 2 1 0\nv 1 1 0\nv 1 2 0\nv 0 2 0\nf";
    for (int i = 0; i < 20000; ++i) l += " 1 2 3 4 5 6";
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh lm = pr::load_mesh(dir.write("l.obj", l + "\n"));
    EXPECT_NE(::testing::internal::GetCapturedStderr().find("dropped 79996 triangles that repeat"), std::string::npos);
    EXPECT_EQ(lm.triangle_count(), 4u);
    double area = 0.0;
    for (std::size_t t = 0; t < lm.triangle_count(); ++t) area += 0.5 * double(face_normal(lm, t).z);
    EXPECT_NEAR(area, 3.0, 1e-6);
}

// Many faces sharing an edge, none a repeat (300,000 pages of a book on one spine): finding the
// faces across each edge for the generated UVs scanned the triangles around an edge's end, the
// square of their number where thousands meet at both ends (30,000 copies of a triangle took
// 21 s so; 100,000 pages about 6 s; now edges are sorted). 300,000 pages (by the square about
// 54 s the old way, 1.2 s now) keep the bound far from both: with 100,000 pages and a bound of
// 3 s it failed once on a machine busy with a second test suite (fifty-first session).
TEST(MeshLoad, ManyFacesOnOneEdgeLoadQuickly)
{
    TempDir dir;
    const int pages = 300000;
    std::string text = "v 0 0 0\nv 1 0 0\n";
    char line[96];
    for (int i = 0; i < pages; ++i) {
        const double a = 3.14159265358979 * i / pages;
        std::snprintf(line, sizeof line, "v 0.5 %.9f %.9f\n", std::cos(a), std::sin(a));
        text += line;
    }
    for (int i = 0; i < pages; ++i) text += "f 1 2 " + std::to_string(i + 3) + "\n";
    const fs::path p = dir.write("book.obj", text);
    const auto start = std::chrono::steady_clock::now();
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(p);
    ::testing::internal::GetCapturedStderr();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_EQ(m.triangle_count(), std::size_t(pages));
    EXPECT_LT(seconds, 15.0 * kSlower);
}

// A circle of 200,000 corners in one face, its positions floats: neighbours 3e-5 apart bend by
// 1e-10, far below float rounding, so about half of its corners turned right or not at all, and
// it was "a concave polygon too large to clip … triangulated as a fan, which may cover area
// outside its outline" (a fan of slivers the prism took 14 s a frame to cross at 50,000 corners;
// found by an exploratory session). Convex to float precision, it is cut by rounds of ears: no
// warning, no triangle wound the other way, its area, and few triangles at any corner.
TEST(MeshLoad, FineCircleInFloatsIsConvex)
{
    TempDir dir;
    const int n = 200000;
    std::string text = "OFF\n" + std::to_string(n) + " 1 0\n";
    char line[96];
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.14159265358979323846 * i / n;
        std::snprintf(line, sizeof line, "%.17g %.17g 0\n", std::cos(a), std::sin(a));
        text += line;
    }
    text += std::to_string(n);
    for (int i = 0; i < n; ++i) text += " " + std::to_string(i);
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("circle.off", text + "\n"));
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(said.find("concave"), std::string::npos) << said;
    double area = 0.0;
    int negative = 0;
    std::vector<int> around(m.weld_count, 0);
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const float z = face_normal(m, t).z;
        negative += z < 0.0f;
        area += 0.5 * double(z);
        for (int k = 0; k < 3; ++k) ++around[m.vertices[m.indices[3 * t + std::size_t(k)]].weld_id];
    }
    EXPECT_EQ(negative, 0);
    EXPECT_NEAR(area, 3.14159265358979, 1e-4);
    EXPECT_EQ(m.triangle_count() + m.dropped_triangles, std::size_t(n - 2));
    EXPECT_LE(*std::max_element(around.begin(), around.end()), 40);
    EXPECT_EQ(m.weld_count, std::uint32_t(n));

    // A real dent made of many small turns, each within rounding, is not convex: the circle with
    // 2,000 of its corners pushed in behind the chord across them.
    std::string dent = "OFF\n" + std::to_string(n) + " 1 0\n";
    const double a0 = 2.0 * 3.14159265358979323846 * 1000 / n;
    for (int i = 0; i < n; ++i) {
        const double a = 2.0 * 3.14159265358979323846 * i / n;
        double x = std::cos(a), y = std::sin(a);
        if (i < 1000 || i > n - 1000) {
            const double s = std::sin(3.14159265358979 * (i < 1000 ? 1000 - i : i - n + 1000) / 2000.0);
            x = std::cos(a0) - 0.01 * s * s; // smooth: every turn within rounding, 0.01 deep
        }
        std::snprintf(line, sizeof line, "%.17g %.17g 0\n", x, y);
        dent += line;
    }
    dent += std::to_string(n);
    for (int i = 0; i < n; ++i) dent += " " + std::to_string(i);
    ::testing::internal::CaptureStderr();
    pr::load_mesh(dir.write("dent.off", dent + "\n"));
    EXPECT_NE(::testing::internal::GetCapturedStderr().find("1 concave polygon too large to clip"), std::string::npos);
}

// OpenMesh stops after the elements a header counts: a cube whose OFF or PLY header counts 1 face
// drew one (exit 0, no word), and garbage after the last face was read past. What follows the
// counted elements must be white space (or, in an OFF, comments); found by an exploratory session.
TEST(MeshErrors, ContentAfterTheCountedElementsIsRefused)
{
    TempDir dir;
    const std::string verts = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n";
    const fs::path off = dir.write("under.off", "OFF\n4 1 0\n" + verts + "3 0 1 2\n3 1 3 2\n");
    EXPECT_ERROR_MENTIONS(load_error(off), off, "line 8: '3 1 3 2' follows the 1 face the header counts (is its face count too small?)");
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
                             "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
    const fs::path ply = dir.write("under.ply", head + verts + "3 0 1 2\n3 1 3 2\n");
    EXPECT_ERROR_MENTIONS(load_error(ply), ply, "line 15: '3 1 3 2' follows the elements the header counts (1 face; is a count too small?)");
    // Blank lines, and comments in an OFF, may follow.
    const pr::PreparedMesh m = pr::load_mesh(dir.write("ok.off", "OFF\n4 1 0\n" + verts + "3 0 1 2\n\n# end\n  \n"));
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(pr::load_mesh(dir.write("ok.ply", head + verts + "3 0 1 2\n\n")).triangle_count(), 1u);
    // Binary PLY: bytes after the last face (white space may follow, as after a binary OFF).
    std::vector<char> bin;
    const std::string bhead = "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                              "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
    bin.assign(bhead.begin(), bhead.end());
    for (const float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) put(bin, v);
    bin.push_back(3);
    for (const std::int32_t i : {0, 1, 2}) put(bin, i);
    std::vector<char> trailing = bin;
    for (char c : std::string("xxxx")) trailing.push_back(c);
    const fs::path bt = dir.write_bytes("trail.ply", trailing);
    EXPECT_ERROR_MENTIONS(load_error(bt), bt, "binary PLY has 4 bytes after the elements the header counts (1 face; is a count too small?)");
    bin.push_back('\n');
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("nl.ply", bin)).triangle_count(), 1u);
    // Elements of fixed-size items are walked in one step (an element without properties counted
    // by the billion took 1.5 s item by item): two items of 3 bytes after the faces are counted,
    // one more byte is not.
    const std::string xhead = bhead.substr(0, bhead.size() - 11) + "element extra 2\nproperty uchar a\nproperty short b\n"
                                                                  "element nothing 4000000000\nend_header\n";
    std::vector<char> xbin(xhead.begin(), xhead.end());
    xbin.insert(xbin.end(), bin.begin() + std::ptrdiff_t(bhead.size()), bin.end() - 1);
    for (int i = 0; i < 6; ++i) xbin.push_back(char(i));
    EXPECT_EQ(pr::load_mesh(dir.write_bytes("extra.ply", xbin)).triangle_count(), 1u);
    xbin.push_back('x');
    const fs::path xt = dir.write_bytes("extra_trail.ply", xbin);
    EXPECT_ERROR_MENTIONS(load_error(xt), xt, "binary PLY has 1 byte");
}

// Messages that named the wrong thing (found by an exploratory session).
TEST(MeshErrors, MessagesNameWhatIsWrong)
{
    TempDir dir;
    // The early size check took 8 bytes for any face, a triangle's: a face "0" or "2 0 1" was "more
    // than a file of … bytes can hold". Any line takes 2.
    const fs::path f0 = dir.write("f0.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n");
    EXPECT_ERROR_MENTIONS(load_error(f0), f0, "line 6: face 0 has fewer than 3 vertices");
    const fs::path f2 = dir.write("f2.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                            "end_header\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n");
    EXPECT_ERROR_MENTIONS(load_error(f2), f2, "face 0 has fewer than 3 vertices");
    // The shortest OFF loads: no line end after its face, no edge count.
    EXPECT_EQ(pr::load_mesh(dir.write("min.off", "OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2")).triangle_count(), 1u);
    // An OFF on one line: the reader takes a vertex a line.
    const fs::path one = dir.write("one.off", "OFF\n3 1 0 0 0 0 1 0 0 0 1 0 3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(one), one, "line 2: values after the vertex, face and edge counts: each vertex and each face must be on a line of its own");
    // An ASCII PLY vertex line short of a value took the next line's first.
    const fs::path sv = dir.write("sv.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                            "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                                            "end_header\n0 0\n1 0 0 0\n0 1 0\n3 0 1 2\n");
    EXPECT_ERROR_MENTIONS(load_error(sv), sv, "line 10: vertex line has 2 values; its 3 properties call for 3");
    // CR line ends: "contains no faces", "the counts must be on the line after 'OFF'".
    for (const auto& [name, text] : {std::pair<std::string, std::string>{"cr.obj", "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r"},
                                     {"cr.off", "OFF\r3 1 0\r0 0 0\r1 0 0\r0 1 0\r3 0 1 2\r"},
                                     {"cr.ply", "ply\rformat ascii 1.0\relement vertex 3\r"}}) {
        const fs::path p = dir.write(name, text);
        EXPECT_ERROR_MENTIONS(load_error(p), p, "uses CR line ends (classic Mac OS)");
    }
    // A NaN texture coordinate was "(1D texture coordinates are not supported)".
    const fs::path vt = dir.write("vt.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0\nf 1/1 2/1 3/1\n");
    EXPECT_ERROR_MENTIONS(load_error(vt), vt, "line 4: texture coordinate value 'nan' is not a finite number");
    // A normal index past the normals was taken without a word; every index is checked.
    const fs::path vn = dir.write("vn.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//5 2//5 3//5\n");
    EXPECT_ERROR_MENTIONS(load_error(vn), vn, "line 5: normal index 5 is out of range (the file has 1)");
    const fs::path vnneg = dir.write("vnneg.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-2 2//1 3//1\n");
    EXPECT_ERROR_MENTIONS(load_error(vnneg), vnneg, "normal index -2 is out of range (1 so far)");
    EXPECT_EQ(pr::load_mesh(dir.write("vnok.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//-1 3//1\n")).triangle_count(), 1u);
}

// Texture coordinates past 2^20, where a float resolves no finer than an eighth of a repeat: the
// prism drew nothing at 1e38 (a warning to check the camera) and a flat colour at 1e20, where the
// reference drew the object (found by an exploratory session). Refused, the file's and generated
// ones alike; up to 2^20 they load.
TEST(MeshErrors, TextureCoordinatesPastSinglePrecisionAreRefused)
{
    TempDir dir;
    const auto triangle = [&](const char* name, const char* u) {
        return dir.write(name, std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt ") + u + " 0\nvt 0 1\nf 1/1 2/2 3/3\n");
    };
    EXPECT_ERROR_MENTIONS(load_error(triangle("big.obj", "1e38")), triangle("big.obj", "1e38"),
                          "texture coordinates reach 1e+38, past 1048576 (2^20)");
    EXPECT_NE(load_error(triangle("neg.obj", "-2e6")).problem().find("scale them down in the file"), std::string::npos);
    EXPECT_NO_THROW(pr::load_mesh(triangle("edge.obj", "1048576")));
    pr::MeshOptions huge;
    huge.force_generated_uvs = true;
    huge.uv_scale = 1e7f;
    const pr::Error e = load_error(triangle("gen.obj", "1"), huge);
    EXPECT_NE(e.problem().find("generated texture coordinates reach"), std::string::npos) << e.problem();
    EXPECT_NE(e.problem().find("use a smaller --uv-scale"), std::string::npos) << e.problem();
}

// ASCII STL is words separated by any white space, keywords in either case: a blank line among a
// facet's vertices, a facet on one line and "Outer Loop" were refused (OpenMesh's reader goes by
// lines; the file is handed to it one keyword a line). The same octahedron in each shape.
TEST(MeshLoad, AsciiStlIsReadWordByWord)
{
    TempDir dir;
    const std::string lines = octa_stl_ascii();
    std::string blank, one_line, mixed_case, cr_only, extra_numbers;
    for (char c : lines) {
        blank += c;
        if (c == '\n') blank += "\n \r\n"; // a blank line after each line
        one_line += c == '\n' ? ' ' : c;
        cr_only += c == '\n' ? '\r' : c; // (old Mac OS line ends)
    }
    for (std::size_t from = 0, at; (at = lines.find('\n', from)) != std::string::npos; from = at + 1) {
        extra_numbers += lines.substr(from, at - from); // "vertex x y z 7": the reader ignored the 7
        if (lines.compare(from, 12, "      vertex") == 0) extra_numbers += " 7";
        extra_numbers += '\n';
    }
    for (std::size_t i = 0; i < lines.size(); ++i) // "Outer Loop", "Vertex", "EndFacet", …
        mixed_case += (i == 0 || lines[i - 1] == ' ' || lines[i - 1] == '\n') ? char(std::toupper(lines[i])) : lines[i];
    const pr::PreparedMesh base = pr::load_mesh(dir.write("lines.stl", lines));
    // Each triangle's corners, sorted, the triangles sorted: the same facets of the same points.
    const auto facets = [](const pr::PreparedMesh& m) {
        std::vector<std::array<float, 9>> all;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            std::array<glm::vec3, 3> c{m.vertices[m.indices[t]].position, m.vertices[m.indices[t + 1]].position,
                                       m.vertices[m.indices[t + 2]].position};
            std::sort(c.begin(), c.end(), [](const glm::vec3& a, const glm::vec3& b) {
                return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
            });
            all.push_back({c[0].x, c[0].y, c[0].z, c[1].x, c[1].y, c[1].z, c[2].x, c[2].y, c[2].z});
        }
        std::sort(all.begin(), all.end());
        return all;
    };
    for (const auto& [name, text] : std::vector<std::pair<std::string, std::string>>{
             {"blank.stl", blank}, {"one_line.stl", "solid octa\n" + one_line.substr(11)}, {"mixed.stl", mixed_case},
             {"cr.stl", cr_only}, {"extra.stl", extra_numbers}}) {
        SCOPED_TRACE(name);
        const pr::PreparedMesh m = pr::load_mesh(dir.write(name, text));
        expect_sane(m);
        EXPECT_EQ(m.triangle_count(), base.triangle_count());
        EXPECT_EQ(facets(m), facets(base));
    }
    // The whole file on one line: the facets are the solid's name, as the reader takes them (it
    // said "contains no faces"; found by an exploratory session, fifty-first).
    EXPECT_ERROR_MENTIONS(load_error(dir.write("all_one.stl", one_line)), dir.path() / "all_one.stl",
                          "line 1: facets on the 'solid' line, whose rest is the solid's name: each facet must "
                          "start on a line of its own");
    // A line of bare numbers among a facet's vertices is no vertex's rest: refused (a vertex line
    // that lost its keyword was dropped without a word; found by a review).
    std::string stray = lines;
    stray.insert(stray.find("      vertex", stray.find("      vertex") + 1), "      5 5 5\n"); // (line 5)
    EXPECT_ERROR_MENTIONS(load_error(dir.write("stray.stl", stray)), dir.path() / "stray.stl",
                          "line 5: expected 'vertex x y z' with finite numbers");
}

// OFF files as other writers leave them (found by an exploratory session, fifty-first): white
// space before the header's keyword ("could not be read as off (the reader reported a failure)"),
// and a face colour after a face's indices without a C header (Geomview allows one in any OFF;
// OpenMesh read it as the next face's values, and the message asked for a COFF header, which is
// vertex colours). Colours are read, not used; other values there are refused.
TEST(MeshLoad, OffIndentedHeaderAndFaceColoursAreRead)
{
    TempDir dir;
    const std::string square = "4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
    for (const std::string& head : {std::string(" OFF\n"), std::string("\t  OFF\n")}) {
        const pr::PreparedMesh m = pr::load_mesh(dir.write("indented.off", head + square + "3 0 1 2\n3 0 2 3\n"));
        expect_sane(m);
        EXPECT_EQ(m.triangle_count(), 2u);
    }
    for (const std::string& colour : {std::string(" 7"), std::string(" 1 0 0"), std::string(" 0.5 0.5 0.5 1"),
                                      std::string("  255\t0 0 # red")}) {
        SCOPED_TRACE(colour);
        const pr::PreparedMesh m =
            pr::load_mesh(dir.write("coloured.off", "OFF\n" + square + "3 0 1 2" + colour + "\n3 0 2 3" + colour + "\n"));
        expect_sane(m);
        ASSERT_EQ(m.triangle_count(), 2u);
        float area = 0.0f;
        for (std::size_t t = 0; t + 2 < m.indices.size(); t += 3) {
            const glm::vec3 a = m.vertices[m.indices[t]].position, b = m.vertices[m.indices[t + 1]].position,
                            c = m.vertices[m.indices[t + 2]].position;
            area += 0.5f * glm::length(glm::cross(b - a, c - a));
        }
        EXPECT_NEAR(area, 1.0f, 1e-5f); // the whole square
    }
    // (A form feed or vertical tab there too.)
    expect_sane(pr::load_mesh(dir.write("ff.off", "\f\v OFF\n" + square + "3 0 1 2\n3 0 2 3\n")));
    const auto message = [&](const std::string& face, const std::string& header = "OFF") {
        return prtest::error_of([&] {
                   pr::load_mesh(dir.write("bad.off", header + "\n" + square + face + "\n3 0 2 3\n"));
               })
            .problem();
    };
    // After a C header OpenMesh takes the rest of a face's line itself, and ignored words there.
    EXPECT_EQ(message("3 0 1 2 foo bar", "COFF"),
              "line 7: face 0 has 2 values after its vertex indices, which are not a colour (1, 3 or 4 numbers)");
    EXPECT_EQ(message("3 0 1 2 1 0"),
              "line 7: face 0 has 2 values after its vertex indices, which are not a colour (1, 3 or 4 numbers)");
    EXPECT_EQ(message("3 0 1 2 red"),
              "line 7: face 0 has 1 value after its vertex indices, which are not a colour (1, 3 or 4 numbers)");
}

// MeshLab writes per-vertex texture coordinates as texture_u texture_v: read as u v (they were
// reported as not read, and UVs generated; found by an exploratory session, fifty-first), in
// ASCII and binary, where the vertex has no u v or s t of its own.
TEST(MeshLoad, PlyTextureUvNamesAreRead)
{
    TempDir dir;
    const std::string head = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                             "property float z\nproperty float texture_u\nproperty float texture_v\n";
    const std::string tail = "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                             "0 0 0 0 0\n2 0 0 1 0\n0 2 0 0 1\n3 0 1 2\n";
    ::testing::internal::CaptureStderr();
    const pr::PreparedMesh m = pr::load_mesh(dir.write("t.ply", head + tail));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    EXPECT_TRUE(m.had_uvs);
    for (const pr::MeshVertex& v : m.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position) / 2.0f);
    // With u v as well, u v are read and texture_u texture_v not.
    const pr::PreparedMesh both = pr::load_mesh(dir.write(
        "b.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
                 "property float texture_u\nproperty float texture_v\nproperty float u\nproperty float v\n"
                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                 "0 0 0 9 9 0 0\n2 0 0 9 9 1 0\n0 2 0 9 9 0 1\n3 0 1 2\n"));
    EXPECT_TRUE(both.had_uvs);
    for (const pr::MeshVertex& v : both.vertices) EXPECT_EQ(v.uv, glm::vec2(v.position) / 2.0f);
    // Other names are said not to be read (not only "no texture coordinates").
    std::string other = head + tail;
    for (const char* name : {"texture_u", "texture_v"}) other.replace(other.find(name), 9, std::string("tex_") + name[8]);
    ::testing::internal::CaptureStderr();
    EXPECT_FALSE(pr::load_mesh(dir.write("o.ply", other)).had_uvs);
    const std::string said = ::testing::internal::GetCapturedStderr();
    EXPECT_NE(said.find("o.ply: vertex properties tex_u, tex_v are not read as texture coordinates (u v or s t are)"),
              std::string::npos)
        << said;
}

// MeshLab's per-corner texture coordinates: a `texcoord` list on each face, u v for each corner in
// the face's order (OpenMesh's reader took it for more indices: "face 1 has fewer than 3
// vertices"; refused by name until the fifty-first session). Read in ASCII and binary, the list
// taken out of what the reader sees; a scalar after it (MeshLab's texnumber) is skipped.
TEST(MeshLoad, PlyFaceTexcoordListsAreRead)
{
    TempDir dir;
    const std::string head = "ply\nformat FORMAT 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                             "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
                             "property list uchar float texcoord\nproperty int texnumber\nend_header\n";
    const auto header = [&](const std::string& format) {
        std::string h = head;
        return h.replace(h.find("FORMAT"), 6, format);
    };
    // A square from (0,0) to (2,2), each corner's UV its position halved, the second face's UVs
    // shifted by 1 in u (a seam along the diagonal: the two faces' corners there differ).
    const float xy[4][2] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
    const int faces[2][3] = {{0, 1, 2}, {0, 2, 3}};
    const auto expect_uvs = [&](const pr::PreparedMesh& m) {
        EXPECT_TRUE(m.had_uvs);
        ASSERT_EQ(m.triangle_count(), 2u);
        EXPECT_EQ(m.vertices.size(), 6u); // (split along the seam)
        for (std::size_t t = 0; t < 2; ++t)
            for (std::size_t c = 0; c < 3; ++c) {
                const pr::MeshVertex& v = m.vertices[m.indices[3 * t + c]];
                // Which face the triangle is: the second holds (0, 2).
                const bool second = std::any_of(m.indices.begin() + std::ptrdiff_t(3 * t),
                                                m.indices.begin() + std::ptrdiff_t(3 * t + 3), [&](std::uint32_t i) {
                                                    return m.vertices[i].position == glm::vec3(0, 2, 0);
                                                });
                EXPECT_EQ(v.uv, glm::vec2(v.position) / 2.0f + glm::vec2(second ? 1.0f : 0.0f, 0.0f));
            }
    };
    std::string ascii = header("ascii");
    for (const auto& p : xy) ascii += std::to_string(p[0]) + " " + std::to_string(p[1]) + " 0\n";
    for (int f = 0; f < 2; ++f) {
        ascii += "3";
        for (int i : faces[f]) ascii += " " + std::to_string(i);
        ascii += " 6";
        for (int i : faces[f]) ascii += " " + std::to_string(xy[i][0] / 2 + f) + " " + std::to_string(xy[i][1] / 2);
        ascii += " 0\n";
    }
    ::testing::internal::CaptureStderr();
    expect_uvs(pr::load_mesh(dir.write("a.ply", ascii)));
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    // Binary, face 0's list holding `first` of its corners' pairs.
    const auto binary = [&](int first) {
        const std::string hb = header("binary_little_endian");
        std::vector<char> b(hb.begin(), hb.end());
        for (const auto& p : xy)
            for (float v : {p[0], p[1], 0.0f}) put(b, v);
        for (int f = 0; f < 2; ++f) {
            put<std::uint8_t>(b, 3);
            for (int i : faces[f]) put<std::int32_t>(b, i);
            put<std::uint8_t>(b, std::uint8_t(f == 0 ? 2 * first : 6));
            for (int c = 0; c < (f == 0 ? first : 3); ++c) {
                put(b, xy[faces[f][c]][0] / 2 + float(f));
                put(b, xy[faces[f][c]][1] / 2);
            }
            put<std::int32_t>(b, 0);
        }
        return b;
    };
    expect_uvs(pr::load_mesh(dir.write_bytes("b.ply", binary(3))));
    // A list of the wrong length, and another list: said.
    std::string short_list = ascii;
    short_list.replace(short_list.find(" 6 "), 3, " 4 ");
    EXPECT_EQ(prtest::error_of([&] { pr::load_mesh(dir.write("s.ply", short_list)); }).problem(),
              "line 16: face 0's texcoord list counts 4 values; its 3 corners call for 6 (u v each)");
    std::string long_list = ascii;
    long_list.replace(long_list.find(" 6 "), 3, " 60 ");
    EXPECT_EQ(prtest::error_of([&] { pr::load_mesh(dir.write("l.ply", long_list)); }).problem(),
              "line 16: face line has 12 values; its texcoord list counts 60, past the line's end");
    EXPECT_EQ(prtest::error_of([&] { pr::load_mesh(dir.write_bytes("sb.ply", binary(2))); }).problem(),
              "binary PLY face 0's texcoord list counts 4 values; its 3 corners call for 6 (u v each)");
    // A count that puts the next face's start off (4 where 6 values follow): said at its face,
    // not at the next one, which then read from the middle of the list.
    std::vector<char> miscounted = binary(3);
    miscounted[header("binary_little_endian").size() + 4 * 12 + 1 + 3 * 4] = 4;
    EXPECT_EQ(prtest::error_of([&] { pr::load_mesh(dir.write_bytes("mb.ply", miscounted)); }).problem(),
              "binary PLY face 0's texcoord list counts 4 values; its 3 corners call for 6 (u v each)");
    std::string other = ascii;
    other.replace(other.find("texcoord"), 8, "texcoords");
    EXPECT_EQ(prtest::error_of([&] { pr::load_mesh(dir.write("o.ply", other)); }).problem(),
              "PLY face element has a list property 'texcoords' besides vertex_indices, which is not read (texture "
              "coordinates are read per vertex, as u v or s t, or per face as one texcoord list)");
}
