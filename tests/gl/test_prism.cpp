// The prism technique against the reference: watertightness, IoU, depth write, grazing views,
// with the walk (the default) and with every front face drawn (--prism-exit exact).
#include "gl_fixture.hpp"

#include "core/error.hpp"
#include "eval/metrics.hpp"
#include "mesh/mesh.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <unistd.h>

using namespace pr;

namespace {

FrameCapture capture(Renderer& r, const Camera& c, Technique t, Marcher m = Marcher::Relief,
                     PrismExit exit = PrismExit::Walk)
{
    DrawSettings s;
    s.technique = t;
    s.marcher = m;
    s.prism_exit = exit;
    r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
    return {r.read_color(), r.read_depth(), c};
}

Scene mesh_scene(const std::string& name, std::shared_ptr<HeightField> h, float depth_fraction)
{
    PreparedMesh mesh = load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/" + name);
    const float depth = depth_fraction * glm::length(mesh.bbox_max - mesh.bbox_min);
    return prtest::one_object(std::move(mesh), std::move(h), depth);
}

// A camera at `eye` looking at `target` (the default field of view), its clip planes fitted to
// the scene's shell.
Camera looking_at(const Scene& scene, glm::vec3 eye, glm::vec3 target)
{
    Camera c;
    c.eye = eye;
    c.target = target;
    fit_clip_planes(c, scene.shell_bounds);
    return c;
}

int holes(const RgbaImage& img)
{
    int n = 0; // uncovered pixels whose four neighbours at distance 2 are covered
    for (int y = 2; y < img.height - 2; ++y)
        for (int x = 2; x < img.width - 2; ++x)
            n += img.at(x, y).a < 128 && img.at(x - 2, y).a >= 128 && img.at(x + 2, y).a >= 128 &&
                 img.at(x, y - 2).a >= 128 && img.at(x, y + 2).a >= 128;
    return n;
}

const PrismExit kExits[] = {PrismExit::Walk, PrismExit::Exact};

// Pixels whose whole 5x5 block the reference covers (inside its outline by more than the 2 px the
// issue allows at outlines), and of them those the technique leaves as background
// (scripts/watertight.sh counts the same).
struct InsideOutline {
    int inner = 0;
    int background = 0;
};

InsideOutline background_inside_outline(const RgbaImage& ref, const RgbaImage& img)
{
    InsideOutline n;
    for (int y = 2; y < ref.height - 2; ++y)
        for (int x = 2; x < ref.width - 2; ++x) {
            bool all = true;
            for (int dy = -2; dy <= 2 && all; ++dy)
                for (int dx = -2; dx <= 2 && all; ++dx) all = ref.at(x + dx, y + dy).a >= 128;
            if (!all) continue;
            ++n.inner;
            n.background += img.at(x, y).a < 128;
        }
    return n;
}

// `scene` uploaded to `r` and drawn from `c` with the reference and with the prism (`marcher`):
// the prism's background inside the reference's outline.
InsideOutline prism_holes(Renderer& r, const Scene& scene, const Camera& c, Marcher marcher = Marcher::Relief)
{
    r.upload(scene);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const RgbaImage ref = capture(r, c, Technique::Reference).color;
    return background_inside_outline(ref, capture(r, c, Technique::Prism, marcher).color);
}

std::shared_ptr<HeightField> bumps_map(int size)
{
    return std::make_shared<HeightField>(load_height("builtin:bumps@" + std::to_string(size)));
}

// `mesh` at constant height h, shell depth 4 % of its diagonal.
Scene constant_height(const char* mesh, float h)
{
    return mesh_scene(mesh, prtest::height_from(8, [h](float, float) { return h; }), 0.04f);
}

// Auto-framed at azimuth 30 degrees, as every view here.
Camera framed(const Scene& scene, float elevation_deg)
{
    return frame_sphere(scene.shell_bounds, 40.0f, 1.0f, elevation_deg, 30.0f);
}

// Framed as `render` frames a single mesh (src/render/scene.cpp: its box grown by the depth,
// azimuth 35), so that a view found with the command line is the same here.
Camera render_framing(const Scene& scene, float elevation_deg)
{
    const PreparedMesh& m = scene.objects[0].mesh;
    const glm::vec3 grow(scene.objects[0].depth);
    const glm::vec3 lo = m.bbox_min - grow, hi = m.bbox_max + grow;
    return frame_sphere(Sphere{0.5f * (lo + hi), 0.5f * glm::length(hi - lo)}, 40.0f, 1.0f, elevation_deg, 35.0f);
}

std::string exit_label(PrismExit e) { return e == PrismExit::Walk ? " (walk)" : " (exact)"; }

} // namespace

// Constant height 1 on the closed sphere: the surface is the top cap everywhere, hit with the
// cap epsilon. Coverage equals the reference's up to rasterization at the outline, with no
// holes between neighbouring prisms.
TEST(Prism, ClosedSphereAtConstantHeightOneIsWatertight)
{
    prtest::context();
    Renderer r(192, 192);
    Scene scene = constant_height("uv_sphere.obj", 1.0f);
    r.upload(scene);
    for (float elevation : {0.0f, 35.0f, 75.0f}) {
        const Camera c = framed(scene, elevation);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        for (PrismExit e : kExits) {
            const FrameCapture prism = capture(r, c, Technique::Prism, Marcher::Relief, e);
            const CompareMetrics m = compare_frames(prism, ref);
            EXPECT_EQ(holes(prism.color), 0) << elevation << exit_label(e);
            EXPECT_LE(m.silhouette_wrong_px, 2u * 192u)
                << "more than ~2 px of outline per row, elevation " << elevation << exit_label(e);
            EXPECT_GT(m.iou, 0.99) << elevation << exit_label(e);
        }
    }
}

// Constant height 0 (the bottom cap): rays end exactly on the surface at their exit; the cap
// epsilon must still count them as hits.
TEST(Prism, BottomCapIsHit)
{
    prtest::context();
    Renderer r(128, 128);
    Scene scene = constant_height("torus.obj", 0.0f);
    r.upload(scene);
    const Camera c = framed(scene, 35.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    for (PrismExit e : kExits) {
        const FrameCapture prism = capture(r, c, Technique::Prism, Marcher::Relief, e);
        EXPECT_GT(compare_frames(prism, ref).iou, 0.99) << exit_label(e);
        EXPECT_EQ(holes(prism.color), 0) << exit_label(e);
    }
}

// Outward bumps on the three bundled curved meshes, three elevations, 160 px: the prism's
// outline follows the reference (IoU >= 0.98 at this size; docs/prism.md has 512 px figures)
// and beats POM's by far; the median depth error is a small fraction of the depth.
TEST(Prism, OutlineMatchesTheReferenceOnCurvedMeshes)
{
    prtest::context();
    Renderer r(160, 160);
    r.set_cache_dir(prtest::cache_dir());
    auto bumps = bumps_map(256);
    for (const char* name : {"uv_sphere.obj", "torus.obj", "rock.obj"}) {
        Scene scene = mesh_scene(name, bumps, 0.04f);
        r.upload(scene);
        const float depth = scene.objects[0].depth;
        for (float elevation : {0.0f, 35.0f, 75.0f}) {
            const Camera c = framed(scene, elevation);
            r.prepare_reference(scene, c, ReferenceOptions{});
            const FrameCapture ref = capture(r, c, Technique::Reference);
            std::size_t relief_wrong = 0;
            for (Marcher marcher : {Marcher::Relief, Marcher::Linear, Marcher::Cone, Marcher::RelaxedCone, Marcher::MaxMip}) {
                const CompareMetrics prism = compare_frames(capture(r, c, Technique::Prism, marcher), ref);
                const std::string what = std::string(name) + " elevation " + std::to_string(elevation) +
                                         " marcher " + marcher_name(marcher);
                EXPECT_GT(prism.iou, 0.98) << what;
                // The fast marchers keep relief's outline (a relaxed step through a bump tip would
                // not). A bump tip thinner along the ray than a linear step is caught or not by
                // where the samples fall, and the cone marchers' minimum steps start elsewhere than
                // relief's: a few pixels either way (torus at 75 degrees: relaxed-cone 7, relief 6;
                // 40 and 36 before the march followed the ray's true texture-space path; max-mip,
                // which meets the bilinear patches exactly where the reference's triangles cut
                // their corners, 9 against 6 at 35 degrees).
                if (marcher == Marcher::Relief) relief_wrong = prism.silhouette_wrong_px;
                EXPECT_LE(prism.silhouette_wrong_px, relief_wrong + 4 + relief_wrong / 10) << what;
                ASSERT_TRUE(prism.depth_error_median.has_value());
                EXPECT_LT(*prism.depth_error_median, 0.02 * depth) << what;
                // The mean too (the issue's target): it counts the pixels where the reference sees
                // through a tear at a UV seam (the sphere's poles, the rock's island borders).
                EXPECT_LT(*prism.depth_error_mean, 0.02 * depth) << what;
            }
            const CompareMetrics exact =
                compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Exact), ref);
            EXPECT_GT(exact.iou, 0.98) << name << " elevation " << elevation << " (exact)";
            // Its mean depth error too, where it draws no wall at a tear (the rock seen from the
            // side: about 10 %). On the rock at 35 degrees an exit test that lost precision far
            // from the eye lost its way in grazing pixels: 3.8 % of depth here, 0.9 % now (at most
            // 1.1 % on the rock, 3.1 % on the sphere and torus, whose poles and inner rim the
            // exact exit steps at).
            if (std::string(name) != "rock.obj" || elevation != 0.0f) {
                ASSERT_TRUE(exact.depth_error_mean.has_value());
                EXPECT_LT(*exact.depth_error_mean, (std::string(name) == "rock.obj" ? 0.02 : 0.04) * depth)
                    << name << " elevation " << elevation << " (exact)";
            }
            const CompareMetrics pom = compare_frames(capture(r, c, Technique::Pom), ref);
            EXPECT_LT(pom.iou, 0.95) << name << " elevation " << elevation;
        }
    }
}

