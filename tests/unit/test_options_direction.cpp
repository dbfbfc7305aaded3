// Directions given by the user (--light, --up, a scene's "light" and camera.up): any finite
// non-zero vector has a direction, however large or small its components; a float normalize
// overflowed at 3e19 and underflowed at 1e-30. Auto-framing takes such an up as it is.
#include "core/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace {

void expect_unit(const std::optional<glm::vec3>& v, glm::vec3 expected)
{
    ASSERT_TRUE(v.has_value());
    EXPECT_NEAR(v->x, expected.x, 1e-6f);
    EXPECT_NEAR(v->y, expected.y, 1e-6f);
    EXPECT_NEAR(v->z, expected.z, 1e-6f);
}

TEST(UnitDirection, HugeAndTinyVectorsKeepTheirDirection)
{
    const float d = 1.0f / std::sqrt(3.0f);
    expect_unit(pr::unit_direction({1e20, 1e20, 1e20}), {d, d, d});
    expect_unit(pr::unit_direction({3e19, 0, 0}), {1, 0, 0});
    expect_unit(pr::unit_direction({0, -1e300, 0}), {0, -1, 0});
    expect_unit(pr::unit_direction({1e-30, 0, 0}), {1, 0, 0});
    expect_unit(pr::unit_direction({1e-30, 1e-30, 1e-30}), {d, d, d});
    expect_unit(pr::unit_direction({0, 0, 5e-324}), {0, 0, 1}); // the smallest double
    expect_unit(pr::unit_direction({3, 4, 0}), {0.6f, 0.8f, 0});
}

TEST(UnitDirection, ZeroAndNonFiniteHaveNone)
{
    const double inf = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_FALSE(pr::unit_direction({0, 0, 0}).has_value());
    EXPECT_FALSE(pr::unit_direction({inf, 0, 0}).has_value());
    EXPECT_FALSE(pr::unit_direction({1, nan, 1}).has_value());
    EXPECT_FALSE(pr::unit_direction({nan, 1, 1}).has_value());
}

TEST(UnitDirection, FrameSphereTakesAHugeUp)
{
    const pr::Sphere bounds{{0, 0, 0}, 1};
    const pr::Camera huge = pr::frame_sphere(bounds, 40, 1, 25, 35, {0, 3e19f, 0});
    const pr::Camera unit = pr::frame_sphere(bounds, 40, 1, 25, 35, {0, 1, 0});
    for (int i = 0; i < 3; ++i) {
        EXPECT_TRUE(std::isfinite(huge.eye[i]));
        EXPECT_FLOAT_EQ(huge.eye[i], unit.eye[i]);
        EXPECT_FLOAT_EQ(huge.up[i], unit.up[i]);
    }
}

} // namespace
