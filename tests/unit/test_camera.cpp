// Clip planes from a scene's bounds (src/core/camera.cpp).
#include "core/camera.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>

#include <cmath>

// A far-away object keeps the near plane at the near object: with one sphere around both, the
// near plane was kept from a fraction of the far plane (1e-4 of 1e5) and cut the near object away
// (a scene with a sphere 4e4 away lost its torus' front, at 7e4 everything).
TEST(Camera, FarObjectDoesNotPushTheNearPlanePastNearOnes)
{
    pr::Camera c;
    c.eye = {0.0f, 0.0f, 5.0f};
    const std::vector<pr::Sphere> objects = {{{0.0f, 0.0f, 0.0f}, 1.0f}, {{0.0f, 0.0f, -1e5f}, 1.0f}};
    const pr::Sphere all{{0.0f, 0.0f, -5e4f}, 5e4f + 1.0f};
    pr::fit_clip_planes(c, objects, all);
    EXPECT_LE(c.near_plane, 5.0f - 1.0f);
    EXPECT_GT(c.near_plane, 0.0f);
    EXPECT_GE(c.far_plane, 1e5f + 5.0f);
    // One object: as for its sphere alone.
    pr::Camera one = c, alone = c;
    pr::fit_clip_planes(one, {objects[0]}, objects[0]);
    pr::fit_clip_planes(alone, objects[0]);
    EXPECT_EQ(one.near_plane, alone.near_plane);
    EXPECT_EQ(one.far_plane, alone.far_plane);
    // The eye inside an object: near is a small fraction of that object's far side, not zero.
    c.eye = {0.0f, 0.0f, 0.5f};
    pr::fit_clip_planes(c, objects, all);
    EXPECT_GT(c.near_plane, 0.0f);
    EXPECT_LT(c.near_plane, 0.01f);
}

// The near plane is a plane across the view axis: it must lie before the nearest point of every
// sphere along that axis, which for a sphere off the axis is nearer than its distance from the eye
// less its radius (a cube 27 degrees off the axis lay wholly in front of the near plane).
TEST(Camera, NearPlaneEnclosesSpheresOffTheViewAxis)
{
    pr::Camera c;
    c.eye = {0.0, 0.0, 40.0};
    c.target = {20.0, 0.0, 0.0};
    const pr::Sphere cube{{0.0, 0.0, 0.0}, std::sqrt(3.0)};
    const glm::dvec3 forward = glm::normalize(c.target - c.eye);
    const double nearest = glm::dot(cube.center - c.eye, forward) - cube.radius; // about 34
    pr::fit_clip_planes(c, cube);
    EXPECT_LE(c.near_plane, nearest);
    EXPECT_GT(c.near_plane, 0.0f);
    EXPECT_GE(c.far_plane, glm::length(c.eye) + cube.radius);
    const std::vector<pr::Sphere> objects = {cube, {{0.0, 0.0, -20.0}, 1.0}};
    pr::fit_clip_planes(c, objects, pr::Sphere{{0.0, 0.0, -10.0}, 12.0});
    EXPECT_LE(c.near_plane, nearest);
    EXPECT_GT(c.near_plane, 0.0f);
}

// The view matrix is lookAt's, but its direction is normalized in double: eye and target 1e-23
// apart gave glm::lookAt a NaN matrix (an empty image) though the view is valid.
TEST(Camera, ViewMatrixIsLookAtsAndStaysFiniteForNearPoints)
{
    pr::Camera c;
    c.eye = {3.0f, 2.0f, 1.0f};
    c.target = {0.0f, 0.5f, 0.0f};
    const glm::mat4 want = glm::lookAt(glm::vec3(c.eye), glm::vec3(c.target), c.up), got = c.view();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_NEAR(got[i][j], want[i][j], 1e-5f) << i << "," << j;
    c.eye = {1e-23f, 0.0f, 0.0f};
    c.target = {0.0f, 0.0f, 0.0f};
    const glm::mat4 tiny = c.view();
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) EXPECT_TRUE(std::isfinite(tiny[i][j])) << i << "," << j;
    EXPECT_NEAR(tiny[0][2], 1.0f, 1e-6f); // looking along -x: the view's z axis is world +x
}

// Auto-framing near the poles: past the elevation where lookAt would degenerate (about 87.4
// degrees) the up vector was -fwd whatever the azimuth and the side, and from below the image
// turned by 145 degrees between -87 and -88 (the default azimuth, 35). The image's up direction
// (the view's second row) now changes smoothly through it, and at the pole follows the azimuth.
TEST(Camera, AutoFramingDoesNotTurnTheImageNearThePoles)
{
    const pr::Sphere bounds{{1, 2, 3}, 2};
    for (const float azimuth : {0.0f, 35.0f, 100.0f, -150.0f})
        for (const float side : {1.0f, -1.0f}) {
            glm::vec3 last(0.0f);
            for (float elevation = 85.0f; elevation <= 90.0f; elevation += 0.25f) {
                const pr::Camera c = pr::frame_sphere(bounds, 40, 1.5f, side * elevation, azimuth);
                const glm::mat4 v = c.view();
                const glm::vec3 image_up(v[0][1], v[1][1], v[2][1]); // world direction of screen up
                for (int i = 0; i < 3; ++i) ASSERT_TRUE(std::isfinite(image_up[i]));
                if (elevation > 85.0f)
                    EXPECT_GT(glm::dot(image_up, last), 0.99f)
                        << "azimuth " << azimuth << ", elevation " << side * elevation;
                last = image_up;
            }
        }
}

// Whether a sphere may show: the reference builds objects out of view only coarsely (a torus's
// level fell from 32 to 25 for two rocks behind the eye; thirty-eighth session).
TEST(Camera, SpheresBehindOrBesideTheViewAreOutOfIt)
{
    pr::Camera c;
    c.eye = {0.0, 0.0, 5.0};
    c.target = {0.0, 0.0, 0.0};
    c.fovy_deg = 40.0f;
    const auto in = [&](glm::dvec3 centre, double radius, double aspect = 1.0) {
        return pr::sphere_in_view(c, aspect, pr::Sphere{centre, radius});
    };
    EXPECT_TRUE(in({0.0, 0.0, 0.0}, 1.0));
    EXPECT_FALSE(in({0.0, 0.0, 8.0}, 1.0));  // behind the eye
    EXPECT_TRUE(in({0.0, 0.0, 5.5}, 1.0));   // around the eye
    EXPECT_TRUE(in({0.0, 0.0, 6.5}, 2.0));   // behind, reaching past it
    // tan 20 degrees * 5 = 1.82 at the target's distance: the top side's plane.
    EXPECT_TRUE(in({0.0, 2.5, 0.0}, 1.0));
    EXPECT_FALSE(in({0.0, 4.0, 0.0}, 1.0));
    EXPECT_FALSE(in({4.0, 0.0, 0.0}, 1.0));
    EXPECT_TRUE(in({4.0, 0.0, 0.0}, 1.0, 2.5)); // a wide picture's sides are further out
}
