// The reference technique (true displaced geometry) and the comparison metrics on real frames.
#include "gl_fixture.hpp"
#include "../unit/temp_dir.hpp"

#include "eval/grid.hpp"
#include "eval/metrics.hpp"
#include "mesh/mesh.hpp"
#include "render/reference_geometry.hpp"
#include "render/scene.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <optional>
#include <string>

using namespace pr;

namespace {

constexpr int kSize = 128;

Camera head_on()
{
    Camera c;
    c.eye = {0, 0, 5};
    c.fovy_deg = 40.0f;
    c.near_plane = 1.0f;
    c.far_plane = 10.0f;
    return c;
}

FrameCapture capture(Renderer& r, const Camera& c, Technique t)
{
    DrawSettings s;
    s.technique = t;
    r.draw(c, glm::vec3(0, 0, 1), s);
    return {r.read_color(), r.read_depth(), c};
}

} // namespace

// A square with a height ramp h = 0.25 + 0.5 u, depth 0.4, seen head-on: every covered pixel's
// depth puts the surface at z = 0.4 * h(u) (the analytic displaced surface), within 0.2% of depth.
// The cap holds for the scene's triangles: the finest levels come down first, to one cap those
// above it share, and objects that want less keep theirs (each object was capped alone: N
// objects built N times the cap; found by an exploratory session, thirty-eighth).
TEST(Reference, TheCapHoldsForTheWholeScene)
{
    std::vector<pr::ReferenceLevel> levels(3);
    levels[0].level = 10, levels[0].texel_level = 10, levels[0].pixel_level = 12;
    levels[1].level = 3, levels[1].texel_level = 3, levels[1].pixel_level = 3;
    levels[2].level = 8, levels[2].texel_level = 8, levels[2].pixel_level = 5;
    // 100 (10^2 + 3^2 + 8^2) = 17,300 uncapped; at a cap of 6: 100 (36 + 9 + 36) = 8,100.
    EXPECT_EQ(pr::cap_reference_levels(levels, {100, 100, 100}, 9000), 8100u);
    EXPECT_EQ(levels[0].level, 6);
    EXPECT_EQ(levels[1].level, 3);
    EXPECT_EQ(levels[2].level, 6);
    EXPECT_TRUE(levels[0].capped);
    EXPECT_FALSE(levels[1].capped);
    EXPECT_FALSE(levels[2].capped); // (its pixel level, 5, is under the 6 it keeps)
    // Nothing under level 1, whatever the cap.
    EXPECT_EQ(pr::cap_reference_levels(levels, {100, 100, 100}, 1), 300u);
    for (const pr::ReferenceLevel& l : levels) EXPECT_EQ(l.level, 1);
}

TEST(Reference, PlaneMatchesTheAnalyticDisplacedSurface)
{
    prtest::context();
    Renderer r(kSize, kSize);
    auto height = prtest::height_from(64, [](float u, float) { return 0.25f + 0.5f * u; });
    Scene scene = prtest::one_object(prtest::square(1.0f), height, 0.4f);
    r.upload(scene);
    const Camera c = head_on();
    const auto stats = r.prepare_reference(scene, c, ReferenceOptions{});
    EXPECT_GE(stats.level, 8);
    const FrameCapture f = capture(r, c, Technique::Reference);
    const glm::mat4 inv = glm::inverse(c.projection(1.0f) * c.view());
    int checked = 0;
    float worst = 0.0f;
    for (int y = 8; y < kSize - 8; ++y)
        for (int x = 8; x < kSize - 8; ++x) {
            const std::size_t p = std::size_t(y) * kSize + x;
            if (f.color.pixels[4 * p + 3] < 128) continue;
            const glm::vec4 ndc((x + 0.5f) / kSize * 2 - 1, (y + 0.5f) / kSize * 2 - 1, f.depth[p], 1); // clip z 0..w
            glm::vec4 w = inv * ndc;
            w /= w.w;
            const float u = (w.x + 1.0f) * 0.5f;
            if (u < 0.03f || u > 0.97f) continue; // bilinear wrap blends the ramp's ends
            worst = std::max(worst, std::abs(w.z - 0.4f * (0.25f + 0.5f * u)));
            ++checked;
        }
    EXPECT_GT(checked, 5000);
    EXPECT_LT(worst, 0.4f * 0.002f);
}

