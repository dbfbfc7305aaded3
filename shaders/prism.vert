// Prism silhouettes, stage 1: world position and normal per vertex for the geometry shader.
#include "common/shared.h"
#include "prism/shell.glsl"

layout(location = PR_ATTR_POSITION) in vec3 a_position;
layout(location = PR_ATTR_NORMAL) in vec3 a_normal;
layout(location = PR_ATTR_UV) in vec2 a_uv;
layout(location = PR_ATTR_TANGENT) in vec4 a_tangent;
layout(location = PR_ATTR_BITANGENT) in vec3 a_bitangent;
layout(location = PR_ATTR_WELD_ID) in uint a_weld_id;

out vec3 g_world;
out vec3 g_normal;
out vec2 g_uv;
flat out uint g_weld;
out vec3 g_tangent;   // dP/du, world (per-vertex exit variant)
out vec3 g_bitangent; // dP/dv, world

void main()
{
    shell_vertex(a_position, a_normal, g_world, g_normal);
    g_uv = a_uv;
    g_weld = a_weld_id;
    g_tangent = mat3(u_model) * a_tangent.xyz;
    g_bitangent = mat3(u_model) * a_bitangent;
    gl_Position = vec4(g_world, 1.0);
}
