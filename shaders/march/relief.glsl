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

// Binary steps as refine_binary, then one secant (the POM interpolation) inside the last bracket
// instead of its midpoint: no extra sample. On a smooth surface the secant's error shrinks with
// the square of the bracket, so fewer halvings reach the same accuracy (cone marchers use it).
float refine_binary_secant(MarchRay r, Bracket b, int steps, UvGrad g)
{
    float lo = b.t_above, hi = b.t_below;
    float d_lo = b.d_above, d_hi = b.d_below; // both >= 0: above at lo, below at hi
    for (int i = 0; i < steps; ++i) {
        float mid = 0.5 * (lo + hi);
        vec3 p = r.origin + mid * r.dir;
        float d = p.z - height_at(p.xy, g);
        if (d <= 0.0) {
            hi = mid;
            d_hi = -d;
        } else {
            lo = mid;
            d_lo = d;
        }
    }
    float sum = d_lo + d_hi;
    return sum > 0.0 ? lo + (hi - lo) * (d_lo / sum) : 0.5 * (lo + hi);
}

