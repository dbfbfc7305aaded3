// The viewer's compositor (src/view/compositor.cpp): a full-screen triangle. Presentation only:
// everything drawn comes from the Renderer; this shows its image over a background.
void main()
{
    vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
