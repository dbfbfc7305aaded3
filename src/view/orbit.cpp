#include "view/orbit.hpp"

#include <algorithm>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>

namespace pr::view {

namespace {

glm::vec3 rotate(glm::vec3 v, glm::vec3 axis, float angle)
{
    return glm::vec3(glm::rotate(glm::mat4(1.0f), angle, axis) * glm::vec4(v, 0.0f));
}

} // namespace

void orbit(Camera& camera, float yaw, float pitch)
{
    const glm::vec3 up = glm::normalize(camera.up);
    glm::vec3 offset = camera.eye - camera.target;
    const float dist = glm::length(offset);
    if (!(dist > 0.0f)) return;
    offset = rotate(offset, up, yaw);
    // Angle from the up axis, kept inside (1 degree, 179 degrees).
    const float polar = std::acos(std::clamp(glm::dot(offset / dist, up), -1.0f, 1.0f));
    const float limit = glm::radians(1.0f);
    const float new_polar = std::clamp(polar - pitch, limit, glm::pi<float>() - limit);
    glm::vec3 right = glm::cross(up, offset);
    if (glm::length(right) < 1e-12f) right = glm::cross(up, glm::vec3(1.0f, 0.0f, 0.0f));
    right = glm::normalize(right);
    offset = rotate(offset, right, polar - new_polar);
    camera.eye = camera.target + offset;
}

void pan(Camera& camera, float dx, float dy, int viewport_height)
{
    const glm::vec3 forward = camera.target - camera.eye;
    const float dist = glm::length(forward);
    if (!(dist > 0.0f) || viewport_height < 1) return;
    const glm::vec3 f = forward / dist;
    const glm::vec3 right = glm::normalize(glm::cross(f, camera.up));
    const glm::vec3 cam_up = glm::cross(right, f);
    // Scene units per pixel at the target's distance.
    const float scale = 2.0f * dist * std::tan(glm::radians(camera.fovy_deg) * 0.5f) / float(viewport_height);
    const glm::vec3 move = (-right * dx + cam_up * dy) * scale;
    camera.eye += move;
    camera.target += move;
}

void zoom(Camera& camera, float steps, const Sphere& bounds)
{
    glm::vec3 offset = camera.eye - camera.target;
    const float dist = glm::length(offset);
    if (!(dist > 0.0f)) return;
    const float min_dist = 1e-3f * bounds.radius;
    const float max_dist = 100.0f * bounds.radius + glm::length(camera.target - bounds.center);
    const float new_dist = std::clamp(dist * std::pow(0.85f, steps), min_dist, max_dist);
    camera.eye = camera.target + offset * (new_dist / dist);
}

glm::vec3 direction_from_angles(float azimuth, float elevation)
{
    return {std::cos(elevation) * std::sin(azimuth), std::sin(elevation), std::cos(elevation) * std::cos(azimuth)};
}

void angles_from_direction(glm::vec3 dir, float& azimuth, float& elevation)
{
    dir = glm::normalize(dir);
    elevation = std::asin(std::clamp(dir.y, -1.0f, 1.0f));
    azimuth = std::atan2(dir.x, dir.z);
}

} // namespace pr::view
