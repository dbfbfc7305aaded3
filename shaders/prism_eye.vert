// Prism silhouettes, the walk from the eye (docs/prism.md, item 12): when the eye is inside an
// object's shell, no cap in front of it faces it, so one triangle covering the screen at the near
// plane starts every ray's walk at the eye, in the prism that holds it (u_march.z).
#include "common/shared.h"

out vec3 v_world; // world position on the near plane
out vec3 v_tex;   // (unused: the walk starts at u_eye_tex)

void main()
{
    vec2 corner = vec2(gl_VertexID == 1 ? 3.0 : -1.0, gl_VertexID == 2 ? 3.0 : -1.0);
    vec4 world = inverse(u_view_proj) * vec4(corner, -1.0, 1.0);
    v_world = world.xyz / world.w;
    v_tex = vec3(0.0);
    gl_Position = vec4(corner, -1.0, 1.0);
}
