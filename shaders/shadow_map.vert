// The reference's shadow map: its displaced triangles seen from the light (depth only; the
// program has no fragment stage). u_shadow maps this object's frame to the map's clip space.
#include "common/shared.h"

layout(location = PR_ATTR_POSITION) in vec3 a_position; // object space

void main()
{
    gl_Position = u_shadow * (u_model * vec4(a_position, 1.0));
}