// Depth 0: the reference is the base mesh. On the square at level 8 every subdivision weight is
// k/8, so subdivided points lie exactly on the original edges and coverage is equal bit for bit.
TEST(Reference, DepthZeroCoverageEqualsFlatExactly)
{
    prtest::context();
    Renderer r(kSize, kSize);
    Scene scene = prtest::one_object(prtest::square(1.0f), prtest::height_from(8, [](float u, float) { return u; }), 0.0f);
    r.upload(scene);
    Camera c = head_on();
    c.eye = {0.7f, 0.4f, 4.0f};
    ReferenceOptions level8;
    level8.level = 8;
    r.prepare_reference(scene, c, level8);
    const CompareMetrics m = compare_frames(capture(r, c, Technique::Flat), capture(r, c, Technique::Reference));
    EXPECT_EQ(m.silhouette_wrong_px, 0u);
    EXPECT_DOUBLE_EQ(m.iou, 1.0);
}

// On a curved mesh at an automatic level, subdivided silhouette points are within float rounding
// of the original edges: only a pixel centre lying on an edge may round the other way (0 to 2 of
// about 3,400 pixels at levels 1 to 8 here; u * v wraps to a sharp step, so the level is the
// sharp maps' finer one).
TEST(Reference, DepthZeroCoverageEqualsFlatOnATorus)
{
    prtest::context();
    Renderer r(kSize, kSize);
    Scene scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/torus.obj"),
                                     prtest::height_from(64, [](float u, float v) { return u * v; }), 0.0f);
    r.upload(scene);
    Camera c = frame_sphere(scene.shell_bounds, 40.0f, 1.0f, 35.0f, 20.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const CompareMetrics m = compare_frames(capture(r, c, Technique::Flat), capture(r, c, Technique::Reference));
    EXPECT_LE(m.silhouette_wrong_px, 2u);
    EXPECT_GT(m.iou, 0.9993);
}