// Sharp-edged boxes: the cone marchers keep the box corners on the outline that relief keeps.
// A cone map's ratio holds at its texel centre; filtered bilinearly between a texel beside a box
// (narrow) and the box's top (wide), it let grazing rays jump over the boxes' corners: 2-3 times
// relief's missing outline pixels here (18-38 against 8-14, IoU 0.002 lower) until the renderer
// narrowed the ratios for filtering (maps::ratios_for_bilinear).
TEST(Prism, ConeMarchersKeepBoxCornersOnTheOutline)
{
    prtest::context();
    Renderer r(192, 192);
    r.set_cache_dir(prtest::cache_dir());
    Scene scene = mesh_scene("torus.obj", std::make_shared<HeightField>(load_height("builtin:boxes@256")), 0.04f);
    r.upload(scene);
    for (float elevation : {0.0f, 35.0f}) {
        const Camera c = framed(scene, elevation);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        const CompareMetrics relief = compare_frames(capture(r, c, Technique::Prism, Marcher::Relief), ref);
        for (Marcher marcher : {Marcher::Cone, Marcher::RelaxedCone}) {
            const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism, marcher), ref);
            const std::string what = "elevation " + std::to_string(elevation) + " marcher " + marcher_name(marcher);
            EXPECT_LE(m.only_in_reference, relief.only_in_reference + 3 + relief.only_in_reference / 5) << what;
            EXPECT_GE(m.iou, relief.iou - 0.001) << what;
        }
    }
}

// A wall 4 texels thick across a 2048 x 32 map (heights 0 and 1) on the bundled plane, seen low
// over it: rays that graze the wall's top edge. The cone marchers' refinement took a sample under
// the wall's top, where the secant from the floor before the wall met the surface, as the hit
// (the prism's cone marcher 42.8 dB against the relief marcher's 53.2); it now takes such a
// sample only where it lies on the bracket's slope to the lower end. And a relaxed cone in front
// of the wall reached a texel past its far side (the relaxed constraint's value at the ray's
// first step out of the surface), so rays just under the top crossed the whole wall in one step:
// 27 outline pixels wrong against the relief marcher's 4, with a 2048 x 2048 map.
TEST(Prism, ConeMarchersMeetAThinWallsFaceUnderItsTop)
{
    prtest::context();
    auto wall = std::make_shared<HeightField>();
    wall->width = 2048;
    wall->height = 32;
    wall->name = "thin wall";
    wall->texels.resize(std::size_t(wall->width) * std::size_t(wall->height));
    for (int y = 0; y < wall->height; ++y)
        for (int x = 1024; x < 1028; ++x) wall->texels[std::size_t(y) * std::size_t(wall->width) + std::size_t(x)] = 1.0f;
    Scene scene = mesh_scene("plane.obj", wall, 0.04f);
    Renderer r(256, 192);
    r.set_cache_dir(prtest::cache_dir());
    r.upload(scene);
    const Camera c = looking_at(scene, {0.6f, 0.15f, 0.3f}, {0.0f, 0.05f, 0.0f});
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    const CompareMetrics relief = compare_frames(capture(r, c, Technique::Prism, Marcher::Relief), ref);
    ASSERT_TRUE(relief.psnr.has_value());
    EXPECT_GT(*relief.psnr, 50.0);
    const CompareMetrics cone = compare_frames(capture(r, c, Technique::Prism, Marcher::Cone), ref);
    ASSERT_TRUE(cone.psnr.has_value());
    EXPECT_GT(*cone.psnr, *relief.psnr - 2.0);
    EXPECT_LE(cone.silhouette_wrong_px, relief.silhouette_wrong_px + 2);
    const CompareMetrics relaxed = compare_frames(capture(r, c, Technique::Prism, Marcher::RelaxedCone), ref);
    ASSERT_TRUE(relaxed.psnr.has_value());
    EXPECT_GT(*relaxed.psnr, *relief.psnr - 2.0);
    EXPECT_LE(relaxed.silhouette_wrong_px, relief.silhouette_wrong_px + 2);
    EXPECT_GT(relaxed.iou, relief.iou - 0.0001);
    std::printf("PSNR relief %.1f, cone %.1f, relaxed-cone %.1f dB; outline px wrong %zu, %zu, %zu\n", *relief.psnr,
                *cone.psnr, relaxed.psnr.value_or(0.0), relief.silhouette_wrong_px, cone.silhouette_wrong_px,
                relaxed.silhouette_wrong_px);
}

// Steps in the height field (slots two texels wide in a 512 map, sheer edges) seen low over the
// plane: the cone marchers' hits keep relief's precision. Each is compared with a dense relief
// march (1024 steps, 10 halvings), whose image relief's default draws to the bit here. Their
// refinement's false position cut a step anywhere and ran out of samples before relief's
// precision (37.5 and 42.9 dB from the dense march), until it bisected, with two samples more,
// once a kink showed (99 and 64.4 dB).
TEST(Prism, ConeMarchersRefineStepsToReliefsPrecision)
{
    prtest::context();
    auto slots = prtest::height_from(512, [](float u, float) { return int(u * 512.0f) % 32 < 2 ? 0.0f : 1.0f; });
    Scene scene = mesh_scene("plane.obj", slots, 0.04f);
    Renderer r(192, 144);
    r.set_cache_dir(prtest::cache_dir());
    r.upload(scene);
    for (glm::vec3 eye : {glm::vec3(0.6f, 0.15f, 0.3f), glm::vec3(-0.5f, 0.12f, 0.6f)}) {
        const Camera c = looking_at(scene, eye, {0.0f, 0.03f, 0.0f});
        const auto draw = [&](Marcher m, int steps, int refine) {
            DrawSettings s;
            s.technique = Technique::Prism;
            s.marcher = m;
            s.steps = steps;
            s.refine = refine;
            r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
            return FrameCapture{r.read_color(), r.read_depth(), c};
        };
        const FrameCapture dense = draw(Marcher::Relief, 1024, 10);
        const DrawSettings defaults;
        const auto psnr = [&](Marcher m) {
            const CompareMetrics x = compare_frames(draw(m, defaults.steps, defaults.refine), dense);
            return x.psnr.value_or(99.0);
        };
        const double relief = psnr(Marcher::Relief);
        EXPECT_GT(relief, 50.0);
        for (Marcher m : {Marcher::Cone, Marcher::RelaxedCone}) {
            const double fast = psnr(m);
            EXPECT_GT(fast, std::min(relief, 60.0) - 6.0) << marcher_name(m) << " eye " << eye.x;
            std::printf("eye (%.1f, %.2f, %.1f): relief %.1f dB, %s %.1f dB from the dense march\n", eye.x, eye.y,
                        eye.z, relief, marcher_name(m).c_str(), fast);
        }
    }
}

// The rock's UV islands give the two sides of a seam different heights: the displaced surface
// is torn there and, at elevation 0, the reference sees the rock's far inside through a tear.
// The walk goes through (a second pass from the far side's bottoms shades those pixels); the
// exact exit, which marches each prism on its own, draws a wall at the step instead.
TEST(Prism, WalkSeesTheFarInsideThroughATear)
{
    prtest::context();
    Renderer r(160, 160);
    Scene scene = mesh_scene("rock.obj", bumps_map(256), 0.04f);
    r.upload(scene);
    const float depth = scene.objects[0].depth;
    const Camera c = framed(scene, 0.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    const CompareMetrics walk = compare_frames(capture(r, c, Technique::Prism), ref);
    const CompareMetrics walls = compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Exact), ref);
    EXPECT_GT(walk.iou, 0.99);
    EXPECT_GE(walk.iou, walls.iou - 0.001);
    EXPECT_LT(*walk.depth_error_mean, 0.02 * depth);
    EXPECT_GT(*walls.depth_error_mean, 4.0 * *walk.depth_error_mean) << "no tear in view: the test shows nothing";
    std::printf("mean depth error, %% of depth: walk %.2f, exact %.2f\n", 100.0 * *walk.depth_error_mean / depth,
                100.0 * *walls.depth_error_mean / depth);
}

