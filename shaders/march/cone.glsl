// Cone stepping (Dummer 2006, "Cone Step Mapping") and relaxed cone stepping (Policarpo &
// Oliveira, GPU Gems 3 ch. 18), one loop for both: the cone texture bound to PR_TEX_CONE holds
// R = height and G = sqrt(c), c = horizontal distance in UV units over height rise (contract
// "Cone maps"). From a point above the surface the ray may advance as far as it stays inside the
// cone standing on the surface below it:
//     dt = c * (z - h) / (|dir.xy| - c * dir.z)
// (a rising ray whose slope is steeper than the cone's never leaves it: it goes to the end).
// With a conservative map the cone is empty, so the ray never passes the surface; with a relaxed
// map it crosses the surface at most once inside the cone, so the first sample below the
// surface brackets the first crossing. Either way refine_cone() finishes (the prism's marchers;
// the base-surface techniques march each sample's bilinear patch exactly instead, below).
//
// Every step is at least the linear step t_end / steps (contract: equal --steps means equal
// step length), so cone stepping never does more work than the linear search and converges
// where cones shrink to nothing near the surface. A map's ratio holds at its texel centre; the
// renderer uploads each ratio narrowed to the smallest of its 3x3 neighbourhood
// (maps::ratios_for_bilinear), so the filtered ratio between texel centres is no wider than the
// narrowest of the four around it (unnarrowed, rays jumped over the corners of boxes).
#include "march/relief.glsl"
#include "march/patch.glsl"

#ifdef PR_HEIGHT_FROM_CONE // (common/height.glsl declares s_cone then)

// A relaxed cone only promises that a ray coming down through it crosses the surface at most
// once; a rising ray (dir.z >= 0: inside a prism, entering through a side wall) may pass through a
// bump and out again within one relaxed step. Such rays step with the conservative cone: the
// renderer binds the relaxed map and the cone map as the layers of one texture (common/height.glsl,
// PR_CONE_IS_RELAXED).

// One fetch of the cone map at level 0, counted as a height sample: (height, c, conservative c)
// for a ray that descends (`rising` false) or rises. A relaxed march reads its own map for a
// descending ray, (height, relaxed c, 0: no conservative c), and the cone map for a rising one,
// (height, conservative c, conservative c), which holds for either: the ray's direction picks the
// layer, one fetch. (With both ratios in one RGB16 texture the prism's relaxed march was 7-9 %
// slower on the blob than its cone march on RG16, for the third channel alone. With the two maps
// in two textures and a branch between their fetches, 7 % slower than with one fetch: llvmpipe
// takes both arms of every branch, and the heights and slopes read from a texture of their own
// missed the CPU's caches that the march had filled.)
vec3 cone_at(vec2 uv, bool rising)
{
    ++g_height_samples;
#if PR_CONE_IS_RELAXED == 1
    vec2 rg = textureLod(s_cone, vec3(uv, rising ? 1.0 : 0.0), 0.0).rg;
    float c = rg.g * rg.g;
    return vec3(rg.r, c, rising ? c : 0.0);
#else
    vec2 rg = textureLod(s_cone, uv, 0.0).rg;
    return vec3(rg.r, rg.g * rg.g, rg.g * rg.g);
#endif
}

// The march's precision, as relief's: a linear step over 2^(--refine + 1) (half its last bracket).
float cone_tolerance(MarchRay r)
{
    return linear_step(r) / exp2(float(u_march.y + 1));
}

