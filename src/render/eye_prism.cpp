// The prism that holds the eye (eye_prism.hpp).
#include "render/eye_prism.hpp"

#include "core/ray_crossing.hpp"

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace pr {

namespace {

// Grows the box lo..hi by the column of corner c from the bottom to height h.
void add_column(glm::vec3& lo, glm::vec3& hi, const ShellCorner& c, float h, float depth)
{
    const glm::vec3 top = c.at(h, depth);
    lo = glm::min(lo, glm::min(c.bottom, top));
    hi = glm::max(hi, glm::max(c.bottom, top));
}

// A box grown by 10^-4 of its size (and a little more): the slack of every box test here.
void add_margin(glm::vec3& lo, glm::vec3& hi)
{
    const glm::vec3 margin = 1e-4f * (hi - lo) + glm::vec3(1e-7f);
    lo -= margin;
    hi += margin;
}

glm::vec3 empty_lo() { return glm::vec3(std::numeric_limits<float>::max()); }
glm::vec3 empty_hi() { return glm::vec3(-std::numeric_limits<float>::max()); }

} // namespace

std::optional<glm::vec3> prism_coordinates(const std::vector<glm::vec4>& corners, std::uint32_t a, std::uint32_t b,
                                           std::uint32_t c, float depth, glm::vec3 eye)
{
    // F(w1, w2, h) = B0 + w1 (B1 - B0) + w2 (B2 - B0) + h d (N0 + w1 (N1 - N0) + w2 (N2 - N0)) - eye.
    const ShellCorner ca = shell_corner(corners, a), cb = shell_corner(corners, b), cc = shell_corner(corners, c);
    const glm::dvec3 b0(ca.bottom), e1 = glm::dvec3(cb.bottom) - b0, e2 = glm::dvec3(cc.bottom) - b0;
    const double d = depth;
    const glm::dvec3 n0 = d * glm::dvec3(ca.normal), m1 = d * glm::dvec3(cb.normal) - n0,
                     m2 = d * glm::dvec3(cc.normal) - n0;
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
    const ShellCorner c[3] = {shell_corner(corners, t[0]), shell_corner(corners, t[1]), shell_corner(corners, t[2])};
    const float h_max = full_shell ? 1.0f : std::max({c[0].top, c[1].top, c[2].top});
    glm::vec3 lo = empty_lo(), hi = empty_hi();
    for (const ShellCorner& k : c) add_column(lo, hi, k, h_max, depth);
    add_margin(lo, hi);
    return glm::all(glm::greaterThanEqual(eye, lo)) && glm::all(glm::lessThanEqual(eye, hi));
}

bool eye_in_prism(const std::vector<glm::vec4>& corners, const std::uint32_t* t, float depth, bool full_shell,
                  glm::vec3 eye)
{
    // The six corners as shell.glsl builds them (load_walk_prism): 0..2 bottom, 3..5 top.
    glm::dvec3 p[6];
    std::uint32_t weld[3];
    for (int k = 0; k < 3; ++k) {
        const ShellCorner c = shell_corner(corners, t[k]);
        p[k] = glm::dvec3(c.bottom) - glm::dvec3(eye);
        p[k + 3] = glm::dvec3(c.at(full_shell ? 1.0f : c.top, depth)) - glm::dvec3(eye);
        weld[k] = c.weld;
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
    b.lo.assign(blocks, empty_lo());
    b.hi.assign(blocks, empty_hi());
    for (std::size_t t = 0; t < triangles; ++t)
        for (int k = 0; k < 3; ++k)
            add_column(b.lo[t / PrismBlocks::kSize], b.hi[t / PrismBlocks::kSize],
                       shell_corner(corners, indices[3 * t + std::size_t(k)]), 1.0f, depth);
    for (std::size_t i = 0; i < blocks; ++i) add_margin(b.lo[i], b.hi[i]);
    return b;
}

bool eye_inside_body(const std::vector<glm::vec4>& corners, const std::vector<std::uint32_t>& indices,
                     const PrismBlocks& blocks, glm::vec3 eye)
{
    // Crossings of the bottom caps by a ray from the eye, signed: +1 where the ray leaves through
    // a cap (an outward face seen from behind), -1 where it enters; the sum is how many bodies
    // hold the eye, inside when positive. (By parity, an eye inside two closed pieces of one mesh
    // nested one in the other counted as outside: the prism drew nothing at all.) A ray through
    // an edge or a corner may count a crossing twice or not at all, so three rays in unrelated
    // directions vote.
    const glm::dvec3 e(eye);
    const std::size_t triangles = indices.size() / 3;
    int votes = 0;
    for (const glm::dvec3& d : vote_ray_directions()) {
        const glm::dvec3 inv = 1.0 / d;
        int winding = 0;
        for (std::size_t block = 0; block < blocks.lo.size(); ++block) {
            // Slab test of the ray against the block's box.
            const glm::dvec3 t0 = (glm::dvec3(blocks.lo[block]) - e) * inv, t1 = (glm::dvec3(blocks.hi[block]) - e) * inv;
            const glm::dvec3 near = glm::min(t0, t1), far = glm::max(t0, t1);
            if (std::max({near.x, near.y, near.z}) > std::min({far.x, far.y, far.z}) || std::min({far.x, far.y, far.z}) < 0.0)
                continue;
            const std::size_t end = std::min(triangles, (block + 1) * PrismBlocks::kSize);
            for (std::size_t t = block * PrismBlocks::kSize; t < end; ++t)
                winding += ray_crossing(e, d, glm::dvec3(shell_corner(corners, indices[3 * t]).bottom),
                                        glm::dvec3(shell_corner(corners, indices[3 * t + 1]).bottom),
                                        glm::dvec3(shell_corner(corners, indices[3 * t + 2]).bottom));
        }
        votes += winding > 0 ? 1 : 0;
    }
    return votes >= 2;
}

} // namespace pr