// Outward bumps on the sphere: the reference compared with itself is perfect, POM (which cannot
// leave the polygon) misses the bumps' outline, and the diff tile shows exactly the counted pixels.
TEST(Reference, CompareOnASphereFindsPomsMissingOutline)
{
    prtest::context();
    Renderer r(kSize, kSize);
    auto bumps = std::make_shared<HeightField>(load_height("builtin:bumps@128"));
    Scene scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/uv_sphere.obj"), bumps, 0.12f);
    r.upload(scene);
    Camera c = frame_sphere(scene.shell_bounds, 40.0f, 1.0f, 20.0f, 30.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    const FrameCapture pom = capture(r, c, Technique::Pom);
    const CompareMetrics self = compare_frames(ref, ref);
    EXPECT_DOUBLE_EQ(self.iou, 1.0);
    EXPECT_TRUE(self.identical);
    const CompareMetrics m = compare_frames(pom, ref);
    EXPECT_LT(m.iou, 0.97);
    EXPECT_GT(m.iou, 0.6);
    EXPECT_GT(m.only_in_reference, 50u);
    EXPECT_EQ(m.only_in_technique, 0u) << "POM carves inward: it never covers more than the shell";
    ASSERT_TRUE(m.depth_error_mean.has_value());
    EXPECT_GT(*m.depth_error_mean, 0.0);
    const RgbaImage diff = silhouette_diff_tile(pom.color, ref.color);
    std::size_t cyan = 0, magenta = 0;
    for (std::size_t p = 0; p < std::size_t(kSize) * kSize; ++p) {
        const glm::u8vec4 px(diff.pixels[4 * p], diff.pixels[4 * p + 1], diff.pixels[4 * p + 2], 255);
        cyan += px == kDiffOnlyReference;
        magenta += px == kDiffOnlyTechnique;
    }
    EXPECT_EQ(cyan, m.only_in_reference);
    EXPECT_EQ(magenta, m.only_in_technique);
}

// Neighbouring triangles of a closed mesh share edge points bit for bit: constant height 1 on
// the sphere leaves no background pixel inside the outline (a crack would show the background).
TEST(Reference, ClosedMeshStaysWatertight)
{
    prtest::context();
    Renderer r(256, 256);
    Scene scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/rock.obj"),
                                     prtest::height_from(32, [](float u, float v) { return 0.5f + 0.5f * std::sin(40 * u) * std::cos(37 * v); }), 0.1f);
    r.upload(scene);
    Camera c = frame_sphere(scene.shell_bounds, 40.0f, 1.0f, 35.0f, 20.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    DrawSettings s;
    s.technique = Technique::Reference;
    r.draw(c, glm::vec3(0, 0, 1), s);
    const RgbaImage img = r.read_color();
    // A hole is an uncovered pixel whose 4 neighbours at distance 2 are all covered.
    int holes = 0;
    for (int y = 2; y < 254; ++y)
        for (int x = 2; x < 254; ++x)
            if (img.at(x, y).a < 128 && img.at(x - 2, y).a >= 128 && img.at(x + 2, y).a >= 128 &&
                img.at(x, y - 2).a >= 128 && img.at(x, y + 2).a >= 128)
                ++holes;
    EXPECT_EQ(holes, 0);
}

namespace {

// Mean of R+G+B over the covered pixels.
double mean_brightness(const RgbaImage& img)
{
    double sum = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i + 3 < img.pixels.size(); i += 4)
        if (img.pixels[i + 3] >= 128) sum += img.pixels[i] + img.pixels[i + 1] + img.pixels[i + 2], ++n;
    return n ? sum / double(n) : 0.0;
}

// One object from meshes/, loaded through a SceneSpec as the command line loads it, auto-framed.
prtest::FramedObject framed_object(const std::string& mesh, const std::string& height, std::optional<float> depth,
                                   const glm::dmat4& transform = glm::dmat4(1.0))
{
    SceneSpec spec;
    ObjectSpec o = prtest::bundled_object(mesh);
    o.height = height;
    o.depth = depth;
    o.transform = transform;
    spec.objects.push_back(o);
    spec.width = spec.height = kSize;
    return prtest::framed(spec);
}

} // namespace

// Scene transforms: `depth` is in world units along world unit normals for every technique, the
// reference included (it displaced in object space, so a scale of 0.5 halved its bumps: the
// prism's IoU against it was 0.949); and a mirror (negative determinant) keeps every technique's
// faces outward (the prism drew nothing, IoU 0.0005, and the base-surface techniques and the
// reference were lit from inside). The light comes from the eye, so a lit mirror image is as
// bright as the original.
TEST(Reference, ScaledAndMirroredObjectsMatchThePrism)
{
    prtest::context();
    struct Case {
        const char* mesh;
        glm::vec3 scale;
        float depth;
        double min_iou;
    };
    const Case cases[] = {{"cube.obj", glm::vec3(0.5f), 0.1f, 0.985},
                          {"plane.obj", glm::vec3(1.0f, 3.0f, 1.0f), 0.08f, 0.99},
                          {"cube.obj", glm::vec3(-1.0f, 1.0f, 1.0f), 0.08f, 0.99},
                          {"torus.obj", glm::vec3(1.0f, -1.0f, 1.0f), 0.08f, 0.99}};
    for (const Case& k : cases) {
        SCOPED_TRACE(std::string(k.mesh) + " scaled " + std::to_string(k.scale.x) + "," + std::to_string(k.scale.y));
        double brightness[2] = {0.0, 0.0};
        for (int mirrored = 0; mirrored < 2; ++mirrored) {
            const auto [scene, c] = framed_object(k.mesh, "builtin:bumps@128", k.depth,
                                                  glm::scale(glm::mat4(1.0f), mirrored ? k.scale : glm::abs(k.scale)));
            Renderer r(kSize, kSize);
            r.upload(scene);
            r.prepare_reference(scene, c, ReferenceOptions{});
            const glm::vec3 light = glm::normalize(c.eye - c.target);
            FrameCapture frames[2];
            for (int t = 0; t < 2; ++t) {
                DrawSettings s;
                s.technique = t ? Technique::Reference : Technique::Prism;
                r.draw(c, light, s);
                frames[t] = {r.read_color(), r.read_depth(), c};
            }
            const CompareMetrics m = compare_frames(frames[0], frames[1]);
            EXPECT_GT(m.iou, k.min_iou) << (mirrored ? "as given" : "unmirrored");
            brightness[mirrored] = mean_brightness(frames[1].color);
        }
        EXPECT_NEAR(brightness[1], brightness[0], 0.2 * brightness[0]) << "the reference lit from inside";
    }
}

