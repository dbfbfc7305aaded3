#pragma once
// Whether a point lies inside closed surfaces, by counting where rays from it cross triangles:
// shared by the renderer's eye-inside-body test (render/eye_prism.cpp) and the loader's nesting
// of closed pieces (mesh/mesh_prepare.cpp).
#include <glm/glm.hpp>

#include <array>
#include <cmath>

namespace pr {

// Three rays in unrelated directions: one through an edge or a corner may count a crossing twice
// or not at all, so inside tests take the vote of the three.
inline const std::array<glm::dvec3, 3>& vote_ray_directions()
{
    static const std::array<glm::dvec3, 3> dirs = {glm::normalize(glm::dvec3(0.5377, 0.7219, 0.4353)),
                                                   glm::normalize(glm::dvec3(-0.6513, 0.2291, -0.7233)),
                                                   glm::normalize(glm::dvec3(0.1847, -0.8966, 0.4025))};
    return dirs;
}

// Where the ray from `origin` along `d` (ahead of the origin only) crosses triangle (a, b, c)
// (Moller-Trumbore): +1 where it goes out through the triangle's front (d . ((b - a) x (c - a))
// positive), -1 where it comes in, 0 where it misses.
inline int ray_crossing(const glm::dvec3& origin, const glm::dvec3& d, const glm::dvec3& a, const glm::dvec3& b,
                        const glm::dvec3& c)
{
    const glm::dvec3 ab = b - a, ac = c - a;
    const glm::dvec3 p = glm::cross(d, ac);
    const double det = glm::dot(ab, p); // = -d . (ab x ac)
    if (std::abs(det) < 1e-300) return 0;
    const glm::dvec3 s = origin - a;
    const double u = glm::dot(s, p) / det;
    if (u < 0.0 || u > 1.0) return 0;
    const glm::dvec3 q = glm::cross(s, ab);
    const double v = glm::dot(d, q) / det;
    if (v < 0.0 || u + v > 1.0) return 0;
    if (!(glm::dot(ac, q) / det > 0.0)) return 0;
    return det < 0.0 ? 1 : -1;
}

} // namespace pr
