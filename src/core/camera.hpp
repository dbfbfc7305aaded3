#pragma once
// Perspective camera (contract): vertical field of view in degrees, eye/target/up, and
// auto-framing on a bounding sphere. World space throughout; clip z from 0 to w
// (glClipControl GL_ZERO_TO_ONE) with reversed depth: 1 at the near plane, 0 at the far one.
// Positions (the eye, the target, a sphere's centre) are double: a scene far from the origin (a
// model in geographic coordinates, 10^6 to 10^7 units out) keeps its view to the last digit,
// while every matrix the shaders get is float and relative to one object's frame (view_from).
#include <glm/glm.hpp>

#include <optional>
#include <vector>

namespace pr {

struct Sphere {
    glm::dvec3 center{0.0};
    double radius = 1.0;
};

struct Camera {
    glm::dvec3 eye{0.0, 0.0, 5.0};
    glm::dvec3 target{0.0};
    glm::vec3 up{0.0f, 1.0f, 0.0f};
    float fovy_deg = 40.0f;
    float near_plane = 0.01f; // chosen from the scene's bounds (see fit_clip_planes)
    float far_plane = 100.0f;

    glm::mat4 view() const;
    // The view of a frame whose origin is at `origin` in world space: view() * translate(origin),
    // in double, so that large world coordinates (an object translated by 10^6) cancel before
    // anything is rounded to float (Renderer::upload_object).
    glm::mat4 view_from(const glm::dvec3& origin) const;
    glm::mat4 projection(float aspect) const;
};

// The unit vector along `v`, or nullopt for the zero vector and for non-finite components. It
// divides by the largest absolute component first, in double: a plain float normalize squares
// the components, which overflows for 3e19 (the result is NaN) and underflows for 1e-30 (the
// vector looks like zero), though both are valid directions.
std::optional<glm::vec3> unit_direction(const glm::dvec3& v);

// What keeps a camera at `eye` looking at `target` with `up` from making a picture: the two
// points are one, or up lies along the view (the sine of their angle under 1e-5: lookAt's side
// vector is their cross product, and float rounding then turns the image by a visible angle).
// The options (naming the flag or the scene key) and scene_camera ask the same question.
enum class ViewProblem { None, SamePoint, UpAlongView };
ViewProblem view_problem(const glm::dvec3& eye, const glm::dvec3& target, const glm::dvec3& up);

// The frame azimuth and elevation are measured in about a unit `up` (auto-framing's, and the
// viewer's light angles): `forward` the horizontal direction of azimuth 0 (+Z made square to
// up, or +X where up is within about 25 degrees of Z), `side` that of azimuth 90 (up × forward:
// +X for the default +Y up). A direction is cos(el) (cos(az) forward + sin(az) side) + sin(el) up.
struct AngleFrame {
    glm::dvec3 side, up, forward;
};
AngleFrame angle_frame(const glm::dvec3& unit_up);

// Auto-framing: looks at `bounds.center` from `elevation_deg` above the horizontal plane
// (perpendicular to `up`) and `azimuth_deg` around `up` (0 looks along -Z from +Z, 90 from +X),
// at the distance where the sphere fits both the vertical and the horizontal field of view.
// `up` need not be unit length (any finite non-zero vector; the zero vector falls back to +Y).
Camera frame_sphere(const Sphere& bounds, float fovy_deg, float aspect, float elevation_deg,
                    float azimuth_deg, glm::dvec3 up = {0.0, 1.0, 0.0});

// The nearest the near plane comes to the eye, as a fraction of the far plane's distance: where
// the eye is inside an object's bounding sphere, near is this fraction of far (the reversed
// float depth of Camera::projection keeps its precision at any fraction; near must only stay
// above 0). At 10^-4 (before the sixteenth session, with the usual depth mapping) a floor 10^5
// units wide, seen from 1 unit above it, lost everything nearer than 15 units.
inline constexpr float kNearFraction = 1e-6f;

// Near and far planes that enclose `bounds` as seen from the camera (near never below
// kNearFraction of far).
void fit_clip_planes(Camera& camera, const Sphere& bounds);

// The same for several objects' bounds: far encloses them all, near comes from the nearest
// (each object's near is kept from a small fraction of its own far side, not the scene's, so
// that a far-away object does not push the near plane past the near ones). `all` encloses them
// (the result is fit_clip_planes(camera, all) for one object).
void fit_clip_planes(Camera& camera, const std::vector<Sphere>& objects, const Sphere& all);

// Whether any of `bounds` may show in a picture of `aspect` (width over height) from `camera`:
// false where the sphere lies wholly behind the eye or outside one of the field of view's four
// sides (the far plane encloses every object: fit_clip_planes).
bool sphere_in_view(const Camera& camera, double aspect, const Sphere& bounds);

// Distance from the eye along the pixel's ray for a window-space depth value (1 at the near plane,
// 0 at the far one: Camera::projection) at pixel
// centre (x + 0.5, y + 0.5) of a width x height image: the contract's depth-error measure.
float depth_to_distance(const Camera& camera, int width, int height, float x, float y, float window_depth);

} // namespace pr
