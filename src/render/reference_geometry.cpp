#include "render/reference_geometry.hpp"

#include "core/transform.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace pr {

namespace {

// The view's frustum in the frame the eye is the origin of: `forward`, `right`, `up` its axes,
// `tan_x`, `tan_y` the tangents of its half angles (a little wider than the image), `near` the
// near plane's distance.
struct Frustum {
    glm::vec3 forward, right, up;
    float tan_x, tan_y, near;
};

// The nearest point to the eye (the origin) of triangle (a, b, c) that lies in the frustum, or
// nothing where none does: the triangle clipped by the frustum's five planes
// (Sutherland-Hodgman), then the nearest point of that convex polygon.
std::optional<glm::vec3> nearest_in_view(glm::vec3 a, glm::vec3 b, glm::vec3 c, const Frustum& f)
{
    // (Each plane adds at most one corner to a convex polygon: 3 + 5.)
    std::array<glm::vec3, 8> poly{a, b, c}, next{};
    int n = 3;
    const auto clip = [&](auto inside) {
        int m = 0;
        for (int i = 0; i < n; ++i) {
            const glm::vec3 p = poly[std::size_t(i)], q = poly[std::size_t((i + 1) % n)];
            const float dp = inside(p), dq = inside(q);
            if (dp >= 0.0f && m < 8) next[std::size_t(m++)] = p;
            if ((dp >= 0.0f) != (dq >= 0.0f) && m < 8) next[std::size_t(m++)] = p + (q - p) * (dp / (dp - dq));
        }
        poly = next;
        n = m;
    };
    const auto z = [&](glm::vec3 p) { return glm::dot(p, f.forward); };
    clip([&](glm::vec3 p) { return z(p) - f.near; });
    clip([&](glm::vec3 p) { return z(p) * f.tan_x - glm::dot(p, f.right); });
    clip([&](glm::vec3 p) { return z(p) * f.tan_x + glm::dot(p, f.right); });
    clip([&](glm::vec3 p) { return z(p) * f.tan_y - glm::dot(p, f.up); });
    clip([&](glm::vec3 p) { return z(p) * f.tan_y + glm::dot(p, f.up); });
    if (n == 0) return std::nullopt;
    // The nearest point: the eye's foot on the plane where it lies inside the polygon, else the
    // nearest of its edges' points.
    const glm::vec3 normal = glm::cross(b - a, c - a);
    const float area2 = glm::dot(normal, normal);
    if (area2 > 0.0f) {
        const glm::vec3 foot = normal * (glm::dot(a, normal) / area2);
        bool inside = true;
        for (int i = 0; i < n && inside; ++i) {
            const glm::vec3 p = poly[std::size_t(i)], q = poly[std::size_t((i + 1) % n)];
            inside = glm::dot(glm::cross(q - p, foot - p), normal) >= 0.0f;
        }
        if (inside) return foot;
    }
    glm::vec3 nearest = poly[0];
    for (int i = 0; i < n; ++i) {
        const glm::vec3 p = poly[std::size_t(i)], q = poly[std::size_t((i + 1) % n)], d = q - p;
        const float len2 = glm::dot(d, d);
        const float t = len2 > 0.0f ? std::clamp(-glm::dot(p, d) / len2, 0.0f, 1.0f) : 0.0f;
        if (glm::dot(p + t * d, p + t * d) < glm::dot(nearest, nearest)) nearest = p + t * d;
    }
    return nearest;
}

// A base triangle's corner: its vertex, its index and its displacement direction (object space).
struct Corner {
    const MeshVertex* v;
    std::uint32_t index;
    glm::vec3 offset;
};

// A grid point: the interpolated vertex and displacement direction.
struct GridPoint {
    MeshVertex v;
    glm::vec3 offset;
};

// Grid point (i, j) of a triangle split at `level`: barycentric weights
// (level - i - j, i, j) / level on corners (a, b, c).
// Edge points are evaluated from the edge's two endpoints only, in the order of their vertex
// indices, so both triangles sharing the edge compute exactly the same floating-point values.
GridPoint lerp_edge(const Corner& x, const Corner& y, int k, int level)
{
    // Point k/level of the way from x to y; canonical order: from the lower index.
    if (x.index > y.index) return lerp_edge(y, x, level - k, level);
    const float t = static_cast<float>(k) / static_cast<float>(level);
    const float s = static_cast<float>(level - k) / static_cast<float>(level);
    GridPoint p;
    MeshVertex& v = p.v;
    v.position = x.v->position * s + y.v->position * t;
    v.normal = x.v->normal * s + y.v->normal * t;
    v.uv = x.v->uv * s + y.v->uv * t;
    v.tangent = x.v->tangent * s + y.v->tangent * t;
    v.bitangent = x.v->bitangent * s + y.v->bitangent * t;
    v.weld_id = x.v->weld_id;
    p.offset = x.offset * s + y.offset * t;
    return p;
}

GridPoint interior(const Corner& a, const Corner& b, const Corner& c, int i, int j, int level)
{
    const float wb = static_cast<float>(i) / static_cast<float>(level);
    const float wc = static_cast<float>(j) / static_cast<float>(level);
    const float wa = static_cast<float>(level - i - j) / static_cast<float>(level);
    GridPoint p;
    MeshVertex& v = p.v;
    v.position = a.v->position * wa + b.v->position * wb + c.v->position * wc;
    v.normal = a.v->normal * wa + b.v->normal * wb + c.v->normal * wc;
    v.uv = a.v->uv * wa + b.v->uv * wb + c.v->uv * wc;
    v.tangent = a.v->tangent * wa + b.v->tangent * wb + c.v->tangent * wc;
    v.bitangent = a.v->bitangent * wa + b.v->bitangent * wb + c.v->bitangent * wc;
    v.weld_id = a.v->weld_id;
    p.offset = a.offset * wa + b.offset * wb + c.offset * wc;
    return p;
}

} // namespace