// The second pass over tears read back on llvmpipe (tiles under scissors) and without a read-back
// on a GPU (every prism's bottom, fragments discarding where nothing is marked) draws the same
// image: the rock's far inside seen through a tear (WalkSeesTheFarInsideThroughATear), and a
// sphere seen from under its surface, whose rays into the body come out on its far side
// (WalkStartsAtTheEyeInsideTheShell), which the second pass alone draws: its IoU against the
// reference is 1, and 0 with the second pass's fragments all discarded.
TEST(Prism, BothSecondPassesDrawTheSame)
{
    prtest::context();
    Renderer r(160, 160);
    ASSERT_EQ(r.tear_pass(), Renderer::TearPass::Tiles); // llvmpipe's
    Scene rock = mesh_scene("rock.obj", bumps_map(256), 0.04f);
    Scene sphere = mesh_scene("uv_sphere.obj", prtest::height_from(16, [](float, float) { return 1.0f; }), 0.04f);
    Camera inside;
    inside.eye = {0.0f, 0.0f, 1.02f};
    inside.target = {0.3f, 0.0f, 0.0f};
    fit_clip_planes(inside, sphere.shell_bounds);
    for (const auto& [scene, camera] : {std::pair{&rock, framed(rock, 0.0f)}, std::pair{&sphere, inside}}) {
        const bool is_rock = scene == &rock;
        SCOPED_TRACE(is_rock ? "rock" : "sphere from inside");
        r.upload(*scene);
        r.prepare_reference(*scene, camera, ReferenceOptions{});
        const FrameCapture ref = capture(r, camera, Technique::Reference);
        r.set_tear_pass(Renderer::TearPass::Tiles);
        const FrameCapture tiles = capture(r, camera, Technique::Prism);
        r.set_tear_pass(Renderer::TearPass::Whole);
        const FrameCapture whole = capture(r, camera, Technique::Prism);
        EXPECT_EQ(tiles.color.pixels, whole.color.pixels);
        EXPECT_EQ(tiles.depth, whole.depth);
        EXPECT_GT(compare_frames(whole, ref).iou, is_rock ? 0.99 : 0.999);
    }
    r.set_tear_pass(Renderer::TearPass::Tiles);
}

// Where the shell's top folds away from the eye, a ray can leave one prism through its top cap
// at an edge and go straight into the neighbour's prism through the neighbour's top; the
// rasterizer gives a pixel on that edge to one cap only, the one facing away, which is not
// drawn. Found on the rock at elevation 75 (the view of scripts/watertight.sh): one pixel inside
// the outline was background until the walk went on into the neighbour there.
TEST(Prism, WalkGoesOnWhereTheTopFoldsAway)
{
    prtest::context();
    Renderer r(512, 512);
    Scene scene = mesh_scene("rock.obj", bumps_map(512), 0.04f); // render's defaults
    const InsideOutline holes = prism_holes(r, scene, render_framing(scene, 75.0f));
    EXPECT_GT(holes.inner, 50000);
    EXPECT_EQ(holes.background, 0);
}

// Where the top folds away seen edge-on, the two caps at the fold cover slivers of a pixel: the
// exit from the cap facing away lay 0.03 from the shared edge in barycentric weight (more than
// the 1e-3 the walk then took for "at the edge") but 0.01 pixel from it on screen, and the
// rasterizer gave the pixel to neither cap; the ray goes into the neighbour's top a little
// further on (the caps' planes part at the edge). One pixel of background in each of these
// views until the twenty-fifth session.
TEST(Prism, WalkGoesOnAtAFoldSeenEdgeOn)
{
    prtest::context();
    for (const auto& [width, height, elevation] : {std::tuple{240, 180, 75.0f}, std::tuple{512, 384, 0.0f}}) {
        SCOPED_TRACE(testing::Message() << width << "x" << height << ", elevation " << elevation);
        // As `render --mesh meshes/rock.obj --size WxH --elevation E` loads and frames it.
        const auto [scene, c] = prtest::framed_bundled("rock.obj", width, height, elevation);
        Renderer r(width, height);
        const InsideOutline holes = prism_holes(r, scene, c);
        EXPECT_GT(holes.inner, 5000);
        EXPECT_EQ(holes.background, 0);
    }
}

// Near a vertex, the top a ray leaves and the top it goes into next need not share an edge: the
// ray crossed the neighbour's top plane just beyond the neighbour's far edge, so it did not go in
// there, and the walk ended (a see-through pinhole, pixel (45, 37); found by an exploratory
// session, fiftieth). It goes on across that edge, a few times around the vertex.
// And where the ray crosses the plane of the fragment's own top a little outside it (the
// rasterizer snaps the cap's corners) and the walk from the nearest plane is lost: it starts again
// across the top's nearest edge (pixel (135, 66) at 192x144, within 2 pixels of the reference's
// outline, so that background_inside_outline does not count it: the full shell covers it).
TEST(Prism, WalkGoesOnAroundAVertex)
{
    prtest::context();
    for (const auto& [width, height] : {std::pair{128, 96}, std::pair{192, 144}}) {
        SCOPED_TRACE(testing::Message() << width << "x" << height);
        // As `render --mesh meshes/rock.obj --height builtin:bumps@256 --size WxH --elevation 15`
        // loads and frames it.
        pr::SceneSpec spec;
        spec.objects.push_back(prtest::bundled_object("rock.obj"));
        spec.objects[0].height = "builtin:bumps@256";
        spec.width = width;
        spec.height = height;
        spec.camera.elevation_deg = 15.0f;
        const auto [scene, c] = prtest::framed(spec);
        Renderer r(width, height);
        const InsideOutline holes = prism_holes(r, scene, c);
        EXPECT_GT(holes.inner, 1000);
        EXPECT_EQ(holes.background, 0);
        if (width == 192) {
            DrawSettings full;
            full.technique = Technique::Prism;
            full.full_shell = true;
            r.draw(c, glm::vec3(0.0f, 0.0f, 1.0f), full);
            EXPECT_GE(r.read_color().at(135, 143 - 66).a, 128); // (the full shell's; rows from the bottom)
            EXPECT_GE(capture(r, c, Technique::Prism).color.at(135, 143 - 66).a, 128);
        }
    }
}

// A ray out through a side into a neighbour whose top it leaves near that side: the walk tried the
// prism it came from, across the top's nearest edge, and its exit took the ray back, so the two
// took turns to the walk's limit of prisms (268 here; on the H200 a few such walks took 30 % of
// the cube's frame). The walk never goes back into the prism it came from.
TEST(Prism, WalkNeverTurnsBackThroughATop)
{
    prtest::context();
    // As `render --mesh meshes/torus.obj --size 256x192 --elevation 60 --azimuth 0` loads and
    // frames it.
    const auto [scene, c] = prtest::framed_bundled("torus.obj", 256, 192, 60.0f, 0.0f);
    Renderer r(256, 192);
    r.set_cache_dir(prtest::cache_dir());
    r.upload(scene);
    for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone}) {
        SCOPED_TRACE(m == Marcher::Relief ? "relief" : "relaxed-cone");
        DrawSettings s;
        s.technique = Technique::Prism;
        s.marcher = m;
        s.count_samples = true;
        r.draw(c, glm::vec3(0.0f, 0.0f, 1.0f), s);
        const SampleCounters counted = r.read_counters();
        ASSERT_GT(counted.fragments, 5000u);
        EXPECT_LT(counted.prisms_most, 128u); // (38; 268, the walk's limit, with the turns)
    }
}

// Max-mip: a descending ray that enters a pyramid cell above its maximum may drop to that height
// only within the cell; jumping past its far side skipped the next cell, which may be higher, and
// left a pixel of background on the UV sphere at elevation 0 (and 1-4 per view elsewhere).
TEST(Prism, MaxMipDoesNotJumpPastACell)
{
    prtest::context();
    Renderer r(512, 512);
    r.set_cache_dir(prtest::cache_dir());
    Scene scene = mesh_scene("uv_sphere.obj", bumps_map(512), 0.04f);
    const InsideOutline holes = prism_holes(r, scene, render_framing(scene, 0.0f), Marcher::MaxMip);
    EXPECT_GT(holes.inner, 40000);
    EXPECT_EQ(holes.background, 0);
}

// Inward and centred displacement: the shell spans the full range around the base surface. On
// the rock's sharp chips an inward shell folds (docs/prism.md, the walk's item 8).
TEST(Prism, InwardAndCentredDisplacementMatchTheReference)
{
    prtest::context();
    Renderer r(128, 128);
    auto bumps = bumps_map(128);
    for (const char* name : {"torus.obj", "rock.obj"}) {
        for (float midlevel : {1.0f, 0.5f}) {
            Scene scene = mesh_scene(name, bumps, 0.04f);
            scene.objects[0].midlevel = midlevel;
            r.upload(scene);
            const Camera c = framed(scene, 35.0f);
            r.prepare_reference(scene, c, ReferenceOptions{});
            const FrameCapture ref = capture(r, c, Technique::Reference);
            for (PrismExit e : kExits) {
                const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, e), ref);
                EXPECT_GT(m.iou, 0.985) << name << " midlevel " << midlevel << exit_label(e);
            }
        }
    }
}

// Where an inward shell folds (the rock's sharp chips), the walk needs the other faces of the
// folded prisms (prism.geom from one point per folded prism, after the top caps): without them
// the prism misses 46 pixels that the reference covers here, with them 8.
TEST(Prism, FoldedPrismsDrawTheirOtherFaces)
{
    prtest::context();
    Renderer r(256, 256);
    r.set_cache_dir(prtest::cache_dir());
    Scene scene = mesh_scene("rock.obj", bumps_map(256), 0.04f);
    scene.objects[0].midlevel = 1.0f;
    r.upload(scene);
    const Camera c = render_framing(scene, 35.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism), capture(r, c, Technique::Reference));
    EXPECT_LE(m.only_in_reference, 20u);
    EXPECT_GT(m.iou, 0.994);
}

