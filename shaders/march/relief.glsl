// Relief mapping's binary search (Policarpo, Oliveira & Comba 2005) after a linear search:
// halves the bracket `steps` times, so the hit is within (t_below - t_above) / 2^steps of the
// first crossing inside the bracket. One height sample per step.
#include "march/linear.glsl"

float refine_binary(MarchRay r, Bracket b, int steps, UvGrad g)
{
    float lo = b.t_above;
    float hi = b.t_below;
    for (int i = 0; i < steps; ++i) {
        float mid = 0.5 * (lo + hi);
        vec3 p = r.origin + mid * r.dir;
        if (p.z <= height_at(p.xy, g))
            hi = mid;
        else
            lo = mid;
    }
    return 0.5 * (lo + hi);
}
