// Relief mapping's binary search (Policarpo, Oliveira & Comba 2005) after a linear search:
// halves the bracket `steps` times, so the hit is within (t_below - t_above) / 2^steps of the
// first crossing inside the bracket. One height sample per step.
#include "march/linear.glsl"

// Halves the bracket `steps` times (one height sample each), keeping the ray's height above the
// surface at both ends (d_above > 0 at t_above, d_below >= 0 below it at t_below).
Bracket halve_bracket(MarchRay r, Bracket b, int steps, UvGrad g)
{
    for (int i = 0; i < steps; ++i) {
        float mid = 0.5 * (b.t_above + b.t_below);
        vec3 p = march_point(r, mid);
        float d = p.z - height_at(p.xy, g);
        if (d <= 0.0) {
            b.t_below = mid;
            b.d_below = -d;
        } else {
            b.t_above = mid;
            b.d_above = d;
        }
    }
    return b;
}

// Relief's refinement: the midpoint of the halved bracket.
float refine_binary(MarchRay r, Bracket b, int steps, UvGrad g)
{
    Bracket h = halve_bracket(r, b, steps, g);
    return 0.5 * (h.t_above + h.t_below);
}
