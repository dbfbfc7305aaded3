#include "core/camera.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace pr {

glm::mat4 Camera::view() const { return view_from(glm::dvec3(0.0)); }

glm::mat4 Camera::view_from(const glm::dvec3& origin) const
{
    // lookAt's frame from a view direction taken in double: glm::lookAt normalizes target - eye
    // in float, and eye and target 1e-23 apart (a valid view: view_problem() checks in double)
    // squared to nothing: the matrix came out NaN and the image empty.
    const glm::vec3 f = unit_direction(glm::dvec3(target) - glm::dvec3(eye)).value_or(glm::vec3(0.0f, 0.0f, -1.0f));
    const glm::vec3 s = glm::normalize(glm::cross(f, unit_direction(glm::dvec3(up)).value_or(glm::vec3(0.0f, 1.0f, 0.0f))));
    const glm::vec3 u = glm::cross(s, f);
    glm::mat4 m(1.0f);
    for (int i = 0; i < 3; ++i) {
        m[i][0] = s[i];
        m[i][1] = u[i];
        m[i][2] = -f[i];
    }
    // The eye relative to the origin, in double: world coordinates of 10^6 cancel exactly.
    const glm::dvec3 e = glm::dvec3(eye) - origin;
    m[3][0] = float(-glm::dot(glm::dvec3(s), e));
    m[3][1] = float(-glm::dot(glm::dvec3(u), e));
    m[3][2] = float(glm::dot(glm::dvec3(f), e));
    return m;
}

glm::mat4 Camera::projection(float aspect) const
{
    // Reversed depth: clip z from 0 to w (glClipControl's GL_ZERO_TO_ONE, set by the renderer),
    // window depth 1 at the near plane and 0 at the far one, into a float depth buffer. Floats
    // are as fine near 0 as the distance n/d needs, so the depth keeps about 7 digits of the
    // distance everywhere, whatever far / near is (with the usual mapping it kept
    // 7 - log10(far / near) digits at the far side, and near had to stay above 10^-4 of far).
    return glm::perspectiveRH_ZO(glm::radians(fovy_deg), aspect, far_plane, near_plane);
}

std::optional<glm::vec3> unit_direction(const glm::dvec3& v)
{
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) return std::nullopt;
    const double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (largest == 0.0) return std::nullopt;
    const glm::dvec3 scaled = v / largest; // largest component +-1: its square cannot overflow
    return glm::vec3(scaled / glm::length(scaled));
}

ViewProblem view_problem(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up)
{
    const std::optional<glm::vec3> forward = unit_direction(target - eye);
    if (!forward) return ViewProblem::SamePoint;
    const std::optional<glm::vec3> unit_up = unit_direction(up);
    if (!unit_up || glm::length(glm::cross(glm::dvec3(*forward), glm::dvec3(*unit_up))) < 1e-5)
        return ViewProblem::UpAlongView;
    return ViewProblem::None;
}