// From a given sample hc0 = cone_at(origin), or with `pending` from one taken as the loop's first;
// `below`, `decide`: as march_linear_from() (march/linear.glsl), whose prism-walk form this is.
// Under the surface the cones (which describe the heights from above) do not hold: the march
// takes linear steps there. Returns the last sample taken in `hc_end`.
Bracket march_cone_from(MarchRay r, vec3 hc0, bool pending, bool decide, inout bool below, out vec3 hc_end)
{
    float min_dt = linear_step(r);
    vec3 hc = hc0;
    hc_end = hc0;
    float run = length(r.dir.xy); // UV units per unit t
    // Rising rays use the conservative ratio (z), descending ones the map's (y); a bent path
    // (march/linear.glsl) that rises anywhere counts as rising (its direction at either end).
    // Its steps are judged along the chord: the bend is a small part of a segment.
    bool rising = max(r.dir.z + r.t_end * r.curve.z, r.dir.z - r.t_end * r.curve.z) >= 0.0;
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
        vec3 p = march_point(r, t_next);
        vec3 hc_next = cone_at(p.xy, rising);
        hc_end = hc_next;
#ifdef PR_PRISM_TEARS
        if (decide && pending) {
            below = p.z < hc_next.x - PR_HIT_EPSILON;
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

// The hit inside a cone march's bracket (a cone step may leave one several linear steps long).
// False position with the Illinois modification (an end kept twice running has its distance
// halved, so neither end sticks), and a bisection after any step that kept more than half the
// bracket. It stops at relief's precision (cone_tolerance()): a sample under the surface where
// the secant from the upper end meets the surface within it of the sample; a sample above where
// the bracket's secant slope says the same. Not where the samples show a kink: a sample above
// that gained less than half that slope on the upper end (a floor before a wall, where the steep
// secant would stop it short of the wall), or one under the surface that lies less than half that
// slope over the lower end (a wall's face and then its top, where the secant from the floor would
// stop it on the top: the cone marchers lit a thin wall's top edge as its top, where the face
// was, 7 dB from the relief marcher in a view low over it). On a straight stretch of surface the
// first sample stops it. At most as many samples as the halvings it replaced (--refine less 4,
// plus one per doubling of the bracket beyond a linear step; at least one), then the secant of
// what is left. Once a kink shows, false position gains little on what is left (a step in the
// surface, which the secant cuts anywhere): it bisects, and takes two more samples (a mesa's or
// slots' edges seen low over the plane were 15 to 44 dB further from the reference than the
// relief marcher's before; docs/cone-maps.md).
float refine_cone(MarchRay r, Bracket b, UvGrad g)
{
    float tol = cone_tolerance(r);
    float ta = b.t_above, tb = b.t_below;
    float fa = b.d_above, fb = -b.d_below; // the ray's height over the surface: > 0 at ta, <= 0 at tb
    float wa = fa, wb = fb;                // the same as false position weighs them
    float moved = 0.0;                     // +1: ta moved last, -1: tb
    bool bisect = false;
    float ratio = (tb - ta) / linear_step(r); // in linear steps
    int n = max(u_march.y + (ratio > 1.0 ? int(ceil(log2(ratio))) : 0) - 4, min(u_march.y, 1));
    bool done = false;
    bool kinked = false;
    float hit = 0.0;
    for (int i = 0; i < n + (kinked ? 2 : 0); ++i) {
        float width = tb - ta;
        if (width <= 2.0 * tol) break;
        float slope = (fa - fb) / width;
        float t = bisect ? 0.5 * (ta + tb) : mix(ta, tb, wa / max(wa - wb, 1e-30));
        vec3 p = march_point(r, t);
        float f = p.z - height_at(p.xy, g);
        bool above = f > 0.0;
        // Straight: a sample above lost at least half the bracket's slope since the upper end, one
        // under it kept half of it to the lower end (else a kink lies between: a floor before a
        // wall, a wall's top edge).
        bool straight = above ? fa - f >= 0.5 * slope * (t - ta) : f - fb >= 0.5 * slope * (tb - t);
        kinked = kinked || !straight;
        float t_under = mix(ta, t, fa / max(fa - f, 1e-30));
        done = straight && (above ? f <= tol * slope : t - t_under <= tol);
        hit = above ? min(t + f / slope, tb) : t_under;
        wb *= above && moved > 0.0 ? 0.5 : 1.0;
        wa *= !above && moved < 0.0 ? 0.5 : 1.0;
        ta = above ? t : ta;
        fa = above ? f : fa;
        wa = above ? f : wa;
        tb = above ? tb : t;
        fb = above ? fb : f;
        wb = above ? wb : f;
        moved = above ? 1.0 : -1.0;
        if (done) break;
        bisect = kinked || tb - ta > 0.5 * width;
    }
    return done ? hit : mix(ta, tb, fa / max(fa - fb, 1e-30));
}

#ifdef PR_CONE_PATCHES
// The base-surface techniques (`cone`, `relaxed-cone`) read the map from another texture
// (src/render/renderer.cpp, make_patch_texture): each R32F texel holds a height and the map's
// ratio, and one textureGather reads the four around a bilinear patch, so a sample gives the
// patch it lies in, whole: its heights, and as its ratio the narrowest of its corners (the bound
// ratios_for_bilinear keeps the filtered ratio under). The march meets the ray's stretch over
// that patch exactly (march/patch.glsl): wherever the first crossing lies in the patch of a
// sample, that sample finds it, with no refinement after it. A cone step that stops just above a
// brick's flat top ends the march there (the march before took a sample under the top and
// refined: 0.43 of relief's samples on builtin:bricks, now 0.31; docs/cone-maps.md).
layout(binding = PR_TEX_PATCH) uniform sampler2D s_patch;

// The ray in patch coordinates (patch (i, j) spans [i, i + 1) x [j, j + 1)), from the origin less
// its whole repeats of the map, so UVs far from 0 keep their precision.
struct PatchRay {
    vec2 x0;
    vec2 dx;
    vec2 inv;   // 1 / dx; huge where dx is 0
    vec2 enter; // the side of a patch where the ray enters it: 0 (its low side) or 1 (as inv's sign)
    vec2 texel; // 1 / the texture's size
    float z0;
    float dz;
};

struct Patch {
    vec4 h;   // heights (h00, h10, h01, h11)
    vec2 lo;  // the patch's corner in the ray's coordinates
    float c;  // the cone's ratio (a relaxed map's own: base-surface rays descend)
};

PatchRay patch_ray(MarchRay r)
{
    vec2 size = vec2(textureSize(s_patch, 0));
    vec2 dx = r.dir.xy * size;
    vec2 inv = vec2(abs(dx.x) > 1e-30 ? 1.0 / dx.x : 1e30, abs(dx.y) > 1e-30 ? 1.0 / dx.y : 1e30);
    return PatchRay((r.origin.xy - floor(r.origin.xy)) * size - 0.5, dx, inv, vec2(lessThan(inv, vec2(0.0))),
                    1.0 / size, r.origin.z, r.dir.z);
}

// One fetch: the patch the ray's point at t lies in. Counted as a height sample.
Patch patch_at(PatchRay pr, float t)
{
    ++g_height_samples;
    vec2 lo = floor(pr.x0 + t * pr.dx);
    // The 2x2 texels around the patch's middle corner, wrapped by the sampler; x = (i0, j1),
    // y = (i1, j1), z = (i1, j0), w = (i0, j0) (renderer.cpp, make_patch_texture).
    vec4 v = textureGather(s_patch, (lo + 1.0) * pr.texel, 0).wzxy * 16777216.0;
    vec4 k = floor(v * (1.0 / 256.0));
    vec4 bytes = v - 256.0 * k;
    float root = min(min(bytes.x, bytes.y), min(bytes.z, bytes.w)) * (1.0 / 255.0);
    return Patch(k * (1.0 / 65535.0), lo, root * root);
}

// The parameters where the ray enters and leaves the patch at lo.
vec2 patch_span(PatchRay pr, vec2 lo)
{
    vec2 a = (lo + pr.enter - pr.x0) * pr.inv, b = (lo + 1.0 - pr.enter - pr.x0) * pr.inv;
    return vec2(max(a.x, a.y), min(b.x, b.y));
}

// The march: true and the hit's t, or false (the ray ends above the surface). One loop, with one
// fetch and one exact test per iteration (llvmpipe runs a loop's whole body for a group of
// fragments as long as any of them is in it: a second loop for the search after the bracket,
// inside this one, cost more than the march). Each iteration takes the ray's stretch over the
// patch last fetched (within the bracket): if the ray meets it there, that is the hit; if the ray
// enters it under the surface, the crossing lies before, and the bracket ends there; else the ray
// is above the surface up to the stretch's end. Until a bracket is known the next sample is a
// cone step from there (at least the linear step from the last sample, and past the patch);
// after, each sample searches the bracket (the first by false position, then bisection), and
// settles the crossing in its patch or takes its patch off the bracket.
bool march_cone_patches(MarchRay r, out float t_hit)
{
    PatchRay pr = patch_ray(r);
    float min_dt = linear_step(r);
    float run = length(r.dir.xy);
    // Past a patch's border by a ten-thousandth of a patch, and a few float steps of the ray's
    // largest coordinate (as march/maxmip.glsl).
    float reach = max(max(abs(pr.x0.x), abs(pr.x0.y)),
                      max(abs(pr.x0.x + r.t_end * pr.dx.x), abs(pr.x0.y + r.t_end * pr.dx.y)));
    float per_patch = 1.0 / max(max(abs(pr.dx.x), abs(pr.dx.y)), 1e-6);
    float nudge = max(1e-4 * min(per_patch, r.t_end), 4.0 * reach / 8388608.0 * per_patch);
    float ta = 0.0, fa = 0.0;     // the ray is above the surface up to ta, fa over it there
    float tb = r.t_end, fb = 0.0; // searching: at or under it at tb
    float t_s = 0.0;              // the last sample
    bool searching = false;
    vec2 searched_in = vec2(-1.0); // the bracket at the last search sample (none yet: -1)
    Patch p = patch_at(pr, 0.0);
    // The cone steps advance at least min_dt (at most `steps` of them); each search sample takes
    // at least a patch off the bracket, which halves after the first.
    for (int i = 0; i <= r.steps + 24; ++i) {
        vec2 span = patch_span(pr, p.lo);
        float t0 = clamp(span.x, ta, tb);
        float t1 = clamp(span.y, t0, tb);
        vec3 g = patch_gap_poly(p.h, clamp(pr.x0 + t0 * pr.dx - p.lo, 0.0, 1.0), pr.dx, pr.z0 + t0 * pr.dz, pr.dz);
        if (g.x <= PR_HIT_EPSILON) {
            // Under where the ray comes over p: the crossing lies before (at ta: only by rounding).
            if (t0 <= ta) {
                t_hit = ta;
                return true;
            }
            tb = t0;
            fb = g.x;
            searching = true;
        } else {
            float s = gap_first_root(g, t1 - t0);
            if (s >= 0.0) {
                t_hit = t0 + s;
                return true;
            }
            ta = t1;
            fa = g.x + (g.y + g.z * (t1 - t0)) * (t1 - t0);
            if (ta >= tb) break;
        }
        if (searching) {
            // A bracket a few float steps wide: its middle rounds to an end, whose patch was taken
            // off already, and neither end moves; the secant below is the crossing (that ran the
            // loop to its bound: 1,455 fragments of the cube under boxes, seen low at --steps
            // 1024, and 3.4 times the frame of the march before; found by an exploratory session).
            if (vec2(ta, tb) == searched_in) break;
            t_s = searched_in.x < 0.0 ? mix(ta, tb, fa / max(fa - fb, 1e-30)) : 0.5 * (ta + tb);
            searched_in = vec2(ta, tb);
        } else {
            float denom = run - p.c * r.dir.z;
            float dt = denom > 1e-12 ? p.c * fa / denom : (p.c > 0.0 ? r.t_end : 0.0);
            t_s = min(max(t_s + min_dt, ta + max(dt, nudge)), r.t_end);
        }
        p = patch_at(pr, t_s);
    }
    // (Only by rounding, or a bracket narrower than its float steps: the secant of what is left.)
    t_hit = searching ? mix(ta, tb, fa / max(fa - fb, 1e-30)) : r.t_end;
    return searching;
}
#endif // PR_CONE_PATCHES
#endif // PR_HEIGHT_FROM_CONE