// Depth write: a plane through the middle of a bumpy sphere hides exactly what the reference
// says it hides (the plane is drawn with `flat`, so only the sphere's depth decides).
TEST(Prism, DepthAgreesWithTheReferenceWhereAPlaneCrosses)
{
    prtest::context();
    Renderer r(128, 128);
    auto bumps = bumps_map(128);
    Scene scene = mesh_scene("uv_sphere.obj", bumps, 0.05f);
    const Camera c = frame_sphere(scene.shell_bounds, 40.0f, 1.0f, 10.0f, 0.0f);
    r.upload(scene);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    for (PrismExit e : kExits) {
        const FrameCapture prism = capture(r, c, Technique::Prism, Marcher::Relief, e);
        // A plane through the centre, facing the camera: the sphere is in front where its distance
        // is below the plane's. Compare that decision pixel by pixel.
        const glm::vec3 n = glm::normalize(c.eye - c.target);
        int disagree = 0, both = 0;
        for (int y = 0; y < 128; ++y)
            for (int x = 0; x < 128; ++x) {
                const std::size_t p = std::size_t(y) * 128 + x;
                if (ref.color.pixels[4 * p + 3] < 128 || prism.color.pixels[4 * p + 3] < 128) continue;
                const glm::mat4 inv = glm::inverse(c.projection(1.0f) * c.view());
                glm::vec4 on_ray = inv * glm::vec4((x + 0.5f) / 64 - 1, (y + 0.5f) / 64 - 1, 0.5f, 1); // any depth
                const glm::vec3 dir = glm::normalize(glm::vec3(on_ray) / on_ray.w - glm::vec3(c.eye));
                const float plane = glm::dot(glm::vec3(c.target - c.eye), n) / glm::dot(dir, n);
                const float dr = depth_to_distance(c, 128, 128, float(x), float(y), ref.depth[p]);
                const float dp = depth_to_distance(c, 128, 128, float(x), float(y), prism.depth[p]);
                ++both;
                disagree += (dr < plane) != (dp < plane);
            }
        EXPECT_GT(both, 3000) << exit_label(e);
        EXPECT_LT(disagree, both / 100) << exit_label(e); // only where the sphere meets the plane within a step
    }
}

// Grazing views: no NaN (black) pixels, no stripes of background inside the outline.
TEST(Prism, GrazingViewHasNoBlackPixelsOrStripes)
{
    prtest::context();
    Renderer r(160, 96);
    auto height = std::make_shared<HeightField>(load_height("builtin:bricks@256"));
    PreparedMesh plane = load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/plane.obj");
    Scene scene = prtest::one_object(std::move(plane), height, 0.1f);
    r.upload(scene);
    Camera c;
    c.eye = {0.0f, 0.12f, 2.6f}; // about 3 degrees above the floor
    c.target = {0.0f, 0.0f, 0.0f};
    c.fovy_deg = 30.0f;
    fit_clip_planes(c, scene.shell_bounds);
    for (PrismExit e : kExits) {
        const FrameCapture f = capture(r, c, Technique::Prism, Marcher::Relief, e);
        std::size_t black = 0, covered = 0;
        for (std::size_t p = 0; p < std::size_t(160) * 96; ++p)
            if (f.color.pixels[4 * p + 3] >= 128) {
                ++covered;
                black += f.color.pixels[4 * p] + f.color.pixels[4 * p + 1] + f.color.pixels[4 * p + 2] == 0;
            }
        EXPECT_GT(covered, 1000u) << exit_label(e);
        EXPECT_EQ(black, 0u) << exit_label(e);
        EXPECT_EQ(holes(f.color), 0) << exit_label(e);
    }
}

// A wall four texels thick in a 2048-texel map, on the bundled plane, whose 512 triangles the walk
// merges into two: the march samples a prism's segment once per two texels however long it is
// (up to four lengths of the map). It stopped at 4 * --steps + 64 samples a segment, a sample
// every 10 texels along the plane's whole width, and stepped over the wall (IoU 0.86; found by an
// exploratory session). The light's march likewise: at --steps 32 it stopped at 2 * 32 + 64
// samples, and light came through the wall's shadow in stripes (61 % of the shadow at --steps 128).
TEST(Prism, LongSegmentsAreSampledEveryTwoTexels)
{
    prtest::context();
    const int n = 2048;
    auto wall = prtest::height_from(n, [n](float u, float) { return std::abs(u * n - 1024.0f) < 2.0f ? 1.0f : 0.0f; });
    PreparedMesh plane = load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/plane.obj");
    Scene scene = prtest::one_object(std::move(plane), wall, 0.25f);
    Renderer r(128, 128);
    r.upload(scene);
    Camera side; // low over the plane, along the wall
    side.eye = {2.5f, 0.35f, 0.3f};
    side.target = {-0.5f, 0.05f, 0.0f};
    fit_clip_planes(side, scene.shell_bounds);
    ReferenceOptions fine;
    fine.level = 128;
    r.prepare_reference(scene, side, fine);
    const FrameCapture ref = capture(r, side, Technique::Reference);
    const FrameCapture prism = capture(r, side, Technique::Prism);
    EXPECT_GT(compare_frames(prism, ref).iou, 0.99);

    Camera above; // the wall's shadow on the floor, seen from overhead
    above.eye = {0.0f, 3.0f, 0.01f};
    above.target = {0.0f, 0.0f, 0.0f};
    fit_clip_planes(above, scene.shell_bounds);
    const glm::vec3 light = glm::normalize(glm::vec3(1.0f, 0.3125f, 0.0f));
    const auto shadowed = [&](int steps) {
        DrawSettings s;
        s.technique = Technique::Prism;
        s.steps = steps;
        const RgbaImage lit = prtest::drawn(r, above, light, s);
        s.shadows = Shadows::Hard;
        const RgbaImage dark = prtest::drawn(r, above, light, s);
        int n_dark = 0;
        for (std::size_t p = 0; p < lit.pixels.size(); p += 4)
            n_dark += lit.pixels[p + 3] >= 128 && int(dark.pixels[p]) + dark.pixels[p + 1] + dark.pixels[p + 2] + 30 <
                                                      int(lit.pixels[p]) + lit.pixels[p + 1] + lit.pixels[p + 2];
        return n_dark;
    };
    const int full = shadowed(256);
    EXPECT_GT(full, 2000); // the wall's height over the light's slope, 0.8 units, from 0 to x = -0.8
    const int coarse = shadowed(32);
    EXPECT_GT(coarse, full * 97 / 100) << coarse << " of " << full;
}

// --steps raises the least samples per texel a segment takes (one per two texels at 32, 16 at
// 1024): a wall one texel thick seen side-on, across the rays, is a tent two texels wide at its
// foot, which one sample per two texels mostly steps over (IoU 0.68 at the default; found by an
// exploratory session, where --steps changed nothing for such grazing rays).
// The bundled plane under a 32² map that is 1 in texel column 7 only, 0.5 deep, and a camera
// level with it looking along -x: every ray crosses the wall (192 x 64 pixels).
struct WallScene {
    Scene scene;
    Camera side;
    WallScene()
    {
        auto wall = prtest::height_from(32, [](float u, float) { return int(u * 32.0f) == 7 ? 1.0f : 0.0f; });
        scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/plane.obj"), wall, 0.5f);
        side.eye = {30.0f, 0.25f, 0.0f};
        side.target = {0.0f, 0.25f, 0.0f};
        side.fovy_deg = 1.528f;
        fit_clip_planes(side, scene.shell_bounds);
    }
};

TEST(Prism, StepsRaiseTheSamplesPerTexelOfGrazingRays)
{
    prtest::context();
    WallScene w;
    const Camera& side = w.side;
    Renderer r(192, 64);
    r.upload(w.scene);
    ReferenceOptions fine;
    fine.level = 16;
    r.prepare_reference(w.scene, side, fine);
    const FrameCapture ref = capture(r, side, Technique::Reference);
    for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone}) {
        const auto iou = [&](int steps) {
            DrawSettings s;
            s.technique = Technique::Prism;
            s.marcher = m;
            s.steps = steps;
            r.draw(side, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
            return compare_frames(FrameCapture{r.read_color(), r.read_depth(), side}, ref).iou;
        };
        EXPECT_LT(iou(32), 0.8) << int(m);
        EXPECT_GT(iou(1024), 0.98) << int(m);
    }
}

// The automatic reference level gives edges of half a texel on maps with sharp steps: with edges
// of one texel on texel boundaries the reference drew that wall at half its height, and
// prism:max-mip, which intersects the bilinear surface exactly, scored IoU 0.65 against it (found
// by an exploratory session). Against the automatic reference it is now exact but for rounding.
TEST(Prism, TheAutomaticReferenceDrawsOneTexelWallsWhole)
{
    prtest::context();
    WallScene w;
    Renderer r(192, 64);
    r.upload(w.scene);
    r.prepare_reference(w.scene, w.side, ReferenceOptions{});
    const FrameCapture ref = capture(r, w.side, Technique::Reference);
    EXPECT_GT(compare_frames(capture(r, w.side, Technique::Prism, Marcher::MaxMip), ref).iou, 0.995);
}