// The automatic level measures the displaced surface's edges on screen, not the base mesh's: a
// shell as deep as the object (the torus at depth 5, framed from far off) took level 2, whose
// coarse triangles put the prism at IoU 0.84 against it where a fine reference (level 24 or 64)
// gives 0.96. Now the level rises with the depth, and the prism measures as against a fine one.
TEST(Reference, AutomaticLevelFollowsADeepShell)
{
    prtest::context();
    int levels[2] = {0, 0};
    for (int deep = 0; deep < 2; ++deep) {
        const auto [scene, c] = framed_object("torus.obj", "builtin:bumps", deep ? 5.0f : 0.1f);
        Renderer r(kSize, kSize);
        r.upload(scene);
        levels[deep] = r.prepare_reference(scene, c, ReferenceOptions{}).level;
        if (!deep) continue;
        FrameCapture frames[2];
        for (int t = 0; t < 2; ++t) {
            DrawSettings s;
            s.technique = t ? Technique::Reference : Technique::Prism;
            r.draw(c, glm::normalize(c.eye - c.target), s);
            frames[t] = {r.read_color(), r.read_depth(), c};
        }
        EXPECT_GT(compare_frames(frames[0], frames[1]).iou, 0.94);
    }
    EXPECT_GE(levels[1], 2 * levels[0]) << "shallow " << levels[0] << ", deep " << levels[1];
}

// Scenes allow scales from 1e-15 to 1e15, and objects from 1e-21 to 1e18 across. The same object
// at scales 1e-20 to 1e17 draws the same picture (auto-framed; the prism from 1e-8 to 1e12, within
// its shell's limits): in floats the normal matrix's inverse overflowed past 7e12 (every
// technique drew nothing), the bump normal's cross product overflowed past 3e9 (the shading went
// black: ambient only), and framing floored radii at 1e-6 scene units (1e-8 drew nothing).
TEST(Reference, ObjectsDrawTheSameAtAnyScale)
{
    prtest::context();
    const auto render = [](float scale, Technique t) {
        const auto [scene, c] =
            framed_object("torus.obj", "builtin:bumps@64", std::nullopt, glm::scale(glm::mat4(1.0f), glm::vec3(scale)));
        Renderer r(kSize, kSize);
        r.upload(scene);
        if (t == Technique::Reference) r.prepare_reference(scene, c, ReferenceOptions{});
        DrawSettings s;
        s.technique = t;
        // The reference with shadows and relief with its depth written, whose shaders read the
        // triangle's normal from the position's derivatives (scaled before their cross product
        // since the forty-first session, which vanished at 1e-20; these views do not show it).
        if (t == Technique::Reference) s.shadows = Shadows::Hard;
        if (t == Technique::Relief) s.depth_write = true;
        r.draw(c, glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f)), s);
        return FrameCapture{r.read_color(), r.read_depth(), c};
    };
    for (const Technique t : {Technique::Flat, Technique::Relief, Technique::Prism, Technique::Reference}) {
        const FrameCapture unit = render(1.0f, t);
        const double unit_brightness = mean_brightness(unit.color);
        ASSERT_GT(prtest::coverage(unit.color), 1000u);
        for (const float scale : {1e-20f, 1e-8f, 3e9f, 1e12f, 1e17f}) {
            // (The prism refuses shells under 2e-9 and over 2e13 across: Prism tests.)
            if (t == Technique::Prism && (scale < 1e-8f || scale > 1e12f)) continue;
            char at_scale[64];
            std::snprintf(at_scale, sizeof at_scale, " at scale %g", double(scale));
            SCOPED_TRACE(technique_name(t) + at_scale);
            const FrameCapture f = render(scale, t);
            CompareMetrics m = compare_frames(f, unit);
            EXPECT_GT(m.iou, 0.995);
            EXPECT_NEAR(mean_brightness(f.color), unit_brightness, 0.03 * unit_brightness);
            // The highlights too (forty-first session: 1e-20 lost them, 4 % of the mean brightness,
            // as the view vector's squared length vanished; 42-81 dB now, by the scale's rounding).
            EXPECT_TRUE(m.identical || (m.psnr && *m.psnr > 40.0)) << (m.psnr ? *m.psnr : -1.0) << " dB";
        }
    }
}

