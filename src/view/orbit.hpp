#pragma once
// Mouse camera control for the viewer (orbit around the target, pan, zoom) and the panel's
// displacement maths (no GL, no window).
// Angles in radians, distances in scene units, pixels in the window's framebuffer.
#include "core/camera.hpp"

namespace pr::view {

// Turns the eye around `camera.target`: `yaw` about the scene's `up`, `pitch` towards it (the eye
// stops a degree short of the poles; it went over them, a pitch's sign turned), and sets the
// camera's up to it. (It turned about
// `camera.up`, which a view along the scene's up replaces with a horizontal direction
// (frame_sphere): a horizontal drag from `--elevation 90` turned the camera over, under the floor;
// found by an exploratory session.) An eye on a pole first steps off it (2.6 degrees) away from
// the picture's up, so that the picture does not turn.
void orbit(Camera& camera, float yaw, float pitch, glm::vec3 up);
// Moves eye and target together so the point under the cursor follows it: (dx, dy) pixels,
// y down, in a viewport `viewport_height` pixels tall.
void pan(Camera& camera, float dx, float dy, int viewport_height);
// Moves the eye towards the target by a factor of 0.85 per step (negative steps move away).
void zoom(Camera& camera, float steps, const Sphere& bounds);

// The panel's depth and midlevel sliders show object 0's; each other object follows: its depth by
// the same ratio (when object 0's was 0, it keeps its own), its midlevel by the same shift,
// within 0..1. (Every object took object 0's midlevel, and with object 0's depth 0 the slider's
// depth: found by an exploratory session.)
struct PanelDisplacement {
    float depth = 0.0f, midlevel = 0.0f;
};
PanelDisplacement follow_panel(float first_depth, float first_midlevel, float depth, float midlevel,
                               float own_depth, float own_midlevel, bool first);

// Unit direction from azimuth (about the scene's `up`, 0 towards +Z made square to it: +Z for
// +Y up, +X where up is within 25 degrees of Z) and elevation (above the plane square to `up`),
// and back. (The panel's light angles; they were about world +Y whatever --up said, so a z-up
// scene's default light read "elevation -13 deg".)
glm::vec3 direction_from_angles(float azimuth, float elevation, glm::vec3 up);
void angles_from_direction(glm::vec3 dir, glm::vec3 up, float& azimuth, float& elevation);

} // namespace pr::view
