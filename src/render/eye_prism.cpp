// The prism that holds the eye (eye_prism.hpp).
#include "render/eye_prism.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace pr {

namespace {

glm::dvec3 bottom_of(const std::vector<glm::vec4>& corners, std::uint32_t i)
{
    return glm::dvec3(corners[3 * std::size_t(i)]);
}

glm::dvec3 normal_of(const std::vector<glm::vec4>& corners, std::uint32_t i)
{
    return glm::dvec3(corners[3 * std::size_t(i) + 1]);
}

} // namespace

std::optional<glm::vec3> prism_coordinates(const std::vector<glm::vec4>& corners, std::uint32_t a, std::uint32_t b,
                                           std::uint32_t c, float depth, glm::vec3 eye)
{
    // F(w1, w2, h) = B0 + w1 (B1 - B0) + w2 (B2 - B0) + h d (N0 + w1 (N1 - N0) + w2 (N2 - N0)) - eye.
    const glm::dvec3 b0 = bottom_of(corners, a), e1 = bottom_of(corners, b) - b0, e2 = bottom_of(corners, c) - b0;
    const double d = depth;
    const glm::dvec3 n0 = d * normal_of(corners, a), m1 = d * normal_of(corners, b) - n0,
                     m2 = d * normal_of(corners, c) - n0;
    const glm::dvec3 target(eye);
    const double scale = std::max({glm::length(e1), glm::length(e2), d, 1e-30});
    glm::dvec3 q(1.0 / 3.0, 1.0 / 3.0, 0.5);
    for (int step = 0; step < 16; ++step) {
        const glm::dvec3 n = n0 + q.x * m1 + q.y * m2;
        const glm::dvec3 f = b0 + q.x * e1 + q.y * e2 + q.z * n - target;
        if (glm::length(f) <= 1e-9 * scale) return glm::vec3(q);
        const glm::dmat3 jacobian(e1 + q.z * m1, e2 + q.z * m2, n); // columns: d/dw1, d/dw2, d/dh
        const double det = glm::determinant(jacobian);
        if (!(std::abs(det) > 1e-300)) return std::nullopt;
        q -= glm::inverse(jacobian) * f;
        if (!(std::abs(q.x) < 1e6 && std::abs(q.y) < 1e6 && std::abs(q.z) < 1e6)) return std::nullopt;
    }
    return std::nullopt;
}

bool eye_near_prism(const std::vector<glm::vec4>& corners, const std::uint32_t* t, float depth, bool full_shell,
                    glm::vec3 eye)
{
    // Every point of the prism lies on a segment from bottom_i to bottom_i + h_max d N_i, h_max
    // its highest top, combined with the barycentric weights: inside those six points' box.
    float h_max = 1.0f;
    if (!full_shell)
        h_max = std::max({corners[3 * std::size_t(t[0]) + 2].x, corners[3 * std::size_t(t[1]) + 2].x,
                          corners[3 * std::size_t(t[2]) + 2].x});
    glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
    for (int k = 0; k < 3; ++k) {
        const glm::vec4* c = &corners[3 * std::size_t(t[k])];
        const glm::vec3 bottom(c[0]);
        const glm::vec3 top = bottom + h_max * depth * glm::vec3(c[1]);
        lo = glm::min(lo, glm::min(bottom, top));
        hi = glm::max(hi, glm::max(bottom, top));
    }
    const glm::vec3 margin = 1e-4f * (hi - lo) + glm::vec3(1e-7f);
    return glm::all(glm::greaterThanEqual(eye, lo - margin)) && glm::all(glm::lessThanEqual(eye, hi + margin));
}

