// Linear search (steep parallax, McGuire & McGuire 2005): walk the ray in equal steps until it
// is at or below the height field. Texture space is (u, v, height), height in [0,1].
//
// The ray is p(t) = origin + t * dir, t in [0, t_end]; `steps` samples after the first one at
// t = 0, so at most steps + 1 height samples. Error bound: a hit is bracketed to one step; a
// feature thinner than a step along the ray can be missed (the cost of equal step lengths).
// A sample counts as a hit when the ray is at most PR_HIT_EPSILON above the surface. The prism
// sets it > 0 so rays that graze a constant cap (height exactly 0 or 1, where the ray ends
// exactly on the surface) still hit despite rounding.
#ifndef PR_HIT_EPSILON
#define PR_HIT_EPSILON 0.0
#endif

// The path may bend: origin + t * dir + t * (t_end - t) * curve, a parabola (the prism's
// texture-space path, which a straight view ray curves where the prism's normals part:
// prism.frag, path_bend; its middle lies t_end^2 / 4 * curve off the chord). The base-surface
// techniques' rays are straight (curve 0).
struct MarchRay {
    vec3 origin;
    vec3 dir;
    float t_end;
    int steps;
    vec3 curve;
};

// The ray's point at parameter t.
vec3 march_point(MarchRay r, float t)
{
    return r.origin + t * r.dir + (t * (r.t_end - t)) * r.curve;
}

struct Bracket {
    bool hit;
    float t_above;  // last parameter with the ray above the surface
    float t_below;  // first parameter with the ray at or below it
    float d_above;  // ray height minus surface height at t_above (> 0)
    float d_below;  // surface height minus ray height at t_below (>= 0)
};

// The linear step: the segment over `steps` (contract: equal --steps means equal step length).
float linear_step(MarchRay r)
{
    return r.t_end / float(max(r.steps, 1));
}

// The prism walk's form (march/cone.glsl has the same): from the height h0 at the origin (the
// walk's segments start where the last one ended, whose last sample it passes on), or with
// `pending`, from a sample at the origin taken as the loop's first (one sampling site: llvmpipe
// expands each into a long stretch of code, and a second one, outside the loop, cost the walk
// 3-4 % of the rock's frame); returns the last height sampled in `h_end`. `below` (the walk under a
// torn surface, prism.frag): the ray comes out *under* the heights, so every distance to the
// surface counts with its sign turned; with `decide`, the sample at the origin decides it.
Bracket march_linear_from(MarchRay r, UvGrad g, float h0, bool pending, bool decide, inout bool below, out float h_end)
{
    float dt = linear_step(r);
    float t = 0.0;
    float side = below ? -1.0 : 1.0;
    h_end = h0;
    float d = pending ? 0.0 : side * (r.origin.z - h0);
    if (!pending && d <= PR_HIT_EPSILON) return Bracket(true, 0.0, 0.0, 0.0, max(-d, 0.0));
    for (int i = pending ? 0 : 1; i <= r.steps; ++i) {
        float t_next = min(float(i) * dt, r.t_end);
        vec3 p = march_point(r, t_next);
        h_end = height_at(p.xy, g);
#ifdef PR_PRISM_TEARS
        if (decide && i == 0) {
            below = p.z < h_end - PR_HIT_EPSILON;
            side = below ? -1.0 : 1.0;
        }
#endif
        float d_next = side * (p.z - h_end);
        if (d_next <= PR_HIT_EPSILON) return Bracket(true, t, t_next, d, max(-d_next, 0.0));
        t = t_next;
        d = d_next;
    }
    return Bracket(false, t, t, d, 0.0);
}

Bracket march_linear(MarchRay r, UvGrad g)
{
    float h_end;
    bool below = false;
    return march_linear_from(r, g, height_at(r.origin.xy, g), false, false, below, h_end);
}

// Parallax occlusion mapping (Tatarchuk 2006): intersect the straight line between the two
// bracketing samples; exact where the height field is linear between them.
float interpolate_bracket(Bracket b)
{
    float w = b.d_above / max(b.d_above + b.d_below, 1e-12);
    return mix(b.t_above, b.t_below, w);
}
