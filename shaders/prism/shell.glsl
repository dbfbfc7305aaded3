// The prism shell of one base triangle (contract: the displaced surface lies inside the
// straight-edged prism P_i + t * depth * N_i, t in [-midlevel, 1 - midlevel]).
// Shared by prism.vert/.geom/.frag so every stage builds bit-identical corners.

// World-space position and unit normal of a mesh vertex.
void shell_vertex(vec3 position, vec3 normal, out vec3 world, out vec3 n)
{
    world = (u_model * vec4(position, 1.0)).xyz;
    n = normalize(mat3(u_normal_matrix) * normal);
}

// Corner of the shell at height h (0 = bottom cap, 1 = top cap).
vec3 shell_corner(vec3 world, vec3 n, float h)
{
    return world + u_displace.x * (h - u_displace.y) * n;
}

// The side quad of edge (a, b) is split along the diagonal from the bottom of the vertex with
// the smaller welded id to the top of the other, so the two prisms sharing the edge build the
// same two triangles (ids split by UV seams would disagree; welded ids cannot).
bool diagonal_from_a(uint weld_a, uint weld_b)
{
    return weld_a < weld_b;
}
