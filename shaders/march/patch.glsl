// A ray against one bilinear patch of a height map, exactly: the patch between four texel centres,
// h(f) = mix(mix(h00, h10, f.x), mix(h01, h11, f.x), f.y) for f in [0,1]^2, is what a bilinear
// fetch reads there, and along a straight ray its height is a quadratic in t. The max-mip
// marcher's finest level (march/maxmip.glsl) and the base-surface cone marchers' patches
// (march/cone.glsl).

// The ray's height over the patch h = (h00, h10, h01, h11) along z0 + t dz, f0 + t df (patch
// coordinates), as g(t) = c0 + c1 t + c2 t^2: returns (c0, c1, c2).
vec3 patch_gap_poly(vec4 h, vec2 f0, vec2 df, float z0, float dz)
{
    float b = h.y - h.x, c = h.z - h.x, d = h.w - h.y - h.z + h.x;
    return vec3(z0 - (h.x + b * f0.x + c * f0.y + d * f0.x * f0.y),
                dz - (b * df.x + c * df.y + d * (f0.x * df.y + f0.y * df.x)),
                -d * df.x * df.y);
}

// The first t in [0, t_len] where g = (c0, c1, c2) (c0 > 0) falls to 0; -1 when none.
float gap_first_root(vec3 g, float t_len)
{
    float root = -1.0;
    if (abs(g.z) <= 1e-7 * (abs(g.y) + abs(g.x))) {
        if (g.y < 0.0) root = -g.x / g.y;
    } else {
        float disc = g.y * g.y - 4.0 * g.z * g.x;
        if (disc >= 0.0) {
            float q = -0.5 * (g.y + (g.y >= 0.0 ? 1.0 : -1.0) * sqrt(disc));
            float r1 = q / g.z, r2 = q != 0.0 ? g.x / q : -1.0;
            float lo = min(r1, r2), hi = max(r1, r2);
            root = lo >= 0.0 ? lo : hi;
        }
    }
    if (root >= 0.0 && root <= t_len) return root;
    // Rays that end on the surface (a cap at height 0 or 1) hit at the end despite rounding.
    return g.x + (g.y + g.z * t_len) * t_len <= PR_HIT_EPSILON ? t_len : -1.0;
}

// First t in [0, t_len] where z0 + t dz <= the bilinear patch with corner heights
// h = (h00, h10, h01, h11) along f0 + t df (patch coordinates in [0,1]^2); -1 when none.
float patch_hit(vec4 h, vec2 f0, vec2 df, float z0, float dz, float t_len)
{
    vec3 g = patch_gap_poly(h, f0, df, z0, dz);
    return g.x <= PR_HIT_EPSILON ? 0.0 : gap_first_root(g, t_len);
}