// The seed's per-vertex exit (distances to the texture-space prism's planes, interpolated):
// near-exact on a flat plane (parallel normals), close on curved meshes, never better than the
// exact per-fragment exit.
TEST(Prism, PerVertexExitIsCloseToTheExactOne)
{
    prtest::context();
    Renderer r(160, 160);
    auto bumps = bumps_map(256);
    for (const char* name : {"plane.obj", "uv_sphere.obj", "torus.obj"}) {
        Scene scene = mesh_scene(name, bumps, 0.04f);
        r.upload(scene);
        const Camera c = framed(scene, 45.0f);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        const CompareMetrics exact =
            compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Exact), ref);
        const CompareMetrics vertex =
            compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Vertex), ref);
        const bool flat = std::string(name) == "plane.obj";
        EXPECT_GT(vertex.iou, flat ? 0.995 : 0.97) << name;
        EXPECT_LE(vertex.iou, exact.iou + 1e-3) << name;
    }
}

// The walk rasterizes only the shell's outside: on a closed mesh about as many fragments as the
// base surface has, where drawing every front face of every prism shades several times more.
TEST(Prism, WalkShadesOnlyTheShellsOutside)
{
    prtest::context();
    Renderer r(128, 128);
    auto bumps = bumps_map(128);
    Scene scene = mesh_scene("torus.obj", bumps, 0.04f);
    r.upload(scene);
    const Camera c = framed(scene, 35.0f);
    const auto fragments = [&](Technique t, PrismExit e) {
        DrawSettings s;
        s.technique = t;
        s.prism_exit = e;
        s.count_samples = true;
        r.draw(c, glm::vec3(0.0f, 0.0f, 1.0f), s);
        return r.read_counters().fragments;
    };
    const auto relief = fragments(Technique::Relief, PrismExit::Walk);
    const auto walk = fragments(Technique::Prism, PrismExit::Walk);
    const auto exact = fragments(Technique::Prism, PrismExit::Exact);
    EXPECT_LT(walk, relief * 13 / 10);
    EXPECT_GT(exact, 3 * walk);
}

// An open mesh: the walk draws the bottom cap and the walls along the boundary, so the plane
// seen from above at an angle (walls in view) and from below matches the reference's outline as
// the exact exit does, and from below its surface.
TEST(Prism, WalkDrawsTheWallsAndBottomOfOpenMeshes)
{
    prtest::context();
    Renderer r(128, 128);
    auto bumps = bumps_map(128);
    Scene scene = mesh_scene("plane.obj", bumps, 0.06f);
    r.upload(scene);
    for (float elevation : {12.0f, -30.0f}) {
        const Camera c = framed(scene, elevation);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        const CompareMetrics walk = compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Walk), ref);
        const CompareMetrics exact =
            compare_frames(capture(r, c, Technique::Prism, Marcher::Relief, PrismExit::Exact), ref);
        EXPECT_GT(walk.iou, 0.98) << elevation;
        EXPECT_GE(walk.iou, exact.iou - 0.002) << elevation;
        // From below, the sheet's back: the walk from the bottom caps goes on under the surface
        // to meet it (it stopped at the bottom cap, a solid slab: PSNR 11 dB, mean depth error
        // 0.46 of the depth).
        if (elevation < 0.0f) {
            EXPECT_LT(*walk.depth_error_mean, 0.05 * scene.objects[0].depth);
            EXPECT_GT(walk.psnr.value_or(1e9), 30.0); // (none where identical)
        }
    }
}

// An open mesh's walls are no skirt: a ray that comes in through a wall under the surface walks
// on under it and meets the sheet from below or leaves it, as the reference (a sheet) has it. The
// plane at constant height 1, raised by the depth, framed from 25 degrees: its front walls showed
// as a skirt below the sheet (IoU 0.848).
TEST(Prism, OpenMeshWallsAreNoSkirt)
{
    prtest::context();
    Renderer r(128, 128);
    Scene scene = mesh_scene("plane.obj", prtest::height_from(16, [](float, float) { return 1.0f; }), 0.04f);
    r.upload(scene);
    const Camera c = framed(scene, 25.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone}) {
        const CompareMetrics walk = compare_frames(capture(r, c, Technique::Prism, m), ref);
        EXPECT_GT(walk.iou, 0.999) << marcher_name(m);
    }
}

// A sheet at the top of the height range (a 1 x 1 map at 1): a ray that comes in through a
// boundary prism's wall within the hit tolerance of the surface hit at once, and was taken to be
// under it, its picture the surface's back: one pixel of the near outline at the ambient level
// where the reference is lit, in every marcher (50.95 dB against it, now equal; found by an
// exploratory session, forty-fourth). Within the tolerance the ray counts as over the surface.
TEST(Prism, ASheetAtTheTopOfTheRangeIsLitToItsOutline)
{
    prtest::context();
    Renderer r(160, 120);
    const Scene scene = prtest::one_object(load_mesh(std::string(PR_SOURCE_DIR) + "/meshes/plane.obj"),
                                           prtest::height_from(1, [](float, float) { return 1.0f; }), 0.3f);
    r.upload(scene);
    Camera c = looking_at(scene, {1.2f, 1.4f, 1.8f}, {0.0f, 0.0f, 0.0f});
    c.fovy_deg = 40.0f;
    DrawSettings s;
    s.technique = Technique::Prism;
    for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone, Marcher::MaxMip}) {
        s.marcher = m;
        const RgbaImage img = prtest::drawn(r, c, glm::normalize(glm::vec3(1.0f, 0.5f, 0.2f)), s);
        int covered = 0, dark = 0;
        for (int y = 0; y < img.height; ++y)
            for (int x = 0; x < img.width; ++x) {
                const glm::u8vec4 p = img.at(x, y);
                if (p.a == 0) continue;
                ++covered;
                dark += int(p.r) + p.g + p.b < 150; // (lit: about 293; the ambient alone: 68)
            }
        EXPECT_GT(covered, 5000) << marcher_name(m);
        EXPECT_EQ(dark, 0) << marcher_name(m);
    }
}

// The texture repeats, so UVs shifted by whole repeats draw the same picture with every marcher.
// Max-mip lost its way far from the origin (UVs near 1000: coordinates near 500 000 texels, where
// its nudge past a cell's border was lost to float rounding: IoU 0.64 on the plane).
TEST(Prism, UvsFarFromTheOriginDrawTheSame)
{
    prtest::context();
    Renderer r(128, 128);
    r.set_cache_dir(prtest::cache_dir());
    auto bumps = bumps_map(128);
    PreparedMesh shifted = prtest::square(1.0f, 2.0f);
    for (MeshVertex& v : shifted.vertices) v.uv += glm::vec2(1000.0f, -1000.0f);
    Scene near_origin = prtest::one_object(prtest::square(1.0f, 2.0f), bumps, 0.2f);
    Scene far_away = prtest::one_object(std::move(shifted), bumps, 0.2f);
    const Camera c = framed(near_origin, 20.0f);
    for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone, Marcher::MaxMip}) {
        r.upload(near_origin);
        const FrameCapture a = capture(r, c, Technique::Prism, m);
        r.upload(far_away);
        const FrameCapture b = capture(r, c, Technique::Prism, m);
        const CompareMetrics cm = compare_frames(b, a);
        EXPECT_GT(cm.iou, 0.999) << marcher_name(m);
        EXPECT_LT(*cm.depth_error_mean, 0.01 * 0.2) << marcher_name(m);
    }
}

// The walk's merged triangles (a flat floor's 512 become 2; docs/prism.md item 11) are
// remembered across uploads (the viewer uploads again whenever the depth changes): an upload of
// another depth draws another picture, and one of the first depth again the same, to the bit.
TEST(Prism, WalkDrawsTheSameAfterUploadingTheSameMeshAgain)
{
    prtest::context();
    Renderer r(96, 96);
    auto bumps = bumps_map(128);
    Scene scene = mesh_scene("plane.obj", bumps, 0.06f);
    const Camera c = framed(scene, 30.0f);
    r.upload(scene);
    const FrameCapture first = capture(r, c, Technique::Prism);
    const float depth = scene.objects[0].depth;
    scene.objects[0].depth = 0.5f * depth;
    r.upload(scene);
    const FrameCapture shallow = capture(r, c, Technique::Prism);
    scene.objects[0].depth = depth;
    r.upload(scene);
    const FrameCapture again = capture(r, c, Technique::Prism);
    EXPECT_NE(shallow.color.pixels, first.color.pixels);
    EXPECT_EQ(again.color.pixels, first.color.pixels);
    int covered = 0;
    for (int y = 0; y < 96; ++y)
        for (int x = 0; x < 96; ++x) covered += first.color.at(x, y).a >= 128;
    EXPECT_GT(covered, 1500);
}

// The tight shell (top caps at the field's local maximum) draws what the full one (top caps at
// height 1) draws, and its rays start lower: fewer height samples per fragment.
TEST(Prism, TightShellMatchesTheFullShellWithFewerSamples)
{
    prtest::context();
    Renderer r(128, 128);
    auto bumps = bumps_map(128);
    for (const char* name : {"torus.obj", "rock.obj"}) {
        Scene scene = mesh_scene(name, bumps, 0.04f);
        r.upload(scene);
        const Camera c = framed(scene, 35.0f);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        double iou[2] = {0.0, 0.0};
        std::uint64_t samples[2] = {0, 0};
        for (bool full : {false, true}) {
            DrawSettings s;
            s.technique = Technique::Prism;
            s.full_shell = full;
            r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
            iou[full] = compare_frames({r.read_color(), r.read_depth(), c}, ref).iou;
            s.count_samples = true;
            r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
            samples[full] = r.read_counters().samples;
        }
        EXPECT_GT(iou[0], 0.98) << name;
        EXPECT_NEAR(iou[0], iou[1], 0.003) << name;
        EXPECT_LT(samples[0], samples[1] * 9 / 10) << name;
    }
}

