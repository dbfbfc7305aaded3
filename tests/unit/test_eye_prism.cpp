// The prism that holds the eye (src/render/eye_prism.hpp), on a flat square of two prisms.
#include "render/eye_prism.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <vector>

namespace {

// The unit square in the XZ plane facing +Y, as the renderer's shell corners (three texels per
// vertex: bottom corner and u, unit normal and v, tight top height and welded id), tops at 0.8,
// depth 0.1; u = x, v = z. Triangles (0, 1, 2) (where x >= z) and (0, 2, 3).
struct Square {
    std::vector<glm::vec4> corners;
    std::vector<std::uint32_t> indices{0, 1, 2, 0, 2, 3};
    Square()
    {
        const glm::vec3 p[4] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
        for (std::uint32_t i = 0; i < 4; ++i) {
            corners.emplace_back(p[i], p[i].x);
            corners.emplace_back(0.0f, 1.0f, 0.0f, p[i].z);
            corners.emplace_back(0.8f, std::bit_cast<float>(i), 0.0f, 0.0f);
        }
    }
};

constexpr float kDepth = 0.1f;

std::optional<pr::EyeInShell> find(const Square& s, glm::vec3 eye, float surface = 0.2f, bool full = false)
{
    return pr::find_eye_prism(s.corners, s.indices, pr::prism_blocks(s.corners, s.indices, kDepth), kDepth, full, eye,
                              [&](glm::vec2) { return surface; });
}

} // namespace

TEST(EyePrism, FindsThePrismAndWhereInItTheEyeIs)
{
    const Square s;
    const auto in = find(s, {0.7f, 0.05f, 0.2f});
    ASSERT_TRUE(in);
    EXPECT_EQ(in->prism, 0u);
    EXPECT_NEAR(in->tex.x, 0.7f, 1e-5f);
    EXPECT_NEAR(in->tex.y, 0.2f, 1e-5f);
    EXPECT_NEAR(in->tex.z, 0.5f, 1e-5f); // 0.05 of a depth of 0.1
    const auto other = find(s, {0.2f, 0.05f, 0.7f});
    ASSERT_TRUE(other);
    EXPECT_EQ(other->prism, 1u);
}

TEST(EyePrism, OnTheFaceTwoPrismsShareEitherHoldsIt)
{
    const Square s;
    const auto in = find(s, {0.5f, 0.05f, 0.5f});
    ASSERT_TRUE(in);
    EXPECT_NEAR(in->tex.x, 0.5f, 1e-5f);
    EXPECT_NEAR(in->tex.y, 0.5f, 1e-5f);
}

TEST(EyePrism, BlocksHoldTheirPrisms)
{
    // 200 squares in a row (400 triangles, seven blocks): the eye over each is found in it.
    Square one;
    std::vector<glm::vec4> corners;
    std::vector<std::uint32_t> indices;
    for (std::uint32_t q = 0; q < 200; ++q) {
        for (std::size_t i = 0; i < one.corners.size(); ++i) {
            glm::vec4 c = one.corners[i];
            if (i % 3 == 0) c.x += float(q);
            if (i % 3 == 2) c.y = std::bit_cast<float>(std::uint32_t(4 * q) + std::uint32_t(i / 3));
            corners.push_back(c);
        }
        for (std::uint32_t i : one.indices) indices.push_back(4 * q + i);
    }
    const pr::PrismBlocks blocks = pr::prism_blocks(corners, indices, kDepth);
    EXPECT_EQ(blocks.lo.size(), 7u);
    for (std::uint32_t q = 0; q < 200; q += 13) {
        const auto in = pr::find_eye_prism(corners, indices, blocks, kDepth, false,
                                           glm::vec3(float(q) + 0.7f, 0.05f, 0.2f), [](glm::vec2) { return 0.2f; });
        ASSERT_TRUE(in) << q;
        EXPECT_EQ(in->prism, 2 * q) << q;
        EXPECT_NEAR(in->tex.x, 0.7f, 1e-4f) << q; // (every square has u 0..1)
    }
}

TEST(EyePrism, NoneAboveTheTopOrBesideTheShell)
{
    const Square s;
    EXPECT_FALSE(find(s, {0.7f, 0.09f, 0.2f}));            // above the tight top (0.8 of the depth)
    EXPECT_TRUE(find(s, {0.7f, 0.09f, 0.2f}, 0.2f, true)); // the full shell goes to 1
    EXPECT_FALSE(find(s, {1.2f, 0.05f, 0.5f}));            // beside it
    EXPECT_FALSE(find(s, {0.7f, -0.01f, 0.2f}));           // under its bottom
}

