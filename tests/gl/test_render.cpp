// Pixel facts of the base-surface techniques on hand-made scenes (no file loaders involved).
#include "gl_fixture.hpp"

#include "mesh/mesh.hpp"

#include <cmath>

using namespace pr;

namespace {

constexpr int kSize = 128;

Camera front_camera()
{
    Camera c;
    c.eye = {0, 0, 5};
    c.target = {0, 0, 0};
    c.fovy_deg = 40.0f;
    c.near_plane = 1.0f;
    c.far_plane = 10.0f;
    return c;
}

RgbaImage draw(Renderer& r, const Camera& c, Technique t, std::vector<float>* depth = nullptr,
               int steps = 32)
{
    DrawSettings s;
    s.technique = t;
    s.steps = steps;
    s.depth_write = depth != nullptr;
    r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.5f, 1.0f)), s);
    if (depth) *depth = r.read_depth();
    return r.read_color();
}

int max_channel_difference(const RgbaImage& a, const RgbaImage& b, std::size_t pixel)
{
    int d = 0;
    for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(a.pixels[4 * pixel + c]) - int(b.pixels[4 * pixel + c])));
    return d;
}

} // namespace

// The square's outline is known exactly: pixel centres inside the projected square are
// covered. Allowed: pixels whose centre lies within 1e-3 px of an edge (rasterization ties).
TEST(Render, SquareCoverageMatchesTheAnalyticOutline)
{
    prtest::context();
    Renderer r(kSize, kSize);
    const Scene scene = prtest::one_object(prtest::square(1.0f), prtest::height_from(16, [](float, float) { return 0.5f; }), 0.0f);
    r.upload(scene);
    const RgbaImage img = draw(r, front_camera(), Technique::Flat);
    const float half_ndc = 1.0f / (5.0f * std::tan(glm::radians(20.0f))); // square edge in NDC
    int wrong = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const float nx = (x + 0.5f) / kSize * 2 - 1, ny = (y + 0.5f) / kSize * 2 - 1;
            const bool inside = std::abs(nx) < half_ndc && std::abs(ny) < half_ndc;
            const bool covered = img.at(x, y).a >= 128;
            wrong += inside != covered;
        }
    EXPECT_EQ(wrong, 0);
    // Alpha is exactly coverage: 0 or 255, no partial values without MSAA.
    for (std::size_t i = 3; i < img.pixels.size(); i += 4) EXPECT_TRUE(img.pixels[i] == 0 || img.pixels[i] == 255);
}

// Where the height is constant 1 (the polygon itself) every technique shows exactly the flat
// image; where it varies, POM shifts texels and normals so the images differ.
TEST(Render, FlatAndPomDifferOnlyWhereTheHeightVaries)
{
    prtest::context();
    Renderer r(kSize, kSize);
    // h = 1 on u < 0.5; bumps on u > 0.5 that rise back to 1 at u = 0.5 and u = 1, so filtering
    // (bilinear, mip levels, the Sobel neighbourhood, repeat wrap) sees no step at the borders.
    auto height = prtest::height_from(64, [](float u, float v) {
        if (u < 0.5f) return 1.0f;
        const float s = std::sin(6.2831853f * (u - 0.5f));
        return 1.0f - s * s * (0.5f + 0.5f * std::sin(6.2831853f * 4.0f * v));
    });
    const Scene scene = prtest::one_object(prtest::square(1.0f), height, 0.15f);
    r.upload(scene);
    Camera c = front_camera();
    c.eye = {1.5f, 1.5f, 4.5f};
    const RgbaImage flat = draw(r, c, Technique::Flat);
    const RgbaImage pom = draw(r, c, Technique::Pom);
    ASSERT_EQ(prtest::coverage(flat), prtest::coverage(pom));
    const glm::mat4 vp = c.projection(1.0f) * c.view();
    std::size_t left_diff = 0, right_diff = 0, right_total = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const std::size_t p = std::size_t(y) * kSize + x;
            if (flat.pixels[4 * p + 3] < 128) continue;
            // Which half of the square is this pixel? Project the square's centre line u = 0.5
            // (x = 0): pixels well left of it lie over h = 1.
            const glm::vec4 top = vp * glm::vec4(0, 1, 0, 1), bottom = vp * glm::vec4(0, -1, 0, 1);
            const glm::vec2 a = (glm::vec2(top) / top.w * 0.5f + 0.5f) * float(kSize);
            const glm::vec2 b = (glm::vec2(bottom) / bottom.w * 0.5f + 0.5f) * float(kSize);
            const float side = (b.x - a.x) * (y + 0.5f - a.y) - (b.y - a.y) * (x + 0.5f - a.x);
            const int d = max_channel_difference(flat, pom, p);
            if (side < -3.0f * glm::length(b - a)) left_diff += d > 1; // x < 0: u < 0.5
            if (side > 3.0f * glm::length(b - a)) {
                ++right_total;
                right_diff += d > 8;
            }
        }
    EXPECT_EQ(left_diff, 0u);
    ASSERT_GT(right_total, 1000u);
    EXPECT_GT(right_diff, right_total / 4) << "POM should change most pixels over varying heights";
}

