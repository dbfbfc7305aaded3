#pragma once
// The linear parts of an object's transform that the renderer needs, computed in double. In
// floats the inverse's determinant (the scale cubed) overflows past a scale of about 7e12 (and
// underflows below about 2e-13), and every normal came out 0 or NaN: an empty image, exit 0,
// whatever the technique (docs/scenes.md allows scales from 1e-15 to 1e15).
#include <glm/mat3x3.hpp>
#include <glm/mat4x4.hpp>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include <algorithm>
#include <cmath>

namespace pr {

// Positions (eye, target, translations, where a mesh lies) and scales beyond this lose all
// meaning in the renderer: positions are double (at 1e15 neighbouring doubles are 0.125 apart),
// scales reach the shaders' 32-bit floats, and the products of two such coordinates (lengths,
// clip planes) overflow floats near 1e19. An eye at 1e30 rendered an empty image. The options
// refuse flags and scene values past it, load_scene an object its mesh's own file puts there.
inline constexpr double kMaxCoordinate = 1e15;

// An object's own frame: its transform without the translation, in float, as the shaders draw it
// (Renderer::upload_object); the translation stays double (GpuObject::origin), so large world
// coordinates cancel before anything is rounded (an object 10^7 out draws as one at the origin).
inline glm::mat4 linear_part(const glm::dmat4& transform)
{
    glm::mat4 m(transform);
    m[3] = glm::vec4(0.0f, 0.0f, 0.0f, 1.0f);
    return m;
}

// The inverse of the transform's 3x3 part: world offsets back to object space.
inline glm::mat3 inverse_linear(const glm::mat4& transform)
{
    return glm::mat3(glm::inverse(glm::dmat3(glm::mat3(transform))));
}

// The normal matrix (inverse transpose of the 3x3 part) scaled by a power of two to a largest
// entry in [0.5, 1): it gives directions only (every use normalizes), and a power of two leaves
// those bit for bit as they were while keeping the matrix in float range at any scale.
inline glm::mat3 normal_matrix(const glm::mat4& transform)
{
    glm::dmat3 m = glm::transpose(glm::inverse(glm::dmat3(glm::mat3(transform))));
    double largest = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(m[c][r]));
    if (largest > 0.0 && std::isfinite(largest)) {
        int exponent = 0;
        std::frexp(largest, &exponent);
        m *= std::ldexp(1.0, -exponent);
    }
    return glm::mat3(m);
}

// The ratio of the largest to the smallest stretch of `a` (the 2-norm condition number: its
// largest singular value over its smallest), by one-sided Jacobi rotations of its columns until
// they are orthogonal, when their lengths are the singular values. A scene refuses transforms
// past 1e6 (check_linear_part); it was measured with Frobenius norms, up to 3 times as large, and
// a scale [1, 1.2e-6, 1] was refused as "condition number 1.18e6" (found by an exploratory
// session, thirty-fifth). Infinity for a singular `a`.
inline double condition_number(glm::dmat3 a)
{
    for (int sweep = 0; sweep < 32; ++sweep) {
        bool rotated = false;
        for (int i = 0; i < 2; ++i)
            for (int j = i + 1; j < 3; ++j) {
                const double alpha = glm::dot(a[i], a[i]), beta = glm::dot(a[j], a[j]), gamma = glm::dot(a[i], a[j]);
                if (!(std::abs(gamma) > 1e-16 * std::sqrt(alpha) * std::sqrt(beta))) continue; // orthogonal enough
                rotated = true;
                // The rotation that makes columns i and j orthogonal (the smaller angle).
                const double zeta = (beta - alpha) / (2.0 * gamma);
                const double t = std::copysign(1.0, zeta) / (std::abs(zeta) + std::hypot(1.0, zeta));
                const double c = 1.0 / std::hypot(1.0, t), s = c * t;
                const glm::dvec3 ai = a[i];
                a[i] = c * ai - s * a[j];
                a[j] = s * ai + c * a[j];
            }
        if (!rotated) break;
    }
    double largest = 0.0, smallest = INFINITY;
    for (int c = 0; c < 3; ++c) {
        largest = std::max(largest, glm::length(a[c]));
        smallest = std::min(smallest, glm::length(a[c]));
    }
    return smallest > 0.0 ? largest / smallest : INFINITY;
}

} // namespace pr