// The same with a colour map, whose level the prism works out from the pixel's footprint on the
// displaced surface (prism.frag, hit_color_lod): its 2x2 system's determinant grows as the scale to
// the fourth, overflowed past 1e9 and read the coarsest level (35.4 dB against the unit scale's
// image at 1e9, 26.7 at 1e10; found by a review).
TEST(Reference, TheColourIsTheSameAtAnyScale)
{
    prtest::context();
    const auto render = [](double scale) {
        SceneSpec spec;
        ObjectSpec o;
        o.mesh = std::string(PR_SOURCE_DIR) + "/meshes/torus.obj";
        o.height = "builtin:bumps@64";
        o.color = "builtin:bricks@128";
        o.transform = glm::scale(glm::dmat4(1.0), glm::dvec3(scale));
        spec.objects.push_back(o);
        spec.width = spec.height = kSize;
        const Scene scene = load_scene(spec);
        const Camera c = scene_camera(spec, scene);
        Renderer r(kSize, kSize);
        r.upload(scene);
        DrawSettings s;
        s.technique = Technique::Prism;
        r.draw(c, glm::normalize(glm::vec3(0.3f, 1.0f, 0.4f)), s);
        return FrameCapture{r.read_color(), r.read_depth(), c};
    };
    const FrameCapture unit = render(1.0);
    for (const double scale : {1e-8, 1e10, 1e12}) {
        const CompareMetrics m = compare_frames(render(scale), unit);
        EXPECT_GT(m.psnr.value_or(1e9), 33.0) << "scale " << scale;
    }
}