bool eye_in_prism(const std::vector<glm::vec4>& corners, const std::uint32_t* t, float depth, bool full_shell,
                  glm::vec3 eye)
{
    // The six corners as shell.glsl builds them (load_walk_prism): 0..2 bottom, 3..5 top.
    glm::dvec3 p[6];
    std::uint32_t weld[3];
    for (int k = 0; k < 3; ++k) {
        const glm::vec4* c = &corners[3 * std::size_t(t[k])];
        const glm::vec3 bottom(c[0]);
        const float top = full_shell ? 1.0f : c[2].x;
        p[k] = glm::dvec3(bottom) - glm::dvec3(eye);
        p[k + 3] = glm::dvec3(bottom + top * (depth * glm::vec3(c[1]))) - glm::dvec3(eye);
        weld[k] = std::bit_cast<std::uint32_t>(c[2].y);
    }
    // The solid angle of each triangle seen from the eye (Van Oosterom and Strackee); their sum
    // over a closed surface is 4 pi inside (either orientation) and 0 outside.
    // An eye in the plane of a triangle and inside it is on the prism's boundary: it counts as in.
    bool on_face = false;
    const auto solid_angle = [&](int i, int j, int k) {
        const glm::dvec3 &a = p[i], &b = p[j], &c = p[k];
        const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
        const double num = glm::dot(a, glm::cross(b, c));
        if (std::abs(num) <= 1e-9 * la * lb * lc) {
            const glm::dvec3 ab = glm::cross(a, b), bc = glm::cross(b, c), ca = glm::cross(c, a);
            on_face = on_face || (glm::dot(ab, bc) >= 0.0 && glm::dot(bc, ca) >= 0.0 && glm::dot(ca, ab) >= 0.0);
            return 0.0;
        }
        const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(b, c) * la + glm::dot(c, a) * lb;
        return 2.0 * std::atan2(num, den);
    };
    double sum = solid_angle(3, 4, 5) + solid_angle(0, 2, 1);
    for (int e = 0; e < 3; ++e) {
        const int a = e, b = (e + 1) % 3;
        if (weld[a] < weld[b]) { // the diagonal from a's bottom to b's top: (a, b, b'), (a, b', a')
            sum += solid_angle(a, b, b + 3) + solid_angle(a, b + 3, a + 3);
        } else { // from b's bottom to a's top: (a, b, a'), (b, b', a')
            sum += solid_angle(a, b, a + 3) + solid_angle(b, b + 3, a + 3);
        }
    }
    // Inside: a winding number of 1. On a face it is 1/2, on an edge the share of the dihedral
    // angle, just outside 0: a point on the prism's boundary counts as in it.
    return on_face || std::abs(sum) > 0.2 * 4.0 * 3.14159265358979323846;
}

PrismBlocks prism_blocks(const std::vector<glm::vec4>& corners, const std::vector<std::uint32_t>& indices, float depth)
{
    PrismBlocks b;
    const std::size_t triangles = indices.size() / 3;
    const std::size_t blocks = (triangles + PrismBlocks::kSize - 1) / PrismBlocks::kSize;
    b.lo.assign(blocks, glm::vec3(std::numeric_limits<float>::max()));
    b.hi.assign(blocks, glm::vec3(-std::numeric_limits<float>::max()));
    for (std::size_t t = 0; t < triangles; ++t) {
        glm::vec3& lo = b.lo[t / PrismBlocks::kSize];
        glm::vec3& hi = b.hi[t / PrismBlocks::kSize];
        for (int k = 0; k < 3; ++k) {
            const glm::vec4* c = &corners[3 * std::size_t(indices[3 * t + std::size_t(k)])];
            const glm::vec3 bottom(c[0]), top = bottom + depth * glm::vec3(c[1]);
            lo = glm::min(lo, glm::min(bottom, top));
            hi = glm::max(hi, glm::max(bottom, top));
        }
    }
    // The margin of eye_near_prism().
    for (std::size_t i = 0; i < blocks; ++i) {
        const glm::vec3 margin = 1e-4f * (b.hi[i] - b.lo[i]) + glm::vec3(1e-7f);
        b.lo[i] -= margin;
        b.hi[i] += margin;
    }
    return b;
}

} // namespace pr