std::size_t reference_bytes_per_triangle(int level)
{
    const std::size_t l = static_cast<std::size_t>(level);
    return (l + 1) * (l + 2) / 2 * sizeof(MeshVertex) + l * l * 3 * sizeof(std::uint32_t);
}

TexelSteps texel_steps(const HeightField& height)
{
    TexelSteps s;
    for (int y = 0; y < height.height; ++y)
        for (int x = 0; x < height.width; ++x) {
            const float h = height.at(x, y);
            s.steepest = std::max({s.steepest, std::abs(height.at(x + 1, y) - h), std::abs(height.at(x, y + 1) - h)});
        }
    s.span = height.max_value() - height.min_value();
    return s;
}

ReferenceLevel choose_reference_level(const PreparedMesh& mesh, const glm::dmat4& transform,
                                      const HeightField& height, const TexelSteps& steps, float depth, float midlevel,
                                      const Camera& camera, int width_px, int height_px, std::size_t max_triangles,
                                      int floor_level)
{
    ReferenceLevel r;
    // Pixels per world unit at distance 1 (vertical field of view over the image height).
    const float tan_half = std::tan(glm::radians(camera.fovy_deg) * 0.5f);
    const float focal_px = 0.5f * static_cast<float>(height_px) / tan_half;
    // Off the axis the picture stretches a length across the ray by 1 / cos^2 of its angle to the
    // axis (x = f tan(angle)): measured at the axis, a wide field of view's edges got a reference
    // far too coarse there (--fovy 178.9: level 2, the prism's IoU 0.968 against it, 0.9998
    // against level 64; found by an exploratory session, thirty-fifth). The angle is taken no
    // wider than the image's corner.
    const float aspect = static_cast<float>(std::max(width_px, 1)) / static_cast<float>(std::max(height_px, 1));
    const float cos_corner = 1.0f / std::sqrt(1.0f + tan_half * tan_half * (1.0f + aspect * aspect));
    const glm::vec3 forward(glm::normalize(camera.target - camera.eye));
    // `steps.steepest`, the steepest rise between neighbouring texels: along an edge spanning s
    // texels the height changes by at most min(1, s * steepest), and the displaced edge is longer
    // by depth times that.
    // The ends of the displacement range along the normal: depth * (h - midlevel), h in [0, 1].
    const float reach = displacement_reach(depth, midlevel);
    // In the object's frame (its translation taken out, in double), as the renderer draws it.
    const glm::mat4 local = linear_part(transform);
    const glm::vec3 eye(camera.eye - glm::dvec3(transform[3]));
    const glm::mat3 normals = normal_matrix(local);
    // Pixels per unit across the ray at `to` from the eye: the nearer, and the further off the
    // axis, the more.
    const auto pixels_per_unit = [&](glm::vec3 to, float closer) {
        const float dist = glm::length(to);
        const float c = std::max(dist > 0.0f ? glm::dot(to, forward) / dist : 1.0f, cos_corner);
        return 1.0f / (std::max(dist - closer, camera.near_plane) * c * c);
    };
    // A large triangle's nearest point in view may lie far from its corners (a two-triangle floor
    // seen from just above it: the corners 14 times as far as the floor under the view, and the
    // reference there 15 dB from the prism): its nearest point in the frustum, the displacement's
    // reach nearer still, counts too.
    const glm::vec3 view_right = glm::normalize(glm::cross(forward, glm::vec3(camera.up)));
    const Frustum frustum{forward, view_right, glm::cross(view_right, forward), 1.02f * tan_half * aspect,
                          1.02f * tan_half, camera.near_plane};
    float max_texel_edge = 0.0f, max_pixel_edge = 0.0f;
    const auto& v = mesh.vertices;
    for (std::size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        float triangle_unit = 0.0f;
        const auto at = [&](int e) { return glm::vec3(local * glm::vec4(v[mesh.indices[t + std::size_t(e)]].position, 1.0f)) - eye; };
        if (const std::optional<glm::vec3> nearest = nearest_in_view(at(0), at(1), at(2), frustum))
            triangle_unit = pixels_per_unit(*nearest, reach);
        for (int e = 0; e < 3; ++e) {
            const MeshVertex& p = v[mesh.indices[t + e]];
            const MeshVertex& q = v[mesh.indices[t + (e + 1) % 3]];
            const glm::vec2 duv = (q.uv - p.uv) * glm::vec2(height.width, height.height);
            const float texel_span = std::max(std::abs(duv.x), std::abs(duv.y));
            max_texel_edge = std::max(max_texel_edge, texel_span);
            const glm::vec3 wp = glm::vec3(local * glm::vec4(p.position, 1.0f));
            const glm::vec3 wq = glm::vec3(local * glm::vec4(q.position, 1.0f));
            const glm::vec3 np = glm::normalize(normals * p.normal);
            const glm::vec3 nq = glm::normalize(normals * q.normal);
            // An edge of the displaced surface is at most the base edge, plus the spread of the
            // normals over the reach (a curved mesh's shell is wider at its outer end), plus the
            // rise of the height along it (deep shells: --depth as large as the object).
            const float displaced = glm::length(wq - wp) + reach * glm::length(nq - np) +
                                    depth * std::min(1.0f, texel_span * steps.steepest);
            // Pixels per unit across the ray at the nearest, most stretched of the edge's ends.
            float per_unit = triangle_unit;
            for (const glm::vec3& end : {wp, wq, wp - reach * np, wq - reach * nq, wp + reach * np, wq + reach * nq})
                per_unit = std::max(per_unit, pixels_per_unit(end - eye, 0.0f));
            max_pixel_edge = std::max(max_pixel_edge, displaced * focal_px * per_unit);
        }
    }
    const float texels_per_edge = steps.steepest > kSharpStep * steps.span ? 0.5f : 1.0f;
    // Bounded before the conversion to int: an eye inside the shell, within the displacement's
    // reach of a triangle it sees, measures it from the near plane, and a narrow field of view
    // took the product past 2^31 (the cast gave INT_MIN, the level fell to the cheap one without
    // a word; found by a review). Not a number counts as the finest.
    const auto bounded_level = [](float edges) {
        const double v = std::ceil(double(edges));
        return v < 1.0 ? 1 : (v <= double(kMaxReferenceLevel) ? int(v) : kMaxReferenceLevel);
    };
    r.texel_level = bounded_level(max_texel_edge / texels_per_edge);
    r.pixel_level = bounded_level(max_pixel_edge);
    const int wanted = std::min(r.texel_level, r.pixel_level);
    r.level = std::max(wanted, std::min(r.texel_level, floor_level));
    const std::size_t tris = std::max<std::size_t>(mesh.triangle_count(), 1);
    while (r.level > 1 && tris * std::size_t(r.level) * std::size_t(r.level) > max_triangles) --r.level;
    r.capped = r.level < wanted;
    return r;
}

