// Auto-framing: the scene's bounds are the full displacement shell's, so a one-sided shell (a
// plane displaced outward) is framed on its own centre, not on the base mesh's.
#include "render/scene.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <filesystem>

namespace {

pr::Scene plane_scene(float midlevel, float angle_deg = 0.0f)
{
    pr::SceneSpec spec;
    pr::ObjectSpec o;
    o.mesh = (std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "plane.obj").string();
    o.height = "builtin:const:1";
    o.depth = 1.0f;
    o.midlevel = midlevel;
    o.transform = glm::rotate(glm::mat4(1.0f), glm::radians(angle_deg), glm::vec3(0, 0, 1));
    spec.objects.push_back(o);
    return pr::load_scene(spec);
}

} // namespace

// The plane spans x, z in [-1, 1] at y = 0 with normals +y; depth 1 puts the shell at y in
// [0, 1] (midlevel 0) or [-1, 0] (midlevel 1): a box 2 x 1 x 2, radius 1.5 around its centre.
// (The base box grown by the reach on every side, before, gave centre y = 0 and radius 3.)
TEST(SceneFraming, BoundsAreTheFullShells)
{
    for (const float midlevel : {0.0f, 1.0f}) {
        const pr::Scene scene = plane_scene(midlevel);
        const float y = midlevel == 0.0f ? 0.5f : -0.5f;
        EXPECT_NEAR(glm::length(scene.shell_bounds.center - glm::dvec3(0.0, y, 0.0)), 0.0f, 1e-5f) << midlevel;
        EXPECT_NEAR(scene.shell_bounds.radius, 1.5f, 1e-5f) << midlevel;
        ASSERT_EQ(scene.object_bounds.size(), 1u);
        EXPECT_NEAR(glm::length(scene.object_bounds[0].center - scene.shell_bounds.center), 0.0f, 1e-6f);
        const pr::Camera camera = pr::scene_camera(pr::SceneSpec{}, scene);
        EXPECT_NEAR(glm::length(camera.target - scene.shell_bounds.center), 0.0f, 1e-5f);
    }
    // Turned 90 degrees about z the normals are world -x (or +x): the shell is displaced along x.
    const pr::Scene turned = plane_scene(0.0f, 90.0f);
    EXPECT_NEAR(std::abs(turned.shell_bounds.center.x), 0.5f, 1e-5f);
    EXPECT_NEAR(turned.shell_bounds.center.y, 0.0f, 1e-5f);
    EXPECT_NEAR(turned.shell_bounds.radius, 1.5f, 1e-5f);
}

// A mesh file named by several objects is read and prepared once (a scene of 60 objects of one
// 1M-triangle mesh read it 60 times, over two minutes): its warnings come once, and each object
// has its own copy, a mirrored one wound the other way.
TEST(SceneLoad, AMeshNamedTwiceIsReadOnce)
{
    pr::SceneSpec spec;
    pr::ObjectSpec o;
    o.mesh = (std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "blob.off").string(); // no UVs: a warning
    spec.objects.push_back(o);
    o.transform = glm::scale(glm::dmat4(1.0), glm::dvec3(-1.0, 1.0, 1.0));
    spec.objects.push_back(o);
    ::testing::internal::CaptureStderr();
    const pr::Scene scene = pr::load_scene(spec);
    const std::string warnings = ::testing::internal::GetCapturedStderr();
    std::size_t count = 0;
    for (std::size_t at = warnings.find("no texture coordinates"); at != std::string::npos;
         at = warnings.find("no texture coordinates", at + 1))
        ++count;
    EXPECT_EQ(count, 1u) << warnings;
    ASSERT_EQ(scene.objects.size(), 2u);
    const auto& a = scene.objects[0].mesh.indices;
    const auto& b = scene.objects[1].mesh.indices;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(a[0], b[0]);
    EXPECT_EQ(a[1], b[2]); // the mirrored copy's triangles reversed, the first object's not
    EXPECT_EQ(a[2], b[1]);
}

// Maps of the same texels under two names share one field, so that the renderer, which keeps
// cone maps, textures and pyramids by the field, builds and uploads them once (builtin:noise and
// builtin:noise@512 built their relaxed maps twice without the cache: 6.4 s against 3.3 s; found
// by an exploratory session, thirty-seventh); each object keeps its own name for the reports. A
// map of other texels under a like name is its own.
TEST(SceneLoad, AMapUnderTwoNamesIsOneField)
{
    pr::SceneSpec spec;
    pr::ObjectSpec o;
    o.mesh = (std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "torus.obj").string();
    for (const char* name : {"builtin:noise@64", "builtin:noise@0064", "builtin:noise@65"}) {
        o.height = name;
        spec.objects.push_back(o);
    }
    const pr::Scene scene = pr::load_scene(spec);
    ASSERT_EQ(scene.objects.size(), 3u);
    EXPECT_EQ(scene.objects[0].height.get(), scene.objects[1].height.get());
    EXPECT_NE(scene.objects[0].height.get(), scene.objects[2].height.get());
    EXPECT_EQ(scene.objects[0].height_name, "builtin:noise@64");
    EXPECT_EQ(scene.objects[1].height_name, "builtin:noise@0064");
}

// The default depth is 4 % of the object's world box's diagonal: the box of its transformed
// vertices, not of its transformed file box's corners. The torus (axis y, 48 segments) turned
// 45° about y has the same vertices as unturned, so the same default depth; the corners' box made
// it 40 % deeper (and a scene's turn drew other bumps than the same turn in the file).
TEST(SceneLoad, DefaultDepthFollowsTheTurnedVerticesBox)
{
    const auto torus_depth = [](double angle_deg) {
        pr::SceneSpec spec;
        pr::ObjectSpec o;
        o.mesh = (std::filesystem::path(PR_SOURCE_DIR) / "meshes" / "torus.obj").string();
        o.transform = glm::rotate(glm::dmat4(1.0), glm::radians(angle_deg), glm::dvec3(0, 1, 0));
        spec.objects.push_back(o);
        return double(pr::load_scene(spec).objects[0].depth);
    };
    const double straight = torus_depth(0.0);
    EXPECT_NEAR(torus_depth(45.0), straight, 1e-5 * straight);
    EXPECT_NEAR(torus_depth(90.0), straight, 1e-5 * straight);
    EXPECT_NEAR(torus_depth(22.5), straight, 0.01 * straight); // 7.5° segments: a little narrower
}
