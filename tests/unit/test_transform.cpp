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

// The ratio of the largest stretch to the smallest (2-norm), as docs/scenes.md states the limit;
// it was taken from Frobenius norms, up to 3 times as large, and refused [1, 1.2e-6, 1].
TEST(Transform, ConditionNumberIsTheRatioOfLargestToSmallestStretch)
{
    EXPECT_NEAR(pr::condition_number(glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(0, 1.2e-6, 0), glm::dvec3(0, 0, 1))),
                1.0 / 1.2e-6, 1e-3);
    // Rotated and mirrored: the stretches 3, 1 and 2.
    const glm::dmat3 r(glm::rotate(glm::dmat4(1.0), 0.7, glm::normalize(glm::dvec3(1, 2, 3))));
    const glm::dmat3 d(glm::dvec3(3, 0, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 2));
    EXPECT_NEAR(pr::condition_number(r * d * glm::transpose(r)), 3.0, 1e-12);
    EXPECT_NEAR(pr::condition_number(r * d), 3.0, 1e-12);
    // A shear by k: singular values (sqrt(k^2 + 4) ± k) / 2, so the ratio is their quotient.
    for (const double k : {0.5, 10.0, 999.0}) {
        SCOPED_TRACE(k);
        glm::dmat3 shear(1.0);
        shear[1][0] = k; // column 1, row 0: x += k y
        const double hi = (std::sqrt(k * k + 4.0) + k) / 2.0, lo = (std::sqrt(k * k + 4.0) - k) / 2.0;
        EXPECT_NEAR(pr::condition_number(shear), hi / lo, 1e-9 * hi / lo);
    }
    EXPECT_GT(pr::condition_number(glm::dmat3(glm::dvec3(1, 0, 0), glm::dvec3(2, 0, 0), glm::dvec3(0, 0, 1))), 1e12);
}