// The colour texture is a compile-time variant (PR_COLOR_TEXTURE), chosen per object: in a scene
// of a coloured and a plain object each of pom, the prism and the reference draws each with its
// own, in either order. The coloured torus has a black colour map over a blue base colour (drawn
// plain, it would be blue), the plain one a red base colour (drawn with a colour texture, it would
// take the unit's stand-in, the grey height map): only highlights (white) on the first, red with
// little green on the second.
TEST(Reference, EachObjectDrawsWithItsOwnColourVariant)
{
    prtest::context();
    for (const bool coloured_first : {true, false}) {
        SceneSpec spec;
        for (int k = 0; k < 2; ++k) {
            ObjectSpec o;
            o.mesh = std::string(PR_SOURCE_DIR) + "/meshes/torus.obj";
            o.height = "builtin:bumps@64";
            const bool coloured = (k == 0) == coloured_first;
            if (coloured) o.color = "builtin:const:0";
            o.base_color = coloured ? glm::vec3(0.0f, 0.0f, 1.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
            // The coloured torus on the left, the plain one on the right.
            o.transform = glm::translate(glm::dmat4(1.0), glm::dvec3(coloured ? -1.4 : 1.4, 0.0, 0.0));
            spec.objects.push_back(o);
        }
        spec.width = 2 * kSize;
        spec.height = kSize;
        const Scene scene = load_scene(spec);
        const Camera c = scene_camera(spec, scene);
        Renderer r(2 * kSize, kSize);
        r.upload(scene);
        r.prepare_reference(scene, c, ReferenceOptions{});
        for (const Technique t : {Technique::Pom, Technique::Prism, Technique::Reference}) {
            DrawSettings s;
            s.technique = t;
            r.draw(c, glm::normalize(glm::vec3(0.3f, 1.0f, 0.8f)), s);
            const RgbaImage img = r.read_color();
            double sum[2][3] = {};
            std::size_t n[2] = {0, 0};
            for (int y = 0; y < img.height; ++y)
                for (int x = 0; x < img.width; ++x) {
                    const auto p = img.at(x, y);
                    if (p.a < 128) continue;
                    const int side = x < img.width / 2 ? 0 : 1;
                    sum[side][0] += p.r;
                    sum[side][1] += p.g;
                    sum[side][2] += p.b;
                    ++n[side];
                }
            ASSERT_GT(n[0], 400u) << technique_name(t);
            ASSERT_GT(n[1], 400u) << technique_name(t);
            const std::string what = std::string(technique_name(t)) + (coloured_first ? ", coloured first" : ", plain first");
            // The coloured torus: no blue cast, and less red than the plain one (its diffuse light).
            EXPECT_LT(sum[0][2], 1.2 * sum[0][0] + 1.0) << what;
            EXPECT_LT(sum[0][0] / double(n[0]), 0.6 * sum[1][0] / double(n[1])) << what;
            // The plain torus: red.
            EXPECT_GT(sum[1][0], 2.0 * sum[1][1]) << what;
        }
    }
}

// A floor far larger than the eye's distance to it: the near plane was kept at 10^-4 of the far
// one (the usual depth mapping lost precision below that), which put it 15 units from an eye 1
// unit above a floor 10^5 wide, and every technique drew only a strip at the horizon (coverage
// 10 % against 96 %); at 10^4 wide the prism lost the nearest rows, whose shell the near plane cut
// (IoU 0.945). With reversed float depth (Camera::projection) the near plane comes to 10^-6 of
// the far one.
TEST(Reference, AFloorMuchWiderThanTheEyesHeightIsNotClipped)
{
    prtest::context();
    for (const float width : {1e4f, 1e5f}) {
        SceneSpec spec;
        ObjectSpec o;
        o.mesh = std::string(PR_SOURCE_DIR) + "/meshes/plane.obj";
        o.height = "builtin:bricks@64";
        o.depth = 0.05f;
        o.transform = glm::scale(glm::mat4(1.0f), glm::vec3(width, 1.0f, width));
        spec.objects.push_back(o);
        spec.camera.eye = glm::vec3(0.0f, 0.8f, 3.0f);
        spec.camera.target = glm::vec3(0.0f);
        spec.width = spec.height = kSize;
        const Scene scene = load_scene(spec);
        const Camera c = scene_camera(spec, scene);
        Renderer r(kSize, kSize);
        r.upload(scene);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        // Below the horizon (a little over half the image at this height) all is floor.
        EXPECT_GT(prtest::coverage(ref.color), std::size_t(0.85 * kSize * kSize)) << width;
        for (const Technique t : {Technique::Flat, Technique::Relief, Technique::Prism}) {
            const CompareMetrics m = compare_frames(capture(r, c, t), ref);
            EXPECT_GT(m.iou, 0.999) << technique_name(t) << " " << width;
        }
    }
}

// An object far from the origin: the shaders and the walk's data work in each object's own frame
// (its transform's translation taken out in double, GpuObject::origin). In world coordinates,
// whose floats are 0.06 apart at 10^6, the prism drew noise: IoU 0.856 and 13 dB against the
// reference at a translation of 10^6, 0.976 at 10^5 (found by an exploratory session, sixteenth
// session). The reference and relief lost precision too.
TEST(Reference, ObjectsFarFromTheOriginDrawAsNearIt)
{
    prtest::context();
    for (const float offset : {0.0f, 1e5f, 1e6f}) {
        const auto [scene, c] = framed_object("torus.obj", "builtin:bumps@64", 0.08f,
                                              glm::translate(glm::mat4(1.0f), glm::vec3(offset, 0.0f, 0.0f)));
        Renderer r(kSize, kSize);
        r.upload(scene);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        ASSERT_GT(prtest::coverage(ref.color), std::size_t(kSize * kSize / 8)) << offset;
        const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism), ref);
        EXPECT_GT(m.iou, 0.99) << offset; // (0.993 at 0)
        ASSERT_TRUE(m.psnr.has_value()) << offset;
        EXPECT_GT(*m.psnr, 30.0) << offset;
    }
}

