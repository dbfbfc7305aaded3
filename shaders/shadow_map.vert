// The reference's shadow maps: its displaced triangles seen from the light (depth only; the
// program has no fragment stage), from one of the directions over its disc with soft shadows.
// u_shadow[map] maps this object's frame to that map's clip space.
// With PR_SHADOW_FROM_EYE, seen from the camera instead: the points the image shows, which the
// map is fitted to (Renderer::ensure_shadow_map).
#include "common/shared.h"

layout(location = PR_ATTR_POSITION) in vec3 a_position; // object space

void main()
{
#ifdef PR_SHADOW_FROM_EYE
    gl_Position = u_view_proj * (u_model * vec4(a_position, 1.0));
#else
    gl_Position = u_shadow[int(u_shadow_bias.w)] * (u_model * vec4(a_position, 1.0));
#endif
}
