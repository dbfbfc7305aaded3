// core/transform.hpp: the normal matrix and the inverse at any scale scenes allow (1e-15..1e15).
#include "core/transform.hpp"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

// In floats the inverse's determinant (s^3) overflowed past s = 7e12 and underflowed below about
// 2e-13: the normals came out 0 or NaN and every technique drew nothing.
TEST(Transform, NormalMatrixGivesUnitNormalsAtEveryScale)
{
    const glm::vec3 n = glm::normalize(glm::vec3(1.0f, 2.0f, -0.5f));
    for (const float s : {1e-15f, 1e-8f, 1.0f, 3e9f, 1e13f, 1e15f}) {
        SCOPED_TRACE(s);
        // A non-uniform scale and a rotation: the normal of the plane through the scaled points.
        const glm::mat4 m = glm::rotate(glm::scale(glm::mat4(1.0f), glm::vec3(s, 2.0f * s, 0.5f * s)), 0.7f,
                                        glm::vec3(0.0f, 0.0f, 1.0f));
        const glm::vec3 got = glm::normalize(pr::normal_matrix(m) * n);
        ASSERT_TRUE(std::isfinite(got.x) && std::isfinite(got.y) && std::isfinite(got.z));
        // Orthogonal to the images of two tangents of n.
        const glm::vec3 t1 = glm::normalize(glm::cross(n, glm::vec3(0.0f, 0.0f, 1.0f)));
        const glm::vec3 t2 = glm::cross(n, t1);
        for (const glm::vec3 t : {t1, t2}) {
            const glm::vec3 wt = glm::normalize(glm::vec3(m * glm::vec4(t, 0.0f)));
            EXPECT_NEAR(glm::dot(got, wt), 0.0f, 1e-5f);
        }
        // And the inverse takes world offsets back.
        const glm::vec3 back = pr::inverse_linear(m) * glm::vec3(m * glm::vec4(n, 0.0f));
        EXPECT_NEAR(glm::length(back - n), 0.0f, 1e-5f);
    }
}

// A power-of-two scaling keeps directions bit for bit: the identity's normals are unchanged.
TEST(Transform, NormalMatrixOfTheIdentityKeepsNormalsExactly)
{
    const glm::vec3 n = glm::normalize(glm::vec3(0.3f, -0.8f, 0.52f));
    EXPECT_EQ(glm::normalize(pr::normal_matrix(glm::mat4(1.0f)) * n), n);
}