// A mesh too large for the prism's buffer textures fails with one clear error (on llvmpipe that
// takes about 33 million vertices: the limit is lowered here), and the renderer stays usable.
TEST(Prism, MeshTooLargeForBufferTexturesFailsClearly)
{
    prtest::context();
    Renderer r(64, 64);
    r.set_texture_buffer_limit(1000); // the torus has 2,304 triangles
    Scene scene = constant_height("torus.obj", 0.5f);
    r.upload(scene);
    const Camera c = framed(scene, 35.0f);
    std::string what;
    try {
        capture(r, c, Technique::Prism);
    } catch (const Error& e) {
        what = e.what();
    }
    EXPECT_NE(what.find("the mesh is too large for the prism technique"), std::string::npos) << what;
    EXPECT_NE(what.find("this OpenGL allows 1000"), std::string::npos) << what;
    r.set_texture_buffer_limit(0);
    const FrameCapture f = capture(r, c, Technique::Prism);
    std::size_t covered = 0;
    for (std::size_t p = 0; p < std::size_t(64) * 64; ++p) covered += f.color.pixels[4 * p + 3] > 0;
    EXPECT_GT(covered, 400u);
}

// The eye inside the shell (a close-up): no cap in front of it faces it, so before the walk
// from the eye (docs/prism.md, item 12) nothing was drawn — an empty image where the reference
// fills the view. On the open plane, over the surface and inside a bump, and on the torus with
// the eye on a plane that holds side faces of its prisms (z = 0: a ray goes out through such a
// face at t = 0, give or take rounding) and off it.
TEST(Prism, WalkStartsAtTheEyeInsideTheShell)
{
    prtest::context();
    Renderer r(128, 96);
    struct View {
        const char* mesh;
        glm::vec3 eye, target;
        bool under = false; // inside a bump
        bool flat_top = false; // the height map is 1 everywhere (else bumps)
        float midlevel = 0.0f;
        int map = 256; // the bumps map's size
    };
    const View views[] = {{"plane.obj", {0.1f, 0.03f, 0.3f}, {0.3f, 0.0f, -0.3f}},
                          {"torus.obj", {1.0f, 0.43f, 0.0f}, {0.5f, 0.3f, 0.9f}},
                          {"torus.obj", {1.0f, 0.43f, 0.013f}, {0.5f, 0.3f, 0.9f}},
                          // On flat ground between bumps, 1e-5 above it (within the walk's hit
                          // tolerance): every ray stopped at the eye and the image was empty.
                          // (At 512 texels the bumps around that spot are far enough that the ground
                          // shows; with the nearest bump's foot two texels away, at 256, the prism
                          // still loses the bump below an eye height of about 1e-4: IoU 0.21.)
                          {"plane.obj", {0.03f, 1e-5f, 0.07f}, {0.5f, -0.04999f, -0.5f}, false, false, 0.0f, 512},
                          // Inside the map's tallest bump (height 0.998 at uv 0.0615, 0.0615), at 0.44
                          // of the depth: the walk starts under the surface and meets it from below.
                          {"plane.obj", {-0.877f, 0.05f, 0.877f}, {-0.2f, 0.02f, 0.3f}, true},
                          // Inside a closed object's body, under its shell: the walk starts at the
                          // bottom caps seen from inside (the image was empty: IoU 0.15 and 0).
                          {"torus.obj", {1.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, true},
                          {"uv_sphere.obj", {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 1.0f}, true},
                          {"cube.obj", {0.1f, 0.2f, 0.0f}, {1.0f, 0.0f, 0.3f}, true},
                          // Under the surface of a sphere, looking into it: the rays that go on
                          // into the body come out on its far side, from inside (second pass; they
                          // drew nothing: IoU 0.89 inside a bump).
                          {"uv_sphere.obj", {0.0f, 0.0f, 1.02f}, {0.3f, 0.0f, 0.0f}, true, true},
                          // Inside the rock (UV seams, sharp chips) with the shell inward: the
                          // faces of prisms folded where the bottoms fold faced the eye and
                          // started walks as from outside (lit shards, 23 dB).
                          {"rock.obj", {0.0f, 0.0f, 0.0f}, {1.0f, 0.2f, 0.3f}, true, false, 1.0f}};
    for (const View& v : views) {
        Scene scene = mesh_scene(v.mesh, v.flat_top ? prtest::height_from(16, [](float, float) { return 1.0f; })
                                                    : bumps_map(v.map),
                                 0.04f);
        scene.objects[0].midlevel = v.midlevel;
        r.upload(scene);
        const Camera c = looking_at(scene, v.eye, v.target);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        int covered = 0;
        for (int y = 0; y < ref.color.height; ++y)
            for (int x = 0; x < ref.color.width; ++x) covered += ref.color.at(x, y).a >= 128;
        ASSERT_GT(covered, ref.color.width * ref.color.height / 4) << v.mesh << ": the view shows little";
        for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone}) {
            const CompareMetrics cm = compare_frames(capture(r, c, Technique::Prism, m), ref);
            const std::string what = std::string(v.mesh) + (m == Marcher::Relief ? " relief" : " relaxed-cone") +
                                     " eye z " + std::to_string(v.eye.z);
            EXPECT_GT(cm.iou, 0.99) << what;
            EXPECT_LT(*cm.depth_error_mean, 0.05 * scene.objects[0].depth) << what;
            // (From under the surface both shade its back, with the front's normal turned: the
            // reference turned the base normal instead, which tilts the bumps the wrong way, and
            // was 10 dB from the prism.)
            // (Identical images have no PSNR: the sphere seen from inside its flat-topped shell
            // may be drawn to the bit.)
            EXPECT_GT(cm.psnr.value_or(1e9), 27.0) << what;
            std::printf("%s%s: IoU %.4f, mean depth error %.5f, PSNR %.1f dB%s\n", what.c_str(),
                        v.under ? " (under the surface)" : "", cm.iou, *cm.depth_error_mean, cm.psnr.value_or(0.0),
                        cm.identical ? " (identical)" : "");
        }
    }
}

// A vertex shared by many triangles: a flat disc as a fan of 2000 slivers around its centre (as
// CAD exports cap cylinders). A ray passing near the centre crosses hundreds of the slivers'
// prisms, and the walk gave up after 256: a hole around the centre (IoU 0.92; 0.32 with 20,000
// slivers). It may now cross twice as many prisms as lie around one vertex.
TEST(Prism, WalkCrossesTheSliversAroundAVertexOfHighValence)
{
    prtest::context();
    Renderer r(128, 128);
    PreparedMesh disc;
    const int n = 2000;
    for (int k = 0; k <= n; ++k) {
        MeshVertex v;
        const float a = 2.0f * 3.14159265f * float(k) / float(n);
        v.position = k == n ? glm::vec3(0.0f) : glm::vec3(std::cos(a), 0.0f, -std::sin(a));
        v.normal = {0, 1, 0};
        v.uv = 0.5f + 0.5f * glm::vec2(v.position.x, -v.position.z);
        v.tangent = glm::vec4(2, 0, 0, 1);   // dP/du
        v.bitangent = glm::vec3(0, 0, -2);   // dP/dv
        v.weld_id = std::uint32_t(k);
        disc.vertices.push_back(v);
    }
    for (int k = 0; k < n; ++k) disc.indices.insert(disc.indices.end(), {std::uint32_t(n), std::uint32_t(k), std::uint32_t((k + 1) % n)});
    disc.weld_count = n + 1;
    disc.bbox_min = {-1, 0, -1};
    disc.bbox_max = {1, 0, 1};
    disc.had_uvs = true;
    Scene scene = prtest::one_object(std::move(disc), bumps_map(64), 0.11f);
    r.upload(scene);
    const Camera c = looking_at(scene, {0.8f, 0.5f, 0.8f}, {0.0f, 0.0f, 0.0f});
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism), ref);
    EXPECT_GT(m.iou, 0.995);
}

// Long slivers along a curved surface: an open cylinder of 2000 sides in one row of quads (as CAD
// exports a tube), each triangle 1.5 long and 0.0016 wide. A ray near the outline runs through
// the shell across about 300 of them, and the walk gave up after 256: the bumps along both sides
// of the outline were missing (IoU 0.964 at 192 x 144, found by an exploratory session; 0.970
// here). It may now cross twice as many prisms as the object's diameter crosses of its narrow
// triangles (walk_prism_limit in renderer.cpp).
TEST(Prism, WalkCrossesTheSliversAlongACylinder)
{
    prtest::context();
    const int sides = 2000;
    std::string obj;
    char line[128];
    for (int row = 0; row < 2; ++row)
        for (int i = 0; i < sides; ++i) {
            const double a = 2.0 * 3.141592653589793 * i / sides;
            std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", 0.5 * std::cos(a), -0.75 + 1.5 * row, 0.5 * std::sin(a));
            obj += line;
        }
    for (int row = 0; row < 2; ++row)
        for (int i = 0; i <= sides; ++i) {
            std::snprintf(line, sizeof line, "vt %.9g %d\n", 2.0 * i / sides, row);
            obj += line;
        }
    for (int i = 0; i < sides; ++i) {
        const int next = (i + 1) % sides;
        std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d %d/%d\n", i + 1, i + 1, sides + i + 1, sides + i + 2,
                      sides + next + 1, sides + i + 3, next + 1, i + 2);
        obj += line;
    }
    PreparedMesh tube = prtest::mesh_from_obj_text(obj, "sliver-tube");
    const float depth = 0.04f * glm::length(tube.bbox_max - tube.bbox_min);
    Scene scene = prtest::one_object(std::move(tube), bumps_map(256), depth);
    Renderer r(128, 96);
    r.upload(scene);
    const Camera c = framed(scene, 20.0f);
    r.prepare_reference(scene, c, ReferenceOptions{});
    const FrameCapture ref = capture(r, c, Technique::Reference);
    const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism), ref);
    EXPECT_GT(m.iou, 0.985);
}

