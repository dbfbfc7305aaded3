// Cone stepping (Dummer 2006, "Cone Step Mapping") and relaxed cone stepping (Policarpo &
// Oliveira, GPU Gems 3 ch. 18), one loop for both: the cone texture bound to PR_TEX_CONE holds
// R = height and G = sqrt(c), c = horizontal distance in UV units over height rise (contract
// "Cone maps"). From a point above the surface the ray may advance as far as it stays inside the
// cone standing on the surface below it:
//     dt = c * (z - h) / (|dir.xy| - c * dir.z)
// (a rising ray whose slope is steeper than the cone's never leaves it: it goes to the end).
// With a conservative map the cone is empty, so the ray never passes the surface; with a relaxed
// map it crosses the surface at most once inside the cone, so the first sample below the
// surface brackets the first crossing. Either way a binary search finishes, ending with a secant
// (refine_binary_secant, march/relief.glsl).
//
// Every step is at least the linear step t_end / steps (contract: equal --steps means equal
// step length), so cone stepping never does more work than the linear search and converges
// where cones shrink to nothing near the surface. A map's ratio holds at its texel centre; the
// renderer uploads each ratio narrowed to the smallest of its 3x3 neighbourhood
// (maps::ratios_for_bilinear), so the filtered ratio between texel centres is no wider than the
// narrowest of the four around it (unnarrowed, rays jumped over the corners of boxes).
#include "march/relief.glsl"

#ifdef PR_HEIGHT_FROM_CONE // (common/height.glsl declares s_cone then)

// A relaxed cone only promises that a ray coming down through it crosses the surface at most
// once; a rising ray (dir.z >= 0: inside a prism, entering through a side wall) may pass through a
// bump and out again within one relaxed step. Such rays step with the conservative cone, which the
// renderer stores in the relaxed texture's blue channel (src/render/renderer.cpp).
#if (defined(PR_MARCHER) && PR_MARCHER == PR_MARCH_RELAXED_CONE) || \
    (defined(PR_TECHNIQUE) && PR_TECHNIQUE == PR_TECH_RELAXED_CONE)
#define PR_CONE_IS_RELAXED 1
#else
#define PR_CONE_IS_RELAXED 0
#endif

// One fetch of the cone map at level 0: (height, c, conservative c). Counted as a height sample.
vec3 cone_at(vec2 uv)
{
    ++g_height_samples;
    vec3 rgb = textureLod(s_cone, uv, 0.0).rgb;
#if PR_CONE_IS_RELAXED == 1
    return vec3(rgb.r, rgb.g * rgb.g, rgb.b * rgb.b);
#else
    return vec3(rgb.r, rgb.g * rgb.g, rgb.g * rgb.g);
#endif
}


// From a given sample hc0 = cone_at(origin), or with `pending` from one taken as the loop's first;
// `below`, `decide`: as march_linear_from() (march/linear.glsl), whose prism-walk form this is.
// Under the surface the cones (which describe the heights from above) do not hold: the march
// takes linear steps there. Returns the last sample taken in `hc_end`.
Bracket march_cone_from(MarchRay r, vec3 hc0, bool pending, bool decide, inout bool below, out vec3 hc_end)
{
    float min_dt = r.t_end / float(max(r.steps, 1));
    float run = length(r.dir.xy); // UV units per unit t
    vec3 hc = hc0;
    hc_end = hc0;
    // Rising rays use the conservative ratio (z), descending ones the map's (y).
    bool rising = r.dir.z >= 0.0;
    float side = below ? -1.0 : 1.0;
    float d = pending ? 0.0 : side * (r.origin.z - hc.x);
    if (!pending && d <= PR_HIT_EPSILON) return Bracket(true, 0.0, 0.0, 0.0, max(-d, 0.0));
    float t = 0.0;
    // Each iteration advances at least min_dt, so at most `steps` of them, after the pending one.
    for (int i = 0; i <= r.steps; ++i) {
        float c = below ? 0.0 : (rising ? hc.z : hc.y);
        float denom = run - c * r.dir.z;
        float dt = denom > 1e-12 ? c * d / denom : (c > 0.0 ? r.t_end : 0.0); // c = 0: no cone
        float t_next = pending ? 0.0 : min(t + max(dt, min_dt), r.t_end);
        vec3 p = r.origin + t_next * r.dir;
        vec3 hc_next = cone_at(p.xy);
        hc_end = hc_next;
#ifdef PR_PRISM_TEARS
        if (decide && pending) {
            below = p.z < hc_next.x;
            side = below ? -1.0 : 1.0;
        }
#endif
        float d_next = side * (p.z - hc_next.x);
        if (d_next <= PR_HIT_EPSILON) return Bracket(true, t, t_next, d, max(-d_next, 0.0));
        pending = false;
        t = t_next;
        d = d_next;
        hc = hc_next;
        if (t >= r.t_end) break;
    }
    return Bracket(false, t, t, d, 0.0);
}

Bracket march_cone(MarchRay r)
{
    vec3 hc_end;
    bool below = false;
    return march_cone_from(r, cone_at(r.origin.xy), false, false, below, hc_end);
}

// Binary steps that leave the bracket of a cone march as narrow as relief's (--refine halvings of
// one linear step): a relaxed cone's last step may be several linear steps long.
// The cone marchers finish with a secant (refine_binary_secant), which replaces the last
// PR_CONE_SECANT_SAVES halvings.
#ifndef PR_CONE_SECANT_SAVES
#define PR_CONE_SECANT_SAVES 4
#endif
int cone_refine_steps(MarchRay r, Bracket b, int refine)
{
    float min_dt = r.t_end / float(max(r.steps, 1));
    float ratio = (b.t_below - b.t_above) / min_dt;
    int halvings = refine + (ratio > 1.0 ? int(ceil(log2(ratio))) : 0);
    return max(halvings - PR_CONE_SECANT_SAVES, min(refine, 1));
}
#endif // PR_HEIGHT_FROM_CONE
