// Prism silhouettes, the walk from the eye (docs/prism.md, item 12): when the eye is inside an
// object's shell, no cap in front of it faces it, so one triangle covering the screen at the near
// plane starts every ray's walk at the eye, in the prism that holds it (u_march.z).
#include "common/shared.h"

out vec3 v_world; // the point of the pixel's ray at the far plane's distance along the view
out vec3 v_tex;   // (unused: the walk starts at u_eye_tex)

void main()
{
    vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    // The ray from the projection's own terms, not from inverse(u_view_proj): the near plane
    // lies as close as 10^-6 of the far one (Camera::projection), and the inverse, in floats,
    // put its points off the rays (the walk from the eye drew 1,400 of 9,800 pixels otherwise).
    // u_proj = shift * perspective: x_ndc = P00 x / -z + shift.x, and u_proj[2].xy = -shift.
    vec3 view_dir = vec3((corner + u_proj[2].xy) / vec2(u_proj[0][0], u_proj[1][1]), -1.0);
    float far_plane = u_proj[3][2] / u_proj[2][2]; // reversed: [2][2] = n / (f - n), [3][2] = n f / (f - n)
    v_world = u_eye.xyz + transpose(mat3(u_view)) * view_dir * far_plane;
    v_tex = vec3(0.0);
    gl_Position = vec4(corner, 1.0, 1.0); // clip z = w: the near plane (reversed depth)
}
