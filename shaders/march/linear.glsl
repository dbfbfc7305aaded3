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

struct MarchRay {
    vec3 origin;
    vec3 dir;
    float t_end;
    int steps;
};

struct Bracket {
    bool hit;
    float t_above;  // last parameter with the ray above the surface
    float t_below;  // first parameter with the ray at or below it
    float d_above;  // ray height minus surface height at t_above (> 0)
    float d_below;  // surface height minus ray height at t_below (>= 0)
};

// The same from a given height h0 at the origin (the prism walk's segments start where the last
// one ended, whose last sample it passes on), returning the last height sampled in `h_end`.
Bracket march_linear_from(MarchRay r, UvGrad g, float h0, out float h_end)
{
    Bracket b = Bracket(false, 0.0, 0.0, 0.0, 0.0);
    float dt = r.t_end / float(max(r.steps, 1));
    float t = 0.0;
    vec3 p = r.origin;
    h_end = h0;
    float d = p.z - h0;
    if (d <= PR_HIT_EPSILON) return Bracket(true, 0.0, 0.0, 0.0, max(-d, 0.0));
    for (int i = 1; i <= r.steps; ++i) {
        float t_next = min(float(i) * dt, r.t_end);
        p = r.origin + t_next * r.dir;
        h_end = height_at(p.xy, g);
        float d_next = p.z - h_end;
        if (d_next <= PR_HIT_EPSILON) return Bracket(true, t, t_next, d, max(-d_next, 0.0));
        t = t_next;
        d = d_next;
    }
    b.t_above = t;
    b.d_above = d;
    return b;
}

Bracket march_linear(MarchRay r, UvGrad g)
{
    float h_end;
    return march_linear_from(r, g, height_at(r.origin.xy, g), h_end);
}

// Parallax occlusion mapping (Tatarchuk 2006): intersect the straight line between the two
// bracketing samples; exact where the height field is linear between them.
float interpolate_bracket(Bracket b)
{
    float w = b.d_above / max(b.d_above + b.d_below, 1e-12);
    return mix(b.t_above, b.t_below, w);
}