// Depth 0: every base-surface technique renders exactly the flat image.
TEST(Render, DepthZeroRendersExactlyTheFlatImage)
{
    prtest::context();
    Renderer r(kSize, kSize);
    auto height = prtest::height_from(64, [](float u, float v) { return 0.5f + 0.5f * std::sin(20 * u) * std::cos(17 * v); });
    r.upload(prtest::one_object(prtest::square(1.0f), height, 0.0f));
    Camera c = front_camera();
    c.eye = {1.0f, 2.0f, 4.0f};
    const RgbaImage flat = draw(r, c, Technique::Flat);
    for (Technique t : {Technique::Normal, Technique::Offset, Technique::Steep, Technique::Pom, Technique::Relief}) {
        const RgbaImage img = draw(r, c, t);
        std::size_t differ = 0;
        for (std::size_t p = 0; p < std::size_t(kSize) * kSize; ++p) differ += max_channel_difference(flat, img, p) > 1;
        EXPECT_EQ(differ, 0u) << technique_name(t);
    }
}

// Grazing view of a bumpy square: every technique keeps the base outline, and no covered pixel
// is black or carries garbage (NaN shading ends up as 0 in RGBA8).
TEST(Render, GrazingAnglesGiveNoHolesAndNoBlackPixels)
{
    prtest::context();
    Renderer r(kSize, kSize);
    auto height = prtest::height_from(128, [](float u, float v) {
        return 0.5f + 0.5f * std::sin(u * 6.2831853f * 8.0f) * std::sin(v * 6.2831853f * 8.0f);
    });
    r.upload(prtest::one_object(prtest::square(1.0f, 2.0f), height, 0.2f));
    Camera c = front_camera();
    c.eye = {0.0f, -4.98f, 0.35f}; // about 4 degrees above the plane
    c.up = {0, 0, 1};
    c.near_plane = 0.5f;
    const RgbaImage flat = draw(r, c, Technique::Flat);
    ASSERT_GT(prtest::coverage(flat), 100u);
    for (const TechniqueInfo& t : technique_table()) {
        if (t.technique == Technique::Reference || t.technique == Technique::Prism)
            continue; // not base-surface techniques: their outline is not the base mesh's
        const RgbaImage img = draw(r, c, t.technique);
        EXPECT_EQ(prtest::coverage(img), prtest::coverage(flat)) << t.name;
        std::size_t black = 0;
        for (std::size_t p = 0; p < std::size_t(kSize) * kSize; ++p)
            if (img.pixels[4 * p + 3] >= 128)
                black += img.pixels[4 * p] + img.pixels[4 * p + 1] + img.pixels[4 * p + 2] == 0;
        EXPECT_EQ(black, 0u) << t.name;
    }
}

// --depth-write: the base-surface techniques carve inward, so the written depth lies behind the
// polygon wherever the height is below 1, and on it where the height is 1.
TEST(Render, DepthWriteCarvesBehindThePolygon)
{
    prtest::context();
    Renderer r(kSize, kSize);
    auto height = prtest::height_from(64, [](float u, float) { return u < 0.5f ? 1.0f : 0.0f; });
    r.upload(prtest::one_object(prtest::square(1.0f), height, 0.3f));
    Camera c = front_camera();
    std::vector<float> flat_depth, relief_depth;
    draw(r, c, Technique::Flat, &flat_depth);
    const RgbaImage img = draw(r, c, Technique::Relief, &relief_depth);
    std::size_t behind = 0, on = 0, covered = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const std::size_t p = std::size_t(y) * kSize + x;
            if (img.pixels[4 * p + 3] < 128) continue;
            ++covered;
            const float d_flat = depth_to_distance(c, kSize, kSize, float(x), float(y), flat_depth[p]);
            const float d_relief = depth_to_distance(c, kSize, kSize, float(x), float(y), relief_depth[p]);
            // Right half (u > 0.5, h = 0) seen head-on: 0.3 units behind, within a step (1/32).
            if (x > kSize / 2 + 4 && std::abs(d_relief - d_flat - 0.3f * d_flat / 5.0f) < 0.3f / 16) ++behind;
            if (x < kSize / 2 - 4 && std::abs(d_relief - d_flat) < 1e-3f) ++on;
        }
    EXPECT_GT(covered, 4000u);
    EXPECT_GT(behind, covered / 2 - 8 * kSize);
    EXPECT_GT(on, covered / 2 - 8 * kSize);
}

