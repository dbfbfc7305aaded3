// Base-surface techniques: transform to world space; the fragment shader does the rest.
#include "common/shared.h"

layout(location = PR_ATTR_POSITION) in vec3 a_position;   // object space
layout(location = PR_ATTR_NORMAL) in vec3 a_normal;       // welded smooth normal, object space
layout(location = PR_ATTR_UV) in vec2 a_uv;
layout(location = PR_ATTR_TANGENT) in vec4 a_tangent;     // dP/du (object units per UV), handedness
layout(location = PR_ATTR_BITANGENT) in vec3 a_bitangent; // dP/dv

out vec3 v_world_pos;
out vec3 v_normal;
out vec2 v_uv;
out vec3 v_tangent;
out vec3 v_bitangent;

void main()
{
    vec4 world = u_model * vec4(a_position, 1.0);
    v_world_pos = world.xyz;
    v_normal = normalize(mat3(u_normal_matrix) * a_normal);
    v_uv = a_uv;
    v_tangent = mat3(u_model) * a_tangent.xyz;
    v_bitangent = mat3(u_model) * a_bitangent;
    gl_Position = u_view_proj * world;
}