AngleFrame angle_frame(const glm::dvec3& unit_up)
{
    const glm::dvec3 ref = std::abs(unit_up.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
    const glm::dvec3 side = glm::normalize(glm::cross(unit_up, ref));
    return {side, unit_up, glm::normalize(glm::cross(side, unit_up))};
}

Camera frame_sphere(const Sphere& bounds, float fovy_deg, float aspect, float elevation_deg,
                    float azimuth_deg, glm::dvec3 up)
{
    Camera c;
    c.fovy_deg = fovy_deg;
    c.up = unit_direction(up).value_or(glm::vec3(0.0f, 1.0f, 0.0f));
    // In double: the eye is the centre plus the view's offset, and at a centre 10^7 out a float
    // eye was off by a good part of the object (docs/scenes.md).
    const glm::dvec3 unit_up(c.up);
    // A basis around `up`: `fwd` is the azimuth-0 horizontal direction towards the eye.
    const AngleFrame frame = angle_frame(unit_up);
    const glm::dvec3 side = frame.side, fwd = frame.forward;
    const double el = glm::radians(double(elevation_deg));
    const double az = glm::radians(double(azimuth_deg));
    const glm::dvec3 across = std::cos(az) * fwd + std::sin(az) * side;
    const glm::dvec3 dir = std::cos(el) * across + std::sin(el) * unit_up;
    // Looking (nearly) straight along `up` makes lookAt degenerate: up becomes what lookAt makes
    // of it below that, its part across the view, which at the pole is the azimuth's horizontal
    // direction, away from the eye from above and towards it from below. (It was -fwd whatever
    // the azimuth and the side: from below, the image turned by 145 degrees between elevations
    // -87 and -88 at the default azimuth.)
    if (std::abs(glm::dot(dir, unit_up)) > 0.999)
        c.up = glm::vec3(glm::normalize(std::cos(el) * unit_up - std::sin(el) * across));
    const double half_v = glm::radians(double(fovy_deg)) * 0.5;
    const double half_h = std::atan(std::tan(half_v) * double(aspect));
    const double half = std::min(half_v, half_h);
    const double distance = bounds.radius / std::sin(half) * 1.02;
    c.target = bounds.center;
    c.eye = bounds.center + dir * distance;
    fit_clip_planes(c, bounds);
    return c;
}

namespace {

// The planes are perpendicular to the view axis: a sphere's nearest point along it is its
// centre's depth along the axis less its radius, which is less than its distance from the eye
// less its radius wherever it lies off the axis. (Until the thirty-first session near was the
// latter: a cube 27 degrees off the axis, in view, lay wholly in front of the near plane and
// nothing was drawn; found by an exploratory session.) Far stays the distance plus the radius,
// which encloses the sphere from any direction.
double near_depth(const Camera& camera, const Sphere& b, double r)
{
    // Over its largest component first, as unit_direction does for the view matrix (in double
    // here): normalize's squared length underflowed for eye and target under 1.5e-162 apart, the
    // near plane came out NaN and the image empty (found by an exploratory session, thirty-fourth).
    glm::dvec3 forward = camera.target - camera.eye;
    const double largest = std::max({std::abs(forward.x), std::abs(forward.y), std::abs(forward.z)});
    forward = largest > 0.0 && std::isfinite(largest) ? glm::normalize(forward / largest) : glm::dvec3(0.0, 0.0, -1.0);
    return glm::dot(b.center - camera.eye, forward) - r;
}

} // namespace

bool sphere_in_view(const Camera& camera, double aspect, const Sphere& bounds)
{
    const glm::dvec3 to = bounds.center - camera.eye;
    const glm::dvec3 view = camera.target - camera.eye;
    if (!(glm::length(view) > 0.0) || glm::length(to) <= bounds.radius) return true; // (the eye inside)
    const glm::dvec3 f = glm::normalize(view);
    const glm::dvec3 side = glm::cross(f, glm::dvec3(camera.up));
    if (!(glm::length(side) > 0.0)) return true;
    const glm::dvec3 r = glm::normalize(side), u = glm::cross(r, f);
    const double x = glm::dot(to, r), y = glm::dot(to, u), z = glm::dot(to, f);
    if (z < -bounds.radius) return false;
    const double ty = std::tan(glm::radians(double(camera.fovy_deg)) * 0.5), tx = ty * aspect;
    // Each side's plane through the eye, its outward unit normal (x or y, -z tan) over its length.
    const auto outside = [&](double along, double tan_half) {
        return (along - z * tan_half) / std::sqrt(1.0 + tan_half * tan_half) > bounds.radius;
    };
    return !(outside(x, tx) || outside(-x, tx) || outside(y, ty) || outside(-y, ty));
}

void fit_clip_planes(Camera& camera, const Sphere& bounds)
{
    const double d = glm::length(camera.eye - bounds.center);
    const double r = bounds.radius * 1.05;
    camera.far_plane = float(d + r);
    camera.near_plane = std::max(float(near_depth(camera, bounds, r)), camera.far_plane * kNearFraction);
}

void fit_clip_planes(Camera& camera, const std::vector<Sphere>& objects, const Sphere& all)
{
    if (objects.size() < 2) return fit_clip_planes(camera, all);
    double near = INFINITY, far = 0.0;
    for (const Sphere& b : objects) {
        const double d = glm::length(camera.eye - b.center);
        const double r = b.radius * 1.05;
        far = std::max(far, d + r);
        near = std::min(near, std::max(near_depth(camera, b, r), (d + r) * double(kNearFraction)));
    }
    camera.far_plane = float(far);
    camera.near_plane = float(std::min(near, far * 0.5));
}

float depth_to_distance(const Camera& camera, int width, int height, float x, float y, float window_depth)
{
    const float aspect = static_cast<float>(width) / static_cast<float>(height);
    const glm::mat4 inv = glm::inverse(camera.projection(aspect));
    const glm::vec4 ndc((x + 0.5f) / width * 2.0f - 1.0f, (y + 0.5f) / height * 2.0f - 1.0f, window_depth,
                        1.0f); // clip z from 0 to w (Camera::projection)
    const glm::vec4 v = inv * ndc;
    return glm::length(glm::vec3(v) / v.w);
}

} // namespace pr