// The bundled UV sphere (radius 1) seen from distance 4: its outline is the circle of angular
// radius asin(1/4). Every pixel whose centre is more than one pixel from that circle is covered
// exactly when it lies inside (the 32-segment polygon deviates by < 0.3 px here).
TEST(Render, LoadedSphereMatchesTheAnalyticSilhouette)
{
    prtest::context();
    Renderer r(kSize, kSize);
    Scene scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/uv_sphere.obj"),
                                     prtest::height_from(16, [](float, float) { return 0.0f; }), 0.0f);
    r.upload(scene);
    Camera c = front_camera();
    c.eye = {0, 0, 4};
    const RgbaImage img = draw(r, c, Technique::Pom);
    const float radius_px = std::tan(std::asin(0.25f)) / std::tan(glm::radians(20.0f)) * kSize / 2;
    int wrong = 0, checked = 0;
    for (int y = 0; y < kSize; ++y)
        for (int x = 0; x < kSize; ++x) {
            const float d = glm::length(glm::vec2(x + 0.5f, y + 0.5f) - glm::vec2(kSize / 2.0f)) - radius_px;
            if (std::abs(d) <= 1.0f) continue;
            ++checked;
            wrong += (d < 0) != (img.at(x, y).a >= 128);
        }
    EXPECT_EQ(wrong, 0);
    EXPECT_GT(checked, kSize * kSize - 700); // the +-1 px band is about 2 * 2 pi r = 570 px
}

// A map much wider than tall draws the same surface as the same heights stored narrower: relief
// and pom read the level of the footprint's shorter side in texels (height_grad). With the
// pixel's own gradients GL took the longer side, and grooves along v of a 2048 x 64 map were
// averaged away along v where the picture magnifies them: drawn flat, 12.8 dB against the
// reference where 32 x 64 gave 26.2 (found by an exploratory session, thirty-sixth).
TEST(Render, AWideMapsShortSideIsNotAveragedAway)
{
    prtest::context();
    Renderer r(kSize, kSize);
    const auto grooves = [](int width) {
        auto hf = std::make_shared<HeightField>();
        hf->width = width;
        hf->height = 64;
        hf->name = "grooves" + std::to_string(width);
        hf->texels.resize(std::size_t(width) * 64);
        for (int y = 0; y < 64; ++y)
            for (int x = 0; x < width; ++x)
                hf->texels[std::size_t(y) * width + x] = 0.5f + 0.5f * std::cos(6.2831853f * 8.0f * (y + 0.5f) / 64.0f);
        return hf;
    };
    Camera c = front_camera();
    c.eye = {0.0f, -2.2f, 2.2f};
    c.up = {0.0f, 0.0f, 1.0f};
    for (const Technique t : {Technique::Relief, Technique::Pom}) {
        Scene narrow = prtest::one_object(prtest::square(1.0f), grooves(32), 0.2f);
        Scene wide = prtest::one_object(prtest::square(1.0f), grooves(2048), 0.2f);
        narrow.objects[0].midlevel = wide.objects[0].midlevel = 1.0f;
        r.upload(narrow);
        const RgbaImage a = draw(r, c, t);
        r.upload(wide);
        const RgbaImage b = draw(r, c, t);
        ASSERT_GT(prtest::coverage(a), 5000u);
        std::size_t differ = 0;
        for (std::size_t p = 0; p < std::size_t(kSize) * kSize; ++p) differ += max_channel_difference(a, b, p) > 24;
        EXPECT_LT(differ, prtest::coverage(a) / 50) << technique_name(t) << ": " << differ << " of "
                                                    << prtest::coverage(a) << " pixels differ by more than 24 levels";
    }
}
