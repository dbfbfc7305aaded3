// render --msaa: passes sampling each pixel at the standard sample positions, resolved into
// alpha = the fraction of samples covered (render/multisample.hpp).
#include "gl_fixture.hpp"

#include "core/error.hpp"
#include "render/multisample.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <utility>

using namespace pr;

namespace {

constexpr int kSize = 96;

Camera camera(glm::vec3 eye)
{
    Camera c;
    c.eye = eye;
    c.target = {0, 0, 0};
    c.near_plane = 1.0f;
    c.far_plane = 10.0f;
    return c;
}

RgbaImage draw(Renderer& r, const Camera& c, Technique t, glm::vec2 offset)
{
    DrawSettings s;
    s.technique = t;
    s.pixel_offset = offset;
    r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.5f, 1.0f)), s);
    return r.read_color();
}

} // namespace

TEST(Multisample, StandardPositionsLieInsideThePixel)
{
    for (const int n : {1, 2, 4, 8, 16}) {
        const auto offsets = sample_offsets(n);
        ASSERT_EQ(offsets.size(), std::size_t(n));
        std::set<std::pair<float, float>> distinct;
        for (const glm::vec2 o : offsets) {
            EXPECT_LE(std::abs(o.x), 0.5f) << n;
            EXPECT_LE(std::abs(o.y), 0.5f) << n;
            distinct.insert({o.x, o.y});
        }
        EXPECT_EQ(distinct.size(), std::size_t(n));
    }
    EXPECT_THROW(sample_offsets(3), Error);
    EXPECT_THROW(sample_offsets(32), Error);
}

// A whole-pixel offset moves the image by exactly the opposite pixel, for the prism too (its
// rays, depth and discards all go through the shifted projection): each pixel sampling the scene
// one pixel right and one down, the image is the first one moved one pixel left and one up, but
// for a few ties on edges.
TEST(Multisample, AnOffsetShiftsThePrismsImage)
{
    prtest::context();
    Renderer r(kSize, kSize);
    const Scene scene = prtest::one_object(
        prtest::square(1.0f), prtest::height_from(32, [](float u, float v) {
            return 0.5f + 0.5f * std::sin(12.0f * u) * std::sin(9.0f * v);
        }),
        0.3f);
    r.upload(scene);
    const Camera c = camera({1.5f, -2.0f, 4.0f});
    const RgbaImage a = draw(r, c, Technique::Prism, {0.0f, 0.0f});
    const RgbaImage b = draw(r, c, Technique::Prism, {1.0f, -1.0f});
    ASSERT_GT(prtest::coverage(a), std::size_t(kSize * kSize / 8));
    int differ = 0;
    for (int y = 1; y < kSize; ++y)
        for (int x = 0; x + 1 < kSize; ++x) {
            const auto p = a.at(x + 1, y - 1), q = b.at(x, y);
            differ += std::max({std::abs(p.r - q.r), std::abs(p.g - q.g), std::abs(p.b - q.b), std::abs(p.a - q.a)}) > 2;
        }
    EXPECT_LE(differ, kSize * kSize / 200) << "of " << kSize * kSize;
}

// A flat square seen head on: pixels inside are 255, outside 0, and along the edges alpha is the
// share of the pixel inside the edge, to within the 16 samples' resolution.
TEST(Multisample, AlphaIsTheCoveredShareOfThePixel)
{
    prtest::context();
    Renderer r(kSize, kSize);
    const Scene scene = prtest::one_object(prtest::square(1.0f), prtest::height_from(8, [](float, float) { return 0.5f; }), 0.0f);
    r.upload(scene);
    const Camera c = camera({0, 0, 5});
    SampleResolve resolve;
    for (const glm::vec2 o : sample_offsets(16)) resolve.add(draw(r, c, Technique::Flat, o));
    const RgbaImage img = resolve.result();
    const float half = kSize * 0.5f / (5.0f * std::tan(glm::radians(20.0f))); // square's half-width, pixels
    const auto inside_1d = [&](float p) { // share of [p, p + 1] within [kSize/2 - half, kSize/2 + half]
        return std::clamp(std::min(p + 1.0f, kSize * 0.5f + half) - std::max(p, kSize * 0.5f - half), 0.0f, 1.0f);
    };
    int darkest_full = 255;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x)
            if (img.at(x, y).a == 255) darkest_full = std::min<int>(darkest_full, img.at(x, y).r);
    int partial = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const float share = inside_1d(float(x)) * inside_1d(float(y));
            const int a = img.at(x, y).a;
            EXPECT_NEAR(a / 255.0f, share, 0.2f) << x << "," << y;
            partial += a > 0 && a < 255;
            // Straight colour: the covering samples' own, not darkened towards the background.
            if (a > 0) EXPECT_GE(img.at(x, y).r, darkest_full - 3) << x << "," << y;
        }
    EXPECT_GT(partial, 4 * int(2 * half) / 2) << "edges are blended";
}

// Each pass samples the scene at its standard position (x right, y up), not at the position turned
// by 180 degrees: the 16 positions are not symmetric about the centre (x from -8/16 to 7/16), so
// a vertical edge through a pixel gives it the share of the positions left of the edge. (Until the
// thirty-ninth session the image was shifted by the offset, which samples the scene at minus it:
// the same for 2 and 4 samples, not for 8 and 16; found by an exploratory session.)
TEST(Multisample, PassesSampleTheStandardPositions)
{
    prtest::context();
    Renderer r(kSize, kSize);
    const Scene scene = prtest::one_object(prtest::square(1.0f), prtest::height_from(8, [](float, float) { return 0.5f; }), 0.0f);
    r.upload(scene);
    const Camera c = camera({0, 0, 5.3f}); // the edge 0.88 of the way across its pixel, between positions
    const std::span<const glm::vec2> offsets = sample_offsets(16);
    SampleResolve resolve;
    for (const glm::vec2 o : offsets) resolve.add(draw(r, c, Technique::Flat, o));
    const RgbaImage img = resolve.result();
    const float edge = kSize * 0.5f + kSize * 0.5f / (5.3f * std::tan(glm::radians(20.0f))); // the right edge, pixels
    const int x = int(std::floor(edge));
    int left = 0, right = 0; // positions left of the edge, and of the turned ones
    for (const glm::vec2 o : offsets) {
        left += float(x) + 0.5f + o.x < edge;
        right += float(x) + 0.5f - o.x < edge;
    }
    ASSERT_NE(left, right) << "the edge falls where both patterns agree";
    for (int y = kSize / 2 - 4; y <= kSize / 2 + 4; ++y)
        EXPECT_NEAR(img.at(x, y).a, 255.0 * left / 16.0, 1.0) << "row " << y << "; the turned positions give " << 255.0 * right / 16.0;
}
