// Wireframe overlays (viewer, docs figures), stage 1: world position and shell normal per vertex,
// computed by the same shell_vertex() as prism.vert, so the overlay's shell is the prism's.
#include "common/shared.h"
#include "prism/shell.glsl"

layout(location = PR_ATTR_POSITION) in vec3 a_position;
layout(location = PR_ATTR_NORMAL) in vec3 a_normal;
layout(location = PR_ATTR_WELD_ID) in uint a_weld_id;

out vec3 g_world;
out vec3 g_normal;
flat out uint g_weld;

void main()
{
    shell_vertex(a_position, a_normal, g_world, g_normal);
    g_weld = a_weld_id;
    gl_Position = vec4(g_world, 1.0);
}
