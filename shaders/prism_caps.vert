// Prism silhouettes, stage 1 of the walk, without a geometry shader: the walk rasterizes only the
// shell's outside (docs/prism.md), and most of it is caps, whose corners belong to their vertex
// (the tight top is shared by the triangles around it). So each vertex goes to its top here
// (PR_PRISM_BOTTOMS: to its bottom, for open meshes, which are seen from below too), and the
// rasterizer culls the caps that face away. (llvmpipe's geometry shader costs more than the rest
// of drawing the shell.) With PR_PRISM_LISTED it feeds prism.geom one point per listed prism.
#include "common/shared.h"
#include "prism/shell.glsl"

out vec3 v_world; // world position on the cap
out vec3 v_tex;   // (u, v, height) there
#ifdef PR_PRISM_LISTED
flat out int g_list_index; // the point's place in the list (the draw's first point counts from its offset)
#endif

void main()
{
#ifdef PR_PRISM_LISTED
    g_list_index = gl_VertexID;
    v_world = vec3(0.0);
    v_tex = vec3(0.0);
    gl_Position = vec4(0.0, 0.0, 0.0, 1.0);
#else
    ShellVertex c = shell_corners(uint(gl_VertexID));
#ifdef PR_PRISM_BOTTOMS
    float h = 0.0;
    v_world = c.bottom_u.xyz;
#else
    float h = shell_top_height(c.top_weld.x);
    v_world = shell_top_corner(c.bottom_u.xyz, c.n_v.xyz, h);
#endif
    v_tex = vec3(c.bottom_u.w, c.n_v.w, h);
    gl_Position = u_view_proj * vec4(v_world, 1.0);
#endif
}