// A scene far from the origin frames and draws as at it: the camera's eye and target, the scene's
// bounds and an object's translation are double, and each object is drawn in floats relative to its
// own origin. In floats the torus translated by (12345678.9, 12345678.9, 0) was 0.1 off where
// the scene said, its bounds were rounded to a unit, and the auto-framed eye so far off that it
// covered 0.5 % of the image instead of 18 % (3·10^7: 0.1 %); and the framing's floor (a millionth
// of the centre's largest coordinate, 12 units there) made it a speck. Now the images are the
// same to the bit at 1.2·10^7, the reference's at 3·10^7 too and the prism's within one level
// there (its march solves for the ray's texture coordinates in each prism, which a last bit of
// the object's placement moves: one value of one pixel), and nearly so at 10^12 (at 9·10^14,
// where doubles are 0.125 apart, the 3-unit torus moves by a few pixels: IoU 0.95).
TEST(Reference, ScenesFarFromTheOriginFrameAsAtIt)
{
    prtest::context();
    const auto draw = [](double offset) {
        const auto [scene, c] = framed_object("torus.obj", "builtin:bumps@64", 0.08f,
                                              glm::translate(glm::dmat4(1.0), glm::dvec3(offset, offset, 0.0)));
        EXPECT_EQ(c.target, scene.shell_bounds.center);
        Renderer r(kSize, kSize);
        r.upload(scene);
        r.prepare_reference(scene, c, ReferenceOptions{});
        return std::pair{capture(r, c, Technique::Reference), capture(r, c, Technique::Prism)};
    };
    const auto [ref0, prism0] = draw(0.0);
    ASSERT_GT(prtest::coverage(ref0.color), std::size_t(kSize * kSize / 8));
    for (const double offset : {12345678.9, 3e7, 1e12}) {
        const auto [ref, prism] = draw(offset);
        if (offset <= 3e7) {
            EXPECT_EQ(ref.color.pixels, ref0.color.pixels) << offset;
            if (offset < 2e7) {
                EXPECT_EQ(prism.color.pixels, prism0.color.pixels) << offset;
            } else {
                ASSERT_EQ(prism.color.pixels.size(), prism0.color.pixels.size());
                int differ = 0, most = 0;
                for (std::size_t i = 0; i < prism.color.pixels.size(); ++i) {
                    const int d = std::abs(int(prism.color.pixels[i]) - int(prism0.color.pixels[i]));
                    differ += d > 0;
                    most = std::max(most, d);
                }
                EXPECT_LE(most, 1) << offset;
                EXPECT_LE(differ, 8) << offset;
            }
        }
        EXPECT_GT(compare_frames(ref, ref0).iou, 0.99) << offset;
        EXPECT_GT(compare_frames(prism, prism0).iou, 0.99) << offset;
    }
}

