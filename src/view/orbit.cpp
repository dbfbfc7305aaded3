#include "view/orbit.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace pr::view {

namespace {

// In double, as the camera's positions: the eye of a scene 10^7 out moves by the offset exactly.
glm::dvec3 rotate(glm::dvec3 v, glm::dvec3 axis, double angle)
{
    return glm::dvec3(glm::rotate(glm::dmat4(1.0), angle, axis) * glm::dvec4(v, 0.0));
}

} // namespace

void orbit(Camera& camera, float yaw, float pitch, glm::vec3 scene_up)
{
    if (!(glm::length(scene_up) > 0.0f)) scene_up = camera.up;
    const glm::dvec3 up = glm::normalize(glm::dvec3(scene_up));
    glm::dvec3 offset = camera.eye - camera.target;
    const double dist = glm::length(offset);
    if (!(dist > 0.0)) return;
    const double along = glm::dot(offset / dist, up);
    const double pole = 0.999; // (frame_sphere's: nearer, its camera's up is not the scene's)
    const glm::dvec3 picture_up = glm::dvec3(camera.up) - glm::dot(glm::dvec3(camera.up), up) * up;
    if (std::abs(along) > pole && glm::length(picture_up) > 0.5) {
        // On a pole, seen with a camera up across the scene's (frame_sphere's view along it): off
        // it as far as frame_sphere's pole reaches, away from the picture's up over the top and
        // towards it under the bottom. (Not where the camera's up is the scene's already, after
        // an orbit: there the picture's up is the eye's own azimuth, and a step to a fixed one
        // turned the picture by up to 180 degrees near the pole; found by a review.)
        const double side = along > 0.0 ? -1.0 : 1.0;
        offset = dist * (pole * (along > 0.0 ? up : -up) +
                         side * std::sqrt(1.0 - pole * pole) * glm::normalize(picture_up));
    }
    camera.up = glm::vec3(up);
    offset = rotate(offset, up, yaw);
    // Angle from the up axis, kept inside (1 degree, 179 degrees).
    const double polar = std::acos(std::clamp(glm::dot(offset / dist, up), -1.0, 1.0));
    const double limit = glm::radians(1.0);
    const double new_polar = std::clamp(polar - double(pitch), limit, glm::pi<double>() - limit);
    glm::dvec3 right = glm::cross(up, offset);
    if (glm::length(right) < 1e-12 * dist) right = glm::cross(up, glm::dvec3(1.0, 0.0, 0.0));
    right = glm::normalize(right);
    // (About cross(up, offset) a positive angle takes the eye away from up. It turned by
    // polar - new_polar, the pitch the wrong way round, which the clamp then mirrored: a pitch
    // past the pole took the eye over it, the picture upside down; found by a review.)
    offset = rotate(offset, right, new_polar - polar);
    camera.eye = camera.target + offset;
}

PanelDisplacement follow_panel(float first_depth, float first_midlevel, float depth, float midlevel,
                               float own_depth, float own_midlevel, bool first)
{
    if (first) return {depth, midlevel};
    const float ratio = first_depth > 0.0f ? depth / first_depth : 1.0f;
    return {own_depth * ratio, std::clamp(own_midlevel + (midlevel - first_midlevel), 0.0f, 1.0f)};
}

void pan(Camera& camera, float dx, float dy, int viewport_height)
{
    const glm::dvec3 forward = camera.target - camera.eye;
    const double dist = glm::length(forward);
    if (!(dist > 0.0) || viewport_height < 1) return;
    const glm::dvec3 f = forward / dist;
    const glm::dvec3 right = glm::normalize(glm::cross(f, glm::dvec3(camera.up)));
    const glm::dvec3 cam_up = glm::cross(right, f);
    // Scene units per pixel at the target's distance.
    const double scale = 2.0 * dist * std::tan(glm::radians(double(camera.fovy_deg)) * 0.5) / double(viewport_height);
    const glm::dvec3 move = (-right * double(dx) + cam_up * double(dy)) * scale;
    camera.eye += move;
    camera.target += move;
}

void zoom(Camera& camera, float steps, const Sphere& bounds)
{
    const glm::dvec3 offset = camera.eye - camera.target;
    const double dist = glm::length(offset);
    if (!(dist > 0.0)) return;
    const double min_dist = 1e-3 * bounds.radius;
    const double max_dist = 100.0 * bounds.radius + glm::length(camera.target - bounds.center);
    const double new_dist = std::clamp(dist * std::pow(0.85, double(steps)), min_dist, max_dist);
    camera.eye = camera.target + offset * (new_dist / dist);
}

namespace {

// The light's angles are measured as auto-framing's (core/camera.hpp, angle_frame): x the side
// (azimuth 90), y the scene's up, z the azimuth's zero.
struct LightFrame {
    glm::vec3 x, y, z;
};

LightFrame light_frame(glm::vec3 up)
{
    const AngleFrame f = angle_frame(glm::dvec3(unit_direction(glm::dvec3(up)).value_or(glm::vec3(0.0f, 1.0f, 0.0f))));
    return {glm::vec3(f.side), glm::vec3(f.up), glm::vec3(f.forward)};
}

} // namespace

glm::vec3 direction_from_angles(float azimuth, float elevation, glm::vec3 up)
{
    const LightFrame f = light_frame(up);
    return std::cos(elevation) * (std::sin(azimuth) * f.x + std::cos(azimuth) * f.z) + std::sin(elevation) * f.y;
}

void angles_from_direction(glm::vec3 dir, glm::vec3 up, float& azimuth, float& elevation)
{
    const LightFrame f = light_frame(up);
    dir = glm::normalize(dir);
    elevation = std::asin(std::clamp(glm::dot(dir, f.y), -1.0f, 1.0f));
    azimuth = std::atan2(glm::dot(dir, f.x), glm::dot(dir, f.z));
}

} // namespace pr::view
