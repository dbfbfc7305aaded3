// Wireframe overlays, stage 3: one colour. The renderer masks alpha writes while drawing
// overlays, so alpha stays the technique's coverage (contract for rendered PNGs).
layout(location = 0) uniform vec4 u_wire_color;

layout(location = 0) out vec4 o_color;

void main()
{
    o_color = u_wire_color;
}