// A mesh whose file is in geographic coordinates (the torus moved to (5000000.3, 3000000.7, 0) in
// the OBJ itself): OpenMesh reads floats, 0.5 apart there, and the torus lost 1320 of its 2304
// triangles as degenerate (prism IoU 0.77 against its reference). The scan's positions, read in
// double, now keep it relative to its centre (PreparedMesh::origin), placed by the scene: the
// same picture as the torus at the origin.
TEST(Reference, MeshFilesInGeographicCoordinatesDrawAsAtTheOrigin)
{
    prtest::context();
    prtest::TempDir dir;
    std::ifstream in(std::string(PR_SOURCE_DIR) + "/meshes/torus.obj");
    std::ostringstream shifted;
    for (std::string line; std::getline(in, line);) {
        float x, y, z;
        if (line.rfind("v ", 0) == 0 && std::sscanf(line.c_str() + 2, "%f %f %f", &x, &y, &z) == 3) {
            char text[96];
            std::snprintf(text, sizeof text, "v %.4f %.4f %.4f", x + 5000000.3, y + 3000000.7, double(z));
            line = text;
        }
        shifted << line << "\n";
    }
    const auto draw = [](const std::string& mesh) {
        SceneSpec spec;
        ObjectSpec o;
        o.mesh = mesh;
        o.height = "builtin:bumps@64";
        spec.objects.push_back(o);
        spec.width = spec.height = kSize;
        const Scene scene = load_scene(spec);
        const Camera c = scene_camera(spec, scene);
        EXPECT_EQ(scene.objects[0].mesh.dropped_triangles, 0u);
        Renderer r(kSize, kSize);
        r.upload(scene);
        r.prepare_reference(scene, c, ReferenceOptions{});
        return std::pair{capture(r, c, Technique::Reference), capture(r, c, Technique::Prism)};
    };
    const auto [ref0, prism0] = draw(std::string(PR_SOURCE_DIR) + "/meshes/torus.obj");
    const auto [ref, prism] = draw(dir.write("utm.obj", shifted.str()).string());
    EXPECT_GT(compare_frames(ref, ref0).iou, 0.999);
    EXPECT_GT(compare_frames(prism, prism0).iou, 0.999);
}

// The parallax techniques and the light's march solve for the view (and light) ray in the frame
// (T, B, N depth), whose determinant grows as the object's scale cubed: under about 1e-10 it fell
// under the degenerate test and past about 1e13 it overflowed, and relief, cone, pom and steep
// drew plain normal mapping, exit 0 (found by an exploratory session). The frame is brought to
// unit scale by a power of two first (frame_scale, height.glsl): the same picture at any scale,
// and at scale 1 the same bits as before.
TEST(Reference, ParallaxHoldsAtAnyScale)
{
    prtest::context();
    const auto draw = [](double scale, Technique t, Shadows shadows) {
        const auto [scene, c] = framed_object("torus.obj", "builtin:bumps@64", std::nullopt,
                                              glm::scale(glm::dmat4(1.0), glm::dvec3(scale)));
        Renderer r(kSize, kSize);
        r.upload(scene);
        DrawSettings s;
        s.technique = t;
        s.shadows = shadows;
        r.draw(c, glm::vec3(-0.4f, 0.75f, 0.55f), s);
        return r.read_color();
    };
    for (const Technique t : {Technique::Relief, Technique::Cone}) {
        for (const Shadows shadows : {Shadows::None, Shadows::Hard}) {
            const RgbaImage one = draw(1.0, t, shadows);
            EXPECT_NE(one.pixels, draw(1.0, Technique::Normal, Shadows::None).pixels);
            for (const double scale : {1e-10, 1e-13, 1e13, 1e15}) {
                const RgbaImage scaled = draw(scale, t, shadows);
                ASSERT_EQ(scaled.pixels.size(), one.pixels.size());
                std::size_t off = 0;
                for (std::size_t i = 0; i < one.pixels.size(); ++i)
                    off += std::abs(int(one.pixels[i]) - int(scaled.pixels[i])) > 2;
                EXPECT_LT(off, one.pixels.size() / 200) << technique_name(t) << " " << scale << " shadows " << int(shadows);
            }
        }
    }
}
