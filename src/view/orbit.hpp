#pragma once
// Mouse camera control for the viewer: orbit around the target, pan, zoom (no GL, no window).
// Angles in radians, distances in scene units, pixels in the window's framebuffer.
#include "core/camera.hpp"

namespace pr::view {

// Turns the eye around `camera.target`: `yaw` about `camera.up`, `pitch` towards it (the eye
// stops just short of the poles so up stays meaningful).
void orbit(Camera& camera, float yaw, float pitch);
// Moves eye and target together so the point under the cursor follows it: (dx, dy) pixels,
// y down, in a viewport `viewport_height` pixels tall.
void pan(Camera& camera, float dx, float dy, int viewport_height);
// Moves the eye towards the target by a factor of 0.85 per step (negative steps move away).
void zoom(Camera& camera, float steps, const Sphere& bounds);

// Unit direction from azimuth (about +Y, 0 towards +Z) and elevation (above the XZ plane), and back.
glm::vec3 direction_from_angles(float azimuth, float elevation);
void angles_from_direction(glm::vec3 dir, float& azimuth, float& elevation);

} // namespace pr::view