// The march follows the view ray's true path in each prism's texture space: the prism's map
// (b, h) -> sum b_i (bottom_i + h depth N_i) is not affine where the normals part, so the texture
// coordinates of the faces' planar triangles at the ray's entry and exit are only near its own,
// and between them its path bends. Marched along the straight line between the faces'
// coordinates, the cube's corners (welded normals 55 degrees off each face) under a deep shell
// drew IoU 0.988-0.991 and PSNR 24-26 dB against the reference, the torus 0.992 and 35 dB; now
// the march's ends come from one step of Newton's method each, its path is the parabola through
// its middle, found the same way (docs/prism.md, item 3): IoU 0.998-0.999 and 32-34 dB, the
// torus 0.998-0.9995 and 52-53 dB (max-mip: two straight halves through that middle). The exact
// exit (every front face drawn) marches the same path: 0.9887-0.9918 and 25-34 dB before, now
// 0.998-0.999 and 32-51 dB.
TEST(Prism, MarchFollowsTheRaysTruePathInTextureSpace)
{
    prtest::context();
    Renderer r(128, 128);
    struct View {
        const char* mesh;
        float depth; // of the bounding box's diagonal
        float elevation;
        double min_psnr;
    };
    // (The cube's diagonal is 2 sqrt(3): a shell 0.2 deep, a tenth of its size.)
    const float deep = 0.2f / (2.0f * std::sqrt(3.0f));
    for (const View& v : {View{"cube.obj", deep, 0.0f, 31.0}, View{"cube.obj", deep, 35.0f, 29.5},
                          View{"torus.obj", 0.04f, 0.0f, 45.0}}) {
        const Scene scene = mesh_scene(v.mesh, bumps_map(256), v.depth);
        r.upload(scene);
        const Camera c = render_framing(scene, v.elevation);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        for (const auto& [m, exit] : {std::pair{Marcher::Relief, PrismExit::Walk}, std::pair{Marcher::RelaxedCone, PrismExit::Walk},
                                      std::pair{Marcher::MaxMip, PrismExit::Walk}, std::pair{Marcher::Relief, PrismExit::Exact}}) {
            const CompareMetrics cm = compare_frames(capture(r, c, Technique::Prism, m, exit), ref);
            const std::string what = std::string(v.mesh) + " elevation " + std::to_string(v.elevation) + " " +
                                     marcher_name(m) + exit_label(exit);
            EXPECT_GT(cm.iou, 0.997) << what;
            EXPECT_GT(cm.psnr.value_or(1e9), v.min_psnr) << what;
            std::printf("%s: IoU %.4f, PSNR %.1f dB\n", what.c_str(), cm.iou, cm.psnr.value_or(1e9));
        }
    }
    // The light's walk for shadows marches between the light ray's true places in each prism too:
    // the torus from 35 degrees at 256 x 256, hard shadows, 33.6 dB against the reference; 29.5 dB
    // with the light's march straight between the faces' coordinates, 28.8 with the view's too.
    // (A bumps map of 256 texels; with the command line's 512, docs/prism.md: 38.0, 31.2, 29.4.)
    const Scene scene = mesh_scene("torus.obj", bumps_map(256), 0.04f);
    Renderer big(256, 256);
    big.upload(scene);
    const Camera c = render_framing(scene, 35.0f);
    big.prepare_reference(scene, c, ReferenceOptions{});
    // (The light as `render` puts it: above-left-behind the viewer, scene_light.)
    const glm::vec3 light = scene_light(SceneSpec{}, c);
    const auto shadowed = [&](Technique t) {
        DrawSettings s;
        s.technique = t;
        s.shadows = Shadows::Hard;
        big.draw(c, light, s);
        return FrameCapture{big.read_color(), big.read_depth(), c};
    };
    const CompareMetrics cm = compare_frames(shadowed(Technique::Prism), shadowed(Technique::Reference));
    std::printf("torus with hard shadows: IoU %.4f, PSNR %.1f dB\n", cm.iou, cm.psnr.value_or(1e9));
    EXPECT_GT(cm.iou, 0.998);
    EXPECT_GT(cm.psnr.value_or(1e9), 31.5);
}

// A caller's scissor bounds the whole draw, the second pass through tears included, and is left
// as it was: the viewer's split view draws each half in its own columns, then its wire overlay.
// The second pass set its tiles' scissors and then turned the test off. (Its pixels stayed in
// the columns even so: it shades only pixels the first pass marked, inside the scissor.)
TEST(Prism, TheSecondPassKeepsTheCallersScissor)
{
    prtest::context();
    const int w = 128, h = 96, half = 70; // the tiles (PR_TEAR_TILE) across the edge
    Renderer r(w, h);
    // Under the surface of a sphere, looking into it: the rays that go on into the body come out
    // on its far side, from inside (the second pass).
    Scene scene = mesh_scene("uv_sphere.obj", prtest::height_from(16, [](float, float) { return 1.0f; }), 0.04f);
    r.upload(scene);
    const Camera c = looking_at(scene, {0.0f, 0.0f, 1.02f}, {0.3f, 0.0f, 0.0f});
    const RgbaImage full = capture(r, c, Technique::Prism).color;
    const RgbaImage before = capture(r, c, Technique::Flat).color; // what the right half keeps
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, half, h);
    const RgbaImage left = capture(r, c, Technique::Prism).color;
    GLint box[4] = {};
    glGetIntegerv(GL_SCISSOR_BOX, box);
    EXPECT_EQ(glIsEnabled(GL_SCISSOR_TEST), GL_TRUE);
    EXPECT_EQ(box[0], 0);
    EXPECT_EQ(box[2], half);
    EXPECT_EQ(box[3], h);
    glDisable(GL_SCISSOR_TEST);
    int changed_right = 0, differ_left = 0, full_differs_right = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const auto a = before.at(x, y), b = left.at(x, y), f = full.at(x, y);
            const bool same_as_before = a.r == b.r && a.g == b.g && a.b == b.b && a.a == b.a;
            const bool same_as_full = f.r == b.r && f.g == b.g && f.b == b.b && f.a == b.a;
            if (x >= half) {
                changed_right += !same_as_before;
                full_differs_right += !(a.r == f.r && a.g == f.g && a.b == f.b && a.a == f.a);
            } else {
                differ_left += !same_as_full;
            }
        }
    ASSERT_GT(full_differs_right, 500) << "the prism and flat images agree: the test shows nothing";
    EXPECT_EQ(changed_right, 0);
    EXPECT_EQ(differ_left, 0);
}

// A triangle whose uvs have no area (all on a line: an open cylinder whose u is one number) is
// shaded as its neighbours with proper uvs: the hit's weights come from its world point where its
// uv gives none. With the triangle's centre instead, each was one flat facet: 33 dB against the
// reference where the same cylinder with proper uvs gave 92, with heights along v only 29.6 against
// 39.2 (found by an exploratory session, thirty-sixth). Both exits, two marchers.
TEST(Prism, TrianglesWithoutUvAreaAreShadedSmoothly)
{
    prtest::context();
    // An open cylinder of 24 sides along y, 4 rings; u around it (or 0.3 everywhere), v along it.
    const auto cylinder = [](bool u_line) {
        std::string obj;
        char line[160];
        const int sides = 24, rings = 4;
        for (int j = 0; j <= rings; ++j)
            for (int i = 0; i <= sides; ++i) {
                const double a = 2.0 * M_PI * i / sides;
                std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\nvt %.9g %.9g\n", std::cos(a), 2.0 * j / rings - 1.0,
                              std::sin(a), u_line ? 0.3 : double(i) / sides, double(j) / rings);
                obj += line;
            }
        for (int j = 0; j < rings; ++j)
            for (int i = 0; i < sides; ++i) {
                const int a = j * (sides + 1) + i + 1, b = a + 1, c = a + sides + 2, d = a + sides + 1;
                std::snprintf(line, sizeof line, "f %d/%d %d/%d %d/%d\nf %d/%d %d/%d %d/%d\n", a, a, d, d, c, c, a, a, c,
                              c, b, b);
                obj += line;
            }
        return prtest::mesh_from_obj_text(obj, "u-line");
    };
    // Stripes along v only: the same surface whatever u says.
    const auto stripes = prtest::height_from(64, [](float, float v) { return 0.5f + 0.4f * std::sin(8.0f * float(M_PI) * v); });
    Scene proper = prtest::one_object(cylinder(false), stripes, 0.08f);
    Scene u_line = prtest::one_object(cylinder(true), stripes, 0.08f);
    Renderer r(160, 160);
    const Camera c = framed(proper, 10.0f);
    for (const PrismExit exit : kExits)
        for (const Marcher marcher : {Marcher::Relief, Marcher::MaxMip}) {
            r.upload(proper);
            const FrameCapture good = capture(r, c, Technique::Prism, marcher, exit);
            r.upload(u_line);
            const CompareMetrics m = compare_frames(capture(r, c, Technique::Prism, marcher, exit), good);
            const std::string label = std::string(marcher == Marcher::Relief ? "relief" : "max-mip") + exit_label(exit);
            EXPECT_GT(m.both, 5000) << label;
            EXPECT_EQ(m.silhouette_wrong_px, 0u) << label;
            EXPECT_TRUE(m.identical || (m.psnr && *m.psnr > 50.0))
                << label << ": PSNR " << (m.psnr ? *m.psnr : 0.0) << " against the proper uvs";
        }
}

