// The viewer's compositor (src/view/compositor.cpp): the view target over a background, the
// split divider, and the reference's silhouette difference tinted (cyan missed, magenta extra).
layout(binding = 0) uniform sampler2D s_view;
layout(binding = 1) uniform sampler2D s_reference;
layout(location = 0) uniform vec4 u_params; // x: divider (px, < 0 none), y: tint, z: height, w: line width
layout(location = 0) out vec4 o_color;
void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy);
    vec4 c = texelFetch(s_view, p, 0);
    vec3 background = mix(vec3(0.13, 0.14, 0.16), vec3(0.32, 0.34, 0.38), gl_FragCoord.y / u_params.z);
    bool covered = c.a >= 0.5;
    // Overlay lines outside the coverage keep alpha 0 but have a colour (the clear colour is 0).
    bool line = !covered && max(c.r, max(c.g, c.b)) > 0.0;
    vec3 color = covered || line ? c.rgb : background;
    if (u_params.y > 0.0) {
        bool ref = texelFetch(s_reference, p, 0).a >= 0.5;
        if (ref && !covered) color = mix(color, vec3(0.0, 1.0, 1.0), 0.65);
        else if (!ref && covered) color = mix(color, vec3(1.0, 0.0, 1.0), 0.65);
    }
    if (u_params.x >= 0.0 && abs(gl_FragCoord.x - u_params.x) < 0.5 * u_params.w + 0.5) color = vec3(1.0);
    o_color = vec4(color, 1.0);
}
