// Cone stepping (Dummer 2006, "Cone Step Mapping") and relaxed cone stepping (Policarpo &
// Oliveira, GPU Gems 3 ch. 18), one loop for both: the cone texture bound to PR_TEX_CONE holds
// R = height and G = sqrt(c), c = horizontal distance in UV units over height rise (contract
// "Cone maps"). From a point above the surface the ray may advance as far as it stays inside the
// cone standing on the surface below it:
//     dt = c * (z - h) / (|dir.xy| - c * dir.z)
// (a rising ray whose slope is steeper than the cone's never leaves it: it goes to the end).
// With a conservative map the cone is empty, so the ray never passes the surface; with a relaxed
// map it crosses the surface at most once inside the cone, so the first sample below the
// surface brackets the first crossing. Either way refine_cone() finishes (false position,
// safeguarded by bisection, to relief's precision).
//
// Every step is at least the linear step t_end / steps (contract: equal --steps means equal
// step length), so cone stepping never does more work than the linear search and converges
// where cones shrink to nothing near the surface; except for up to PR_CONE_LANDINGS "landings"
// per march: where the cone allows less than a linear step, the ray is closing on the surface,
// and the secant through the last two samples predicts where it gets there, the next sample is
// taken just past that point instead of a linear step on (shorter, so nothing is stepped over
// that the linear step would not). On a surface that is straight there the sample is just under
// it, and the secant between it and the sample before is the hit: no refinement at all. A map's ratio holds at its texel centre; the
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


// The march's precision, as relief's: a linear step over 2^(--refine + 1) (half its last bracket).
float cone_tolerance(MarchRay r)
{
    return r.t_end / float(max(r.steps, 1)) / exp2(float(u_march.y + 1));
}

#ifndef PR_CONE_LANDINGS
#define PR_CONE_LANDINGS 2
#endif

// From a given sample hc0 = cone_at(origin), or with `pending` from one taken as the loop's first;
// `below`, `decide`: as march_linear_from() (march/linear.glsl), whose prism-walk form this is.
// Under the surface the cones (which describe the heights from above) do not hold: the march
// takes linear steps there. Returns the last sample taken in `hc_end`. A landing that finds the
// hit returns it as a bracket of width 0.
Bracket march_cone_from(MarchRay r, vec3 hc0, bool pending, bool decide, inout bool below, out vec3 hc_end)
{
    float min_dt = r.t_end / float(max(r.steps, 1));
    float tol = cone_tolerance(r);
    float run = length(r.dir.xy); // UV units per unit t
    vec3 hc = hc0;
    hc_end = hc0;
    // Rising rays use the conservative ratio (z), descending ones the map's (y).
    bool rising = r.dir.z >= 0.0;
    float side = below ? -1.0 : 1.0;
    float d = pending ? 0.0 : side * (r.origin.z - hc.x);
    if (!pending && d <= PR_HIT_EPSILON) return Bracket(true, 0.0, 0.0, 0.0, max(-d, 0.0));
    float t = 0.0;
    float t_prev = -1.0, d_prev = 0.0; // the sample before (t, d); t_prev < 0: none
    int landings = 0;
    // Each iteration but the pending one and the landings advances at least min_dt, so
    // steps + PR_CONE_LANDINGS + 1 of them reach t_end; one more for rounding.
    for (int i = 0; i <= r.steps + PR_CONE_LANDINGS + 1; ++i) {
        float c = below ? 0.0 : (rising ? hc.z : hc.y);
        float denom = run - c * r.dir.z;
        float dt = denom > 1e-12 ? c * d / denom : (c > 0.0 ? r.t_end : 0.0); // c = 0: no cone
        float step = max(dt, min_dt);
        bool landing = false;
        if (dt < min_dt && t_prev >= 0.0 && landings < PR_CONE_LANDINGS) {
            float closing = (d_prev - d) / (t - t_prev); // height gained on the surface per unit t
            if (closing > 0.0 && d < closing * min_dt) {
                step = max(min(d / closing + tol, min_dt), dt);
                landing = true;
                ++landings;
            }
        }
        float t_next = pending ? 0.0 : min(t + step, r.t_end);
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
        if (landing && d_next < 0.0) {
            // Under the surface just past the predicted point: where the secant between the
            // two samples meets the surface within the precision of it, that is the hit.
            float t_hit = mix(t, t_next, d / (d - d_next));
            if (t_next - t_hit <= 2.0 * tol) return Bracket(true, t_hit, t_hit, 0.0, 0.0);
        }
        if (d_next <= PR_HIT_EPSILON) return Bracket(true, t, t_next, d, max(-d_next, 0.0));
        t_prev = pending ? -1.0 : t;
        d_prev = d;
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

// The hit inside a cone march's bracket, to relief's precision (cone_tolerance(); a bracket of
// width 0 is a hit already). False position with the Illinois modification (the end kept twice
// running has its distance halved, so neither end sticks), and a bisection after any step that
// left more than half the bracket, so the bracket at least halves every two samples; at most as
// many samples as relief's halvings of the same bracket. A sample stops the search when the
// distance it leaves to the surface, over the slope of the secants through it, is within the
// precision: on a surface that is straight there, the first sample does. The slope is the
// smaller of the bracket's and of the secant to the bracket's end on the sample's side, so a
// sample just above a floor with a wall ahead (the bracket steep, the floor flat) does not stop.
float refine_cone(MarchRay r, Bracket b, UvGrad g)
{
    float tol = cone_tolerance(r);
    float ta = b.t_above, tb = b.t_below;
    float fa = b.d_above, fb = -b.d_below; // the ray's height over the surface: > 0 at ta, <= 0 at tb
    float wa = fa, wb = fb;                // the same, as false position weighs them
    int moved = 0;                         // +1: ta moved last, -1: tb
    bool bisect = false;
    float ratio = (tb - ta) * float(max(r.steps, 1)) / r.t_end;
    int n = u_march.y + (ratio > 1.0 ? int(ceil(log2(ratio))) : 0);
    for (int i = 0; i < n && tb - ta > 2.0 * tol; ++i) {
        float width = tb - ta;
        float slope = (fa - fb) / width;
        float t = bisect ? 0.5 * (ta + tb) : mix(ta, tb, wa / max(wa - wb, 1e-30));
        vec3 p = r.origin + t * r.dir;
        float f = p.z - height_at(p.xy, g);
        if (f > 0.0) {
            // Above: trusted only where the secant from the bracket's upper end is about as
            // steep as the bracket (no kink between, like a floor before a wall).
            bool straight = (fa - f) >= 0.5 * slope * (t - ta);
            ta = t;
            fa = wa = f;
            if (moved > 0) wb *= 0.5;
            moved = 1;
            if (straight && f <= tol * slope) return min(t + f / slope, tb);
        } else {
            tb = t;
            fb = wb = f;
            if (moved < 0) wa *= 0.5;
            moved = -1;
            // Under: the secant from the upper end meets the surface within the precision.
            float t_hit = mix(ta, tb, fa / max(fa - fb, 1e-30));
            if (tb - t_hit <= tol) return t_hit;
        }
        bisect = tb - ta > 0.5 * width;
    }
    return mix(ta, tb, fa / max(fa - fb, 1e-30));
}
#endif // PR_HEIGHT_FROM_CONE