TEST(EyePrism, SaysWhetherTheEyeIsUnderTheSurface)
{
    const Square s;
    const auto over = find(s, {0.7f, 0.05f, 0.2f}, 0.2f);  // height 0.5 over a surface at 0.2
    const auto under = find(s, {0.7f, 0.05f, 0.2f}, 0.6f); // under one at 0.6
    ASSERT_TRUE(over && under);
    EXPECT_FALSE(over->under);
    EXPECT_TRUE(under->under);
}

// A closed body: the unit cube's twelve triangles as bottom caps (normals outward). Inside it,
// and on the line through its centre and a corner or an edge (where a ray may meet an edge),
// the eye is in the body; outside it, not; a ray along a face plane leaves the vote to the others.
TEST(EyePrism, EyeInsideTheBodyByItsBottomCrossings)
{
    std::vector<glm::vec4> corners;
    const glm::vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    for (std::uint32_t i = 0; i < 8; ++i) {
        corners.emplace_back(p[i], 0.0f);
        corners.emplace_back(glm::normalize(p[i] - glm::vec3(0.5f)), 0.0f);
        corners.emplace_back(1.0f, std::bit_cast<float>(i), 0.0f, 0.0f);
    }
    const std::vector<std::uint32_t> indices{0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                             3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    const pr::PrismBlocks blocks = pr::prism_blocks(corners, indices, 0.1f);
    for (const glm::vec3 eye : {glm::vec3(0.5f), glm::vec3(0.1f, 0.2f, 0.9f), glm::vec3(0.25f, 0.25f, 0.25f),
                                glm::vec3(0.5f, 0.5f, 0.01f)})
        EXPECT_TRUE(pr::eye_inside_body(corners, indices, blocks, eye)) << eye.x << "," << eye.y << "," << eye.z;
    for (const glm::vec3 eye : {glm::vec3(1.5f, 0.5f, 0.5f), glm::vec3(-0.01f, 0.5f, 0.5f), glm::vec3(0.5f, 0.5f, -3.0f),
                                glm::vec3(5.0f)})
        EXPECT_FALSE(pr::eye_inside_body(corners, indices, blocks, eye)) << eye.x << "," << eye.y << "," << eye.z;
}

// Closed pieces of one mesh nested one in the other: an eye inside both counted two crossings,
// even, and was taken for outside (the prism drew nothing at all: IoU 0). Counted by winding, it
// is inside; inside a hollow solid's cavity (the inner piece wound inward) it is outside.
TEST(EyePrism, EyeInsideNestedBodiesByTheWindingOfBottomCrossings)
{
    const glm::vec3 p[8] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const std::uint32_t cube[36] = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                    3, 7, 6, 3, 6, 2, 0, 4, 7, 0, 7, 3, 1, 2, 6, 1, 6, 5};
    for (const bool hollow : {false, true}) {
        std::vector<glm::vec4> corners;
        std::vector<std::uint32_t> indices;
        for (int piece = 0; piece < 2; ++piece) {
            const float scale = piece == 0 ? 1.0f : 0.4f, offset = piece == 0 ? 0.0f : 0.3f;
            for (std::uint32_t i = 0; i < 8; ++i) {
                const std::uint32_t id = std::uint32_t(corners.size() / 3);
                corners.emplace_back(offset + scale * p[i], 0.0f);
                corners.emplace_back(glm::normalize(p[i] - glm::vec3(0.5f)), 0.0f);
                corners.emplace_back(1.0f, std::bit_cast<float>(id), 0.0f, 0.0f);
            }
            for (int t = 0; t < 12; ++t) {
                const std::uint32_t base = 8u * std::uint32_t(piece);
                const bool inward = hollow && piece == 1;
                indices.insert(indices.end(), {base + cube[3 * t], base + cube[3 * t + (inward ? 2 : 1)],
                                               base + cube[3 * t + (inward ? 1 : 2)]});
            }
        }
        const pr::PrismBlocks blocks = pr::prism_blocks(corners, indices, 0.1f);
        EXPECT_EQ(pr::eye_inside_body(corners, indices, blocks, glm::vec3(0.5f, 0.45f, 0.55f)), !hollow)
            << (hollow ? "in the cavity" : "inside both");
        EXPECT_TRUE(pr::eye_inside_body(corners, indices, blocks, glm::vec3(0.1f, 0.2f, 0.15f))) << "between them";
        EXPECT_FALSE(pr::eye_inside_body(corners, indices, blocks, glm::vec3(1.5f, 0.5f, 0.5f))) << "outside";
    }
}