std::size_t cap_reference_levels(std::vector<ReferenceLevel>& levels, const std::vector<std::size_t>& triangles,
                                 std::size_t max_triangles)
{
    int top = 1;
    for (const ReferenceLevel& l : levels) top = std::max(top, l.level);
    const auto total = [&](int cap) {
        std::size_t sum = 0;
        for (std::size_t k = 0; k < levels.size(); ++k) {
            const auto l = std::size_t(std::min(levels[k].level, cap));
            sum += std::max<std::size_t>(triangles[k], 1) * l * l;
        }
        return sum;
    };
    int cap = top;
    while (cap > 1 && total(cap) > max_triangles) --cap;
    for (ReferenceLevel& l : levels) {
        l.level = std::min(l.level, cap);
        l.capped = l.level < std::min(l.texel_level, l.pixel_level);
    }
    return total(cap);
}

int cheap_reference_level(std::size_t scene_triangles)
{
    const std::size_t tris = std::max<std::size_t>(scene_triangles, 1);
    int level = 1;
    while (tris * std::size_t(level + 1) * std::size_t(level + 1) <= kCheapReferenceTriangles) ++level;
    return level;
}

void tessellate_reference(const PreparedMesh& mesh, const glm::mat4& transform, const HeightField& height,
                          float depth, float midlevel, int level, std::size_t first, std::size_t last,
                          std::vector<MeshVertex>& vertices, std::vector<std::uint32_t>& indices)
{
    level = std::max(level, 1);
    const auto& v = mesh.vertices;
    // The world unit normal of the prism's shell (make_shell_corners: the normal matrix, then
    // normalized), taken back to object space by the inverse of the transform's linear part.
    const glm::mat3 to_object = inverse_linear(transform);
    const glm::mat3 normals = normal_matrix(transform);
    const auto corner = [&](std::uint32_t i) {
        return Corner{&v[i], i, to_object * glm::normalize(normals * v[i].normal)};
    };
    const int per_row_total = (level + 1) * (level + 2) / 2;
    std::vector<std::uint32_t> grid(static_cast<std::size_t>(per_row_total));
    for (std::size_t t = first; t < last; ++t) {
        const Corner a = corner(mesh.indices[3 * t]), b = corner(mesh.indices[3 * t + 1]),
                     c = corner(mesh.indices[3 * t + 2]);
        // Grid points row by row: j = 0..level (towards c), i = 0..level-j (towards b).
        int n = 0;
        for (int j = 0; j <= level; ++j) {
            for (int i = 0; i <= level - j; ++i) {
                GridPoint p;
                if (j == 0) p = lerp_edge(a, b, i, level);              // edge a-b
                else if (i == 0) p = lerp_edge(a, c, j, level);         // edge a-c
                else if (i + j == level) p = lerp_edge(b, c, j, level); // edge b-c
                else p = interior(a, b, c, i, j, level);
                // Displace along the interpolated (not renormalized) normal: S stays inside the
                // straight-edged prism (contract).
                const float h = height.sample(p.v.uv);
                p.v.position += depth * (h - midlevel) * p.offset;
                grid[static_cast<std::size_t>(n++)] = static_cast<std::uint32_t>(vertices.size());
                vertices.push_back(p.v);
            }
        }
        // Row start offsets: row j starts after rows 0..j-1 of (level + 1 - r) points each.
        const auto at = [level](int i, int j) { return j * (level + 1) - j * (j - 1) / 2 + i; };
        for (int j = 0; j < level; ++j) {
            for (int i = 0; i < level - j; ++i) {
                const std::uint32_t p0 = grid[at(i, j)], p1 = grid[at(i + 1, j)], p2 = grid[at(i, j + 1)];
                indices.insert(indices.end(), {p0, p1, p2});
                if (i + 1 < level - j) {
                    const std::uint32_t p3 = grid[at(i + 1, j + 1)];
                    indices.insert(indices.end(), {p1, p3, p2});
                }
            }
        }
    }
}

} // namespace pr
