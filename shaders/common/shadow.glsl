// Self-shadowing (PR_SHADOWS): from a point on the height field, march towards the light through
// the height field, in texture space (u, v, height), up to the top of the height range. Hard:
// any surface sample above the ray blocks the light. Soft: the light fades with the smallest
// clearance angle seen along the way (height above the surface over distance travelled), the
// usual penumbra estimate; blocked samples give 0. Samples count as height samples (contract).
// `l_tex` is the light direction in texture space (the same frame the view ray is solved in).
//
// The cone marchers (PR_HEIGHT_FROM_CONE) step the light ray through their cone map: from a
// point above the surface the ray may go on as far as it stays inside the empty cone standing on
// the surface below it (march/cone.glsl; a rising ray, so the conservative ratio: a relaxed cone
// promises nothing to it), and a ray steeper than that cone never leaves it, so nothing further
// on can block it. Each step is at least the linear march's, so it never takes more samples.
#ifndef PR_SHADOW_SOFTNESS
#define PR_SHADOW_SOFTNESS 6.0 // clearance slope (height/run) of full light is 1/this
#endif

float light_visibility(vec3 tex, vec3 l_tex, UvGrad g)
{
#ifdef PR_SHADOWS
    // Light at or below the base surface's horizon: a light ray that does not rise stays in the
    // height range for ever (or comes from under the surface, through the object's body), so
    // it is blocked. (It used to count as unblocked: bump flanks facing such a light stayed lit,
    // and a sphere's night side showed them, shadows on or off.)
    // (Against the light's run: l_tex's length goes as one over the object's scale.)
    if (l_tex.z <= 1e-6 * length(l_tex.xy)) return 0.0;
#ifdef PR_HEIGHT_FROM_CONE
    // The cone marchers' refinement may end a little under the surface (a sample under it where
    // the secant meets it within relief's precision), which on a steep wall of boxes is far under
    // the height at that uv: straight up from there the wall itself blocked a light overhead
    // (0.4 % of the pixels of builtin:boxes, on walls facing the eye). The march starts on the
    // surface at that uv.
    tex.z = max(tex.z, cone_at(tex.xy).x);
#endif
    float t_end = (1.0 - tex.z) / l_tex.z;
    if (t_end <= 0.0) return 1.0;
    // --steps per full height range, and at least one sample per two texels along the way (as the
    // prism's march), bounded as the prism's march is: in full over four lengths of the map (by
    // 2 * --steps + 64 alone, a light low over a plane with a 2048-texel map came through a
    // wall's shadow in stripes).
    vec2 size = vec2(textureSize(s_height, 0));
    vec2 texels = t_end * l_tex.xy * size;
    int steps = clamp(int(ceil(float(u_march.x) * (1.0 - tex.z) + 0.5 * length(texels))), 1,
                      max(2 * max(u_march.x, 1) + 64, int(2.0 * max(size.x, size.y))));
    float dt = t_end / float(steps);
    const float bias = 2e-3;
    float visibility = 1.0;
    float run = length(l_tex.xy); // UV units per unit t
#ifdef PR_HEIGHT_FROM_CONE
    float t = dt;
    for (int i = 1; i <= steps && t < t_end; ++i) {
        vec3 p = tex + t * l_tex;
        vec3 hc = cone_at(p.xy);
        float clearance = p.z + bias - hc.x;
#else
    for (int i = 1; i <= steps; ++i) {
        float t = float(i) * dt;
        vec3 p = tex + t * l_tex;
        float clearance = p.z + bias - height_at(p.xy, g);
#endif
#if PR_SHADOWS == PR_SHADOWS_HARD
        if (clearance < 0.0) return 0.0;
#else
        visibility = min(visibility, clamp(PR_SHADOW_SOFTNESS * clearance / (t * run + 1e-6), 0.0, 1.0));
        if (visibility <= 0.0) return 0.0;
#endif
#ifdef PR_HEIGHT_FROM_CONE
        float denom = run - hc.z * l_tex.z;
        if (denom <= 0.0) break; // steeper than the cone: it stays inside
        t += max(hc.z * (p.z - hc.x) / denom, dt);
#endif
    }
    return visibility;
#else
    return 1.0;
#endif
}

// The light direction in the texture space of the frame (t, b, n * depth).
vec3 light_in_texture_space(vec3 t_axis, vec3 b_axis, vec3 n, float depth, vec3 light_dir)
{
    mat3 frame = mat3(t_axis, b_axis, n * depth);
    float scale = frame_scale(frame); // (the solution does not change: height.glsl)
    frame *= scale;
    if (!(abs(determinant(frame)) > 1e-30)) return vec3(0.0, 0.0, 1.0);
    return inverse(frame) * (scale * light_dir);
}