// A cylinder as Blender exports it: `sides` side quads with a UV seam, each cap one n-gon (which
// the loader cuts into a fan of slivers) on a UV island of its own, split normals. `side_uv(s, t)`
// maps the side's (around, up) in [0, 1]^2, `cap_uv(cap, x, y)` a cap's disc in [0, 1]^2.
template <class SideUv, class CapUv>
PreparedMesh blender_cylinder(int sides, SideUv side_uv, CapUv cap_uv)
{
    std::string obj;
    char line[200];
    const auto add = [&](const char* format, double a, double b, double c) {
        std::snprintf(line, sizeof line, format, a, b, c);
        obj += line;
    };
    const auto add_uv = [&](glm::vec2 uv) {
        std::snprintf(line, sizeof line, "vt %.9g %.9g\n", double(uv.x), double(uv.y));
        obj += line;
    };
    for (int row = 0; row < 2; ++row)
        for (int i = 0; i < sides; ++i) {
            const double a = 2.0 * M_PI * i / sides;
            add("v %.9g %.9g %.9g\n", 0.5 * std::cos(a), 1.5 * row - 0.75, 0.5 * std::sin(a));
        }
    for (int row = 0; row < 2; ++row) // vt 1 .. 2 (sides + 1): the side, a column more (the seam)
        for (int i = 0; i <= sides; ++i) {
            add_uv(side_uv(double(i) / sides, double(row)));
        }
    for (int cap = 0; cap < 2; ++cap) // then the bottom cap's, then the top's
        for (int i = 0; i < sides; ++i) {
            const double a = 2.0 * M_PI * i / sides;
            add_uv(cap_uv(cap, 0.5 + 0.5 * std::cos(a), 0.5 + 0.5 * std::sin(a)));
        }
    for (int i = 0; i < sides; ++i) {
        const double a = 2.0 * M_PI * i / sides;
        add("vn %.9g 0 %.9g\n", std::cos(a), std::sin(a), 0.0);
    }
    obj += "vn 0 -1 0\nvn 0 1 0\n";
    for (int i = 0; i < sides; ++i) {
        const int j = (i + 1) % sides;
        std::snprintf(line, sizeof line, "f %d/%d/%d %d/%d/%d %d/%d/%d %d/%d/%d\n", i + 1, i + 1, i + 1, sides + i + 1,
                      sides + i + 2, i + 1, sides + j + 1, sides + i + 3, j + 1, j + 1, i + 2, j + 1);
        obj += line;
    }
    for (int cap = 1; cap >= 0; --cap) { // the top cap wound the other way round
        obj += "f";
        for (int k = 0; k < sides; ++k) {
            const int i = cap ? sides - 1 - k : k;
            std::snprintf(line, sizeof line, " %d/%d/%d", cap * sides + i + 1, 2 * (sides + 1) + cap * sides + i + 1,
                          sides + 1 + cap);
            obj += line;
        }
        obj += "\n";
    }
    return prtest::mesh_from_obj_text(obj, "blender-cylinder-" + std::to_string(sides));
}

// An 8-bit map of `width` x `height` from level(x, row), rows from the top as in a PNG.
template <class Level>
std::shared_ptr<HeightField> map_8bit(int width, int height, Level level)
{
    auto map = std::make_shared<HeightField>();
    map->width = width;
    map->height = height;
    map->name = "test";
    map->texels.resize(std::size_t(width) * std::size_t(height));
    for (int row = 0; row < height; ++row)
        for (int x = 0; x < width; ++x)
            map->texels[std::size_t(height - 1 - row) * std::size_t(width) + std::size_t(x)] = float(level(x, row)) / 255.0f;
    return map;
}

// Blender-style cylinders under maps whose side and caps differ at the rims: the surface tears
// there, and the reference sees through the crack (the object's inside, or the back of a cap's
// rim pushed out past the side). The tight shell's tops at a rim differ enough that some of the
// cap's slivers fold, and a folded prism's walls are drawn: a walk from one took the ray to be
// over the surface where it came out of the crack, under it, and hit at once. Its wall on the
// rim (24 sides) drew the cap where the reference shows the crack, 28 dB against it at 256 x 192,
// where the full shell, whose prisms do not fold there, drew 39; its walls on the cap's own edges
// (128 sides) drew the cap's underside unlit over the rim's lobe, 27.6 dB against 36.3 (here, at
// 192 x 144, 41.4 against 55.4 and 32.9 against 38.5 before, 53.7 and 38.5 now). The walk
// from a folded prism's wall now decides its side by its first sample, as a walk crossing a seam
// does. Found by exploratory sessions (thirty-eighth and thirty-ninth).
TEST(Prism, TightShellSeesIntoATearFromAFoldedWall)
{
    prtest::context();
    struct Case {
        const char* name;
        PreparedMesh mesh;
        std::shared_ptr<HeightField> map;
        float depth, elevation;
    };
    std::vector<Case> cases;
    // 24 sides; the side at u 0..0.75, v 0..0.5, the caps round (0.8, 0.15) and (0.8, 0.6). The
    // map, 200 x 50: a plateau of 1 across the side's top rim, a sine under the caps.
    cases.push_back({"24 sides", blender_cylinder(
                                     24, [](double s, double t) { return glm::vec2(0.75 * s, 0.5 * t); },
                                     [](int cap, double x, double y) {
                                         return glm::vec2(0.7 + 0.2 * x, 0.05 + 0.45 * cap + 0.2 * y);
                                     }),
                     map_8bit(200, 50,
                              [](int x, int row) {
                                  return x >= 21 && x <= 59 && row >= 11 && row <= 39
                                             ? 255
                                             : (x > 100 ? int(127.0 + 127.0 * std::sin(x / 7.0)) : 0);
                              }),
                     0.1f, 25.0f});
    // 128 sides on a 4 x 4 atlas (the side in cell 0, the caps in cells 1 and 2); the map, 200²:
    // 0 on the side but a plateau at its top rim, bands of a sine along u on the caps.
    const auto cell = [](int c, double x, double y) {
        return glm::vec2(float(c % 4) * 0.25f + 0.02f + 0.21f * float(x), float(c / 4) * 0.25f + 0.02f + 0.21f * float(y));
    };
    cases.push_back({"128 sides",
                     blender_cylinder(
                         128, [&](double s, double t) { return cell(0, s, t); },
                         [&](int cap, double x, double y) { return cell(1 + cap, x, y); }),
                     map_8bit(200, 200,
                              [](int x, int row) {
                                  const double u = (x + 0.5) / 200.0, v = 1.0 - (row + 0.5) / 200.0;
                                  const double lu = std::fmod(4.0 * u, 1.0), lv = std::fmod(4.0 * v, 1.0);
                                  if (u < 0.25 && v < 0.25) return lu >= 0.2 && lu <= 0.6 && lv >= 0.6 ? 255 : 0;
                                  return int(std::lround(255.0 * (0.5 + 0.5 * std::sin(u * 2.0 * M_PI * 14.0))));
                              }),
                     0.15f, 60.0f});
    for (Case& k : cases) {
        Scene scene = prtest::one_object(std::move(k.mesh), k.map, k.depth);
        Renderer r(192, 144);
        r.upload(scene);
        const Camera c = frame_sphere(scene.shell_bounds, 40.0f, 192.0f / 144.0f, k.elevation, 35.0f);
        r.prepare_reference(scene, c, ReferenceOptions{});
        const FrameCapture ref = capture(r, c, Technique::Reference);
        double psnr[2] = {0.0, 0.0};
        for (bool full : {false, true}) {
            DrawSettings s;
            s.technique = Technique::Prism;
            s.full_shell = full;
            r.draw(c, glm::normalize(glm::vec3(-0.3f, 0.6f, 1.0f)), s);
            const CompareMetrics m = compare_frames({r.read_color(), r.read_depth(), c}, ref);
            EXPECT_GT(m.iou, 0.995) << k.name << (full ? ", full" : ", tight");
            psnr[full] = m.psnr.value_or(0.0);
        }
        EXPECT_GT(psnr[1], 30.0) << k.name << ": the full shell draws the crack";
        EXPECT_GT(psnr[0], psnr[1] - 3.0) << k.name << ": the tight shell " << psnr[0] << " dB, the full one " << psnr[1];
        std::printf("%s: PSNR against the reference: tight shell %.1f dB, full %.1f dB\n", k.name, psnr[0], psnr[1]);
    }
}
