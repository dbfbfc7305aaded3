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
//
// Soft shadows: a round light of angular radius u_light_dir.w (its tangent; --light-size is the
// diameter in degrees, 2 by default) centred on the light's direction, which the nearest
// occluder's edge cuts: a ray towards the disc is marched (one per upright strip of it: "The disc
// in strips" below; each strip's share is taken over its own ray's edge), and the edge lies across
// the disc as far below (or above) the ray as the smallest clearance angle seen along the
// way, the angle taken in the world, so that the penumbra is the same whatever the depth and the
// texture's scale: between the ray and the point on the surface under (or over) it, seen from the
// start, from the clearance's slope over the run in the world (clearance in height units times
// the depth, over the run in UV units times the world length of one along the ray: g_soft_scale)
// and the ray's own slope (g_soft_slope), by the tangent of a difference of angles. The march goes on under the surface while
// the edge is less than the radius above the centre. soft_light is the edge's offset across the
// disc's diameter, 0 (edge at the top) to 1 (at the bottom; 1/2 at a clearance of 0); disc_share
// turns it into the share of the disc's area over the edge, which light_visibility returns.
// (Until the twenty-second session the disc lay under the light's direction, the direction its
// top: the whole penumbra fell outside the hard shadow, which it widened by the disc's diameter,
// where the reference's soft shadows, from shadow maps over the disc, straddle its edge.)
// (Until the twentieth session it was the clearance over the run in texture units, times 6: it
// narrowed as the depth grew, and darkened flat ground under a low light depending on --depth.)
// (The radius was a constant of this file, tan 1 degree, until the twenty-first session.)

float g_soft_scale = 1.0; // world slope per texture-space clearance slope (light_in_texture_space)
// The tangent of the marched ray's elevation over the base surface in the world, and the
// light's own (light_in_texture_space; soft_light_ray may raise the one marched). At most 10^6:
// a light along the normal.
float g_soft_slope = 0.0;
float g_soft_light_slope = 0.0;
// soft_light at a clearance of 0: 1/2, the edge through the disc's centre, less where the ray
// marched is raised over the light's (soft_light_ray).
float g_soft_offset = 0.5;

// soft_light before it is clamped to [0, 1] (1e30 past 90 degrees): it orders near misses that
// all leave the whole disc lit (march_light).
float soft_light_unclamped(float clearance, float run)
{
    float k = g_soft_scale * clearance / max(run, 1e-30);
    float across = 1.0 + g_soft_slope * (g_soft_slope - k);
    return across > 0.0 ? g_soft_offset + (k / across) / max(2.0 * u_light_dir.w, 1e-30) : 1e30;
}

// The light seen past a clearance (height units) over a run (UV units) from the start: the
// tangent of the angle between the ray and the surface's point there, k / (1 + T (T - k)) for the
// clearance's world slope k and the ray's T (T - k is the point's), over the disc's diameter (in
// tangents: a small-angle estimate). Past 90 degrees (the denominator not positive: a point far
// under a steep ray) it is lit. (Until the twenty-second session the clearance's slope alone:
// right for a low light, but a clearance seen from under a light at 25 degrees makes an angle
// cos^2 25 = 0.82 times that, and the penumbra was that much narrower than the reference's, at
// 60 degrees 4 times.)
float soft_light(float clearance, float run)
{
    return clamp(soft_light_unclamped(clearance, run), 0.0, 1.0);
}

// soft_light inverted: the world slope of a clearance that leaves `visibility`, over the disc's
// diameter (the cone marchers' soft steps). A visibility so low that every point does leaves
// -1e30.
float soft_threshold(float visibility)
{
    float q = (visibility - g_soft_offset) * 2.0 * u_light_dir.w; // tangent of the angle
    float t = g_soft_slope;
    float across = 1.0 + q * t;
    return across > 0.0 ? q * (1.0 + t * t) / across / max(2.0 * u_light_dir.w, 1e-30) : -1e30;
}

// soft_light's clearance-to-run ratio per diameter, for small angles: soft_threshold is over it.
float soft_gain()
{
    return g_soft_scale / max(2.0 * u_light_dir.w, 1e-30);
}

// The share of the disc over an edge at soft_light's offset `v`: the area of the segment it cuts
// off. (0 and 1 are left as they are: hard shadows pass through too.)
float disc_share(float v)
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    float x = clamp(2.0 * v - 1.0, -1.0, 1.0);
    return 1.0 - (acos(x) - x * sqrt(1.0 - x * x)) * (1.0 / 3.14159265);
#else
    return v;
#endif
}

// ---- The disc in strips ------------------------------------------------------------------------
// One ray's clearance is taken up and down only (its height over the surface): it puts a level
// edge across the disc, as a wall's top or a box's far edge does. Beside an occluder the ray
// towards the disc's centre passes over low ground and sees nothing, and the sides of a shadow
// (the edges that run along the light's horizontal direction) stayed hard, a pixel wide, whatever
// the light's size. So a soft light is marched along soft_strips() rays: the disc is cut into
// upright strips of equal area (across the plane of the light and the base normal), each lit by
// its own ray through its centroid, with a level edge of its own, and the light is the sum of the
// strips' shares over their edges (strip_share). A level edge gives every ray the same offset and
// the sum is disc_share's. Each strip draws the shadow of the light along its ray, so a shadow's
// side comes in as many steps as there are strips (a fan of shadows behind a box); their number
// grows with the light's size, so that neighbouring rays stay about 4 degrees apart or less: 3
// strips below 10 degrees across, 5 below 20, 7 from 20 to 30. (Until the thirty-seventh
// session one ray, the centre's: a 16-texel box on the plane under a light of 30 degrees, 0.33
// units behind the box, had a side penumbra 1 pixel wide where the reference's was 11.)
int soft_strips()
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    // By the radius's tangent, against those of 5 and 10 degrees, over 1e-4 of them, so that sizes
    // of 10 and 20 degrees count as such. (The size worked back with atan: llvmpipe's is off by
    // 1.5e-5, and 10 and 20 degrees drew with a strip each side fewer; found by an exploratory
    // session.)
    float w = u_light_dir.w * (1.0 + 1e-4);
    return w >= 0.1763269807 ? 7 : (w >= 0.0874886635 ? 5 : 3);
#else
    return 1;
#endif
}

// The integral of sqrt(1 - x^2) from 0 to x.
float half_disc_integral(float x)
{
    x = clamp(x, -1.0, 1.0);
    return 0.5 * (x * sqrt(1.0 - x * x) + asin(x));
}

// The strips' inner borders across the unit disc, for 3, 5 and 7 strips (from index 0, 2 and 6):
// the x left of which lies k / strips of the disc's area, 2 (x sqrt(1 - x^2) + asin x) = pi (2 k /
// strips - 1). (Solved in the shader, by Newton's method, they cost a fifth of relaxed-cone's frame
// under a light of 2 degrees.)
const float PR_STRIP_BORDERS[12] = float[](-0.2649320846, 0.2649320846, -0.4918618328, -0.1577361938, 0.1577361938,
                                           0.4918618328, -0.5990605805, -0.3434778249, -0.1124370958, 0.1124370958,
                                           0.3434778249, 0.5990605805);

// Strip `strip` of `strips` across the unit disc: its borders (x, y) and its centroid's x (z),
// 0 for the middle one.
vec3 soft_strip(int strip, int strips)
{
    if (strips < 3) return vec3(-1.0, 1.0, 0.0);
    int first = strips == 3 ? 0 : (strips == 5 ? 2 : 6); // (the table's, for border 1)
    float a = strip == 0 ? -1.0 : PR_STRIP_BORDERS[first + strip - 1];
    float b = strip == strips - 1 ? 1.0 : PR_STRIP_BORDERS[first + strip];
    float ca = max(1.0 - a * a, 0.0), cb = max(1.0 - b * b, 0.0);
    // (2/3) ((1 - a^2)^(3/2) - (1 - b^2)^(3/2)) over the strip's area, pi / strips.
    float x = (2.0 / 3.0) * (ca * sqrt(ca) - cb * sqrt(cb)) * float(strips) / 3.14159265;
    if (2 * strip + 1 == strips) x = 0.0;
    return vec3(a, b, x);
}

// The world direction of the ray through `strip` (soft_strip) towards the light along
// `light_dir` (unit), for a surface with unit normal `n`: turned sideways (along n x light_dir)
// by the strip's centroid on the disc. The strips stand across the plane of the light and the
// normal, which a light within the disc's radius of the normal does not define (the disc holds
// the normal's direction): there they close in on the centre, in proportion to the light's angle
// from the normal over the radius, to one ray along the light at the normal, whatever the side.
// (Turned along whatever side the tilt gave, they drew a box's side penumbra on two opposite
// sides under a light 0.06 degrees off the normal, and on the other two with the tilt turned 90
// degrees, up to 42 levels apart, where the reference draws all four; found by an exploratory
// session.) The light itself with hard shadows.
vec3 soft_strip_dir(vec3 light_dir, vec3 n, vec3 strip)
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    vec3 side = cross(n, light_dir);
    float w = u_light_dir.w, sine = length(side); // (the sine of the light's angle from the normal)
    float spread = clamp(sine * sqrt(1.0 + w * w) / max(w, 1e-30), 0.0, 1.0); // over the radius's sine
    return sine > 0.0 ? normalize(light_dir + (strip.z * w * spread / sine) * side) : light_dir;
#else
    return light_dir;
#endif
}

// The share of the disc in `strip` (soft_strip) over an edge at soft_light's offset `v` (0: the
// edge at the disc's top, 1: at its bottom), lit by its own ray (soft_strip_dir). The offset
// itself with hard shadows.
float strip_share(vec3 strip, float v)
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    float a = strip.x, b = strip.y;
    float e = 1.0 - 2.0 * clamp(v, 0.0, 1.0); // the edge's height across the unit disc
    // The strip's area over y = |e| (the chord spans |x| <= w there), and over y = e: the strip
    // less its area under y = e, which is the area over y = -e.
    float f = abs(e), w = sqrt(max(1.0 - f * f, 0.0));
    float lo = clamp(a, -w, w), hi = clamp(b, -w, w);
    float over = max(half_disc_integral(hi) - half_disc_integral(lo) - f * (hi - lo), 0.0);
    float strip_area = 2.0 * (half_disc_integral(b) - half_disc_integral(a));
    return (e >= 0.0 ? over : strip_area - over) * (1.0 / 3.14159265);
#else
    return v;
#endif
}

// The light along `l_tex` seen from under the surface, through the height field turned over
// (g_height_flip: the prism's back of an open sheet): its rise turned, in the soft light's slope too.
vec3 turned_light(vec3 l_tex)
{
    g_soft_light_slope = -g_soft_light_slope;
    g_soft_slope = g_soft_light_slope;
    return vec3(l_tex.xy, -l_tex.z);
}

// Back to the light's own ray, as light_in_texture_space left it (the prism's walk follows it).
void soft_light_own_ray()
{
    g_soft_offset = 0.5;
    g_soft_slope = g_soft_light_slope;
}

// Soft shadows: the ray the light march follows, for the light along `l_tex` (texture space).
// Its own where it rises at least a quarter of the radius over the base surface's horizon (in
// the world), else raised to that, with g_soft_offset lowered by what the raise adds to every
// clearance angle: the march stays bounded (a ray that hardly rises runs through the height
// range for ever), and the part of the disc over the horizon is still lit when its centre is
// under it (a light at the horizon lights half the disc). Sets g_soft_offset and g_soft_slope.
vec3 soft_light_ray(vec3 l_tex)
{
    soft_light_own_ray();
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    float run = length(l_tex.xy);
    float lowest = 0.25 * u_light_dir.w; // (the tangent of a quarter of the radius, near enough)
    if (run > 0.0 && g_soft_light_slope < lowest) {
        // (The raise's tangent; past 90 degrees, a light from nearly straight under the
        // surface, no part of the disc is over it: its sign turned, and every point was lit;
        // found by a review.)
        float t = g_soft_light_slope;
        float across = 1.0 + lowest * t;
        g_soft_offset = across > 0.0 ? 0.5 - (lowest - t) / across / max(2.0 * u_light_dir.w, 1e-30) : -1e30;
        g_soft_slope = lowest;
        l_tex.z = lowest / max(g_soft_scale, 1e-30) * run;
    }
#endif
    return l_tex;
}

// The light a soft shadow leaves above a flat surface: the part of the disc above the base
// surface's horizon (`l_tex` in texture space: its slope; soft_light's offset, not yet the
// disc's share). 1 with hard shadows.
float soft_horizon(vec3 l_tex)
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    float run = length(l_tex.xy);
    return run > 0.0 ? soft_light(l_tex.z, run) : 1.0;
#else
    return 1.0;
#endif
}

#ifdef PR_HEIGHT_FROM_CONE
// The cone map at `uv` for the light's march: under the surface (g_height_flip: the prism's light
// march from the back of an open sheet, in the height field turned over) the turned heights and
// no cone, so the march steps as the linear one does (the cones stand on the upper side only).
// `rising`: with the conservative ratio (the light's steps; the height alone: false).
vec3 light_cone_at(vec2 uv, bool rising)
{
    vec3 hc = cone_at(uv, rising);
#if defined(PR_PRISM_TEARS) || defined(PR_HEIGHT_FLIP)
    if (g_height_flip > 0.0) hc = vec3(1.0 - hc.x, 0.0, 0.0);
#endif
    return hc;
}
#endif

// How a light march along a stretch of its ray ended (march_light).
#define PR_LIGHT_ON 1      // not blocked along the stretch: the march goes on past its end
#define PR_LIGHT_BLOCKED 0 // a sample under the surface (hard), or no light left (soft)

// One light sample at `t` of the ray from `origin` along `dir` (march_light): in x its clearance
// over the surface (the bias added), in y the cone map's conservative ratio there (the cone
// marchers; else 0).
vec2 light_sample(vec3 origin, vec3 dir, float t, UvGrad g)
{
    const float bias = 2e-3;
    vec3 p = origin + t * dir;
#ifdef PR_HEIGHT_FROM_CONE
    vec3 hc = light_cone_at(p.xy, true);
    return vec2(p.z + bias - hc.x, hc.z);
#else
    return vec2(p.z + bias - height_at(p.xy, g), 0.0);
#endif
}

// The light ray from `origin` along `dir` in texture space, up to t_end: samples at every step
// after the origin (the origin's own is the caller's), `rise` the height it gains there (the
// linear steps' count: --steps per full height range), at least texel_samples() per texel of
// the way. `run_before`: the distance in UV units the ray has gone before `origin` (the soft
// penumbra's), `visibility` as light_visibility's, both updated.
//
// Then the sample that came nearest to blocking the light (the least angle the ray clears the
// surface by, seen from where the light's ray starts, or the least light seen, which is that
// angle's measure too) is looked at again where the heights bend: bilinear heights bend on the lines
// through texel centres, and a box's edge is such a bend, where the ray's clearance is least and
// which samples a step apart miss by up to a step. The crossings of those lines next to that
// sample (the nearest on either side, between the samples before and after it) are sampled too.
// (Missed, the soft penumbra of a box's edge fell in steps as the receiver moved, and with the
// cone marchers' longer steps rose again inside it: a bright line along a box's shadow, 30 levels
// of 255 over the penumbra's 80; found by an exploratory session, twenty-ninth. By the least
// clearance, hard shadows took on flat ground the first sample, a step's rise over the surface,
// for the nearest miss, and never sampled the crest of a wall a texel thin that the samples
// straddled: ragged teeth of light reached into such walls' shadows, 805 pixels of 13,723 in
// Shadows.ThinWallsCastWholeShadowsUnderALowLight; found by an exploratory session, thirtieth.)
int march_light(vec3 origin, vec3 dir, float t_end, float rise, inout float run_before, inout float visibility, UvGrad g)
{
#ifdef PR_SHADOWS
    // --steps per full height range, and at least texel_samples() per texel along the way (as the
    // prism's march), bounded as the prism's march is: in full over four lengths of the map (by
    // 2 * --steps + 64 alone, a light low over a plane with a 2048-texel map came through a
    // wall's shadow in stripes).
    // (Bounded before the conversion: a light just over the horizon on an 8192-texel map asks
    // for more than an int holds.)
    vec2 size = vec2(textureSize(s_height, 0));
    vec2 texels = t_end * dir.xy * size;
    int bound = march_sample_bound(2, size);
    float wanted = ceil(float(u_march.x) * rise + texel_samples() * length(texels));
    int steps = max(int(min(wanted, float(bound))), 1);
    // Where the bound cuts the samples short, the first half of them keep the full density (dt,
    // up to t_split) and the rest share what is left (dt_far): the ray is lowest over the surface
    // near its start, and a wall that blocks it further on stands as often nearer (the maps
    // repeat). Spread evenly, a ray over 11 lengths of a 64-texel map stepped 5.7 texels and went
    // through a wall a texel thin in stripes of light across its shadow (two columns of 118
    // pixels, builtin depth 2 on the plane under a light 5 degrees up; found by an exploratory
    // session, thirty-second; Shadows.ThinWallsShadowRaysLongerThanTheBound).
    float dt = t_end / float(steps), t_split = t_end, dt_far = dt;
    if (wanted > float(bound) && steps >= 2) {
        dt = t_end / wanted;
        t_split = float(steps / 2) * dt;
        dt_far = (t_end - t_split) / float(steps - steps / 2);
    }
    float run = length(dir.xy); // UV units per unit t
    // The nearest miss so far (the angle it clears by, or the light it leaves, unclamped: where every
    // sample leaves the whole disc lit, the one that comes nearest to dimming it), where, and the
    // samples' places before and after it (the linear march's: a step either side, after it).
    float least = 1e30, t_least = -1.0, t_before = 0.0, t_after = t_end;
#ifdef PR_HEIGHT_FROM_CONE
    float t_last = 0.0;
    bool after_least = false;
    // Each step is at least dt, and one that reaches t_end by that least step alone ends there:
    // the stretch's end is sampled (a prism's exit is no other stretch's sample; where none
    // follows, at an open sheet's edge, the cone marchers stepped past it, and a wall there cast a
    // shadow a texel narrower than relief's; found by an exploratory session, thirtieth).
    float t = min(dt, t_end);
    int most = t_split < t_end ? steps + 1 : steps; // (a least step across t_split takes one more)
    for (int i = 1; i <= most; ++i) {
#else
    for (int i = 1; i <= steps; ++i) {
        float t = i <= steps / 2 || t_split == t_end ? float(i) * dt : t_split + float(i - steps / 2) * dt_far;
#endif
        vec2 sample_ = light_sample(origin, dir, t, g);
        float clearance = sample_.x;
#if PR_SHADOWS == PR_SHADOWS_HARD
        if (clearance < 0.0) return PR_LIGHT_BLOCKED;
        float near = clearance / max(run_before + t * run, 1e-30); // (the angle it clears by)
#else
        float near = soft_light_unclamped(clearance, run_before + t * run);
        visibility = min(visibility, clamp(near, 0.0, 1.0));
        if (visibility <= 0.0) return PR_LIGHT_BLOCKED;
#endif
        bool nearer = near < least;
        t_least = nearer ? t : t_least;
        least = min(least, near);
#ifdef PR_HEIGHT_FROM_CONE
        t_after = after_least ? t : t_after;
        t_before = nearer ? t_last : t_before;
        after_least = nearer;
        t_last = t;
#endif
#ifdef PR_HEIGHT_FROM_CONE
        float c = sample_.y;
        float denom = run - c * dir.z;
#if PR_SHADOWS == PR_SHADOWS_HARD
        // Steeper than the cone: it stays inside, and nothing further on along this straight
        // stretch can block it. (Only this stretch: the prism's light walk goes on in the next
        // prism's texture frame, where the ray's slope may be less.)
        if (denom <= 0.0) break;
        float clear = c * (clearance - 2e-3) / denom; // (the clearance less the bias)
#else
        // Soft: the cone bounds the heights s further on by hc.x + s * run / c (under the surface
        // too), so the clearance there is at least clearance - s * denom / c, and the light seen
        // there at least soft_light of that over the run. The step goes as far as that bound
        // leaves at least `visibility` (both sides times c: a cone of 0 steps dt), short of the
        // cone's own exit:
        // a near miss that would dim the light more is sampled, not stepped over. (The hard step
        // went through such misses: behind a wall lower than the range, the cone marchers drew
        // no penumbra at all where relief drew one.) Where the bound never falls below
        // `visibility` (a ray steeper than the cone, rising fast enough), nothing further on along
        // this stretch dims the light more.
        // (soft_threshold: the clearance's slope over the diameter that leaves `visibility`.)
        float gain = soft_gain();
        float least_slope = soft_threshold(visibility);
        float margin = c * (gain * clearance - least_slope * (run_before + t * run));
        float shrink = gain * denom + c * least_slope * run;
        if (shrink <= 0.0) break;
        float clear = margin / shrink;
#endif
        // Where the cone clears the rest of the stretch, its end needs no sample; where only the
        // least step reaches it, it does.
        if (t + clear >= t_end) break;
        t = min(t + max(clear, t < t_split ? dt : dt_far), t_end);
#endif
    }
    // The crossings of the lines through texel centres next to the nearest miss (above): the last
    // before it and the first after it, of either axis, within the samples around it.
#ifndef PR_HEIGHT_FROM_CONE
    t_before = t_least - (t_least <= t_split ? dt : dt_far);
    t_after = min(t_least + (t_least < t_split ? dt : dt_far), t_end);
#endif
    if (t_least > 0.0) {
        vec2 grid = (origin.xy + t_least * dir.xy) * size - 0.5; // texel centres at whole numbers
        vec2 per_t = dir.xy * size;
        vec2 lower = ceil(grid) - 1.0, upper = floor(grid) + 1.0; // the lines either side of it
        bvec2 forward = greaterThan(per_t, vec2(0.0));
        bvec2 moving = greaterThan(abs(per_t), vec2(1e-30));
        vec2 safe = mix(vec2(1.0), per_t, bvec2(moving));
        vec2 back = mix(vec2(-1e30), t_least + (mix(upper, lower, forward) - grid) / safe, moving);
        vec2 ahead = mix(vec2(1e30), t_least + (mix(lower, upper, forward) - grid) / safe, moving);
        float t_back = max(back.x, back.y), t_ahead = min(ahead.x, ahead.y);
        for (int k = 0; k < 2; ++k) {
            float tk = k == 0 ? t_back : t_ahead;
            // (Not before the first sample from the hit, whose own is the caller's; but in the
            // prism walk's later stretches, from their start: a crossing between it, the last
            // prism's exit, and the first sample was sampled by neither stretch, and a line of
            // light ran through a thin wall's shadow where its crest met a prism's side; found by
            // an exploratory session, forty-fourth.)
            if (!(tk >= (run_before > 0.0 ? 0.0 : dt) && tk > t_before && tk < t_after)) continue;
            float clearance = light_sample(origin, dir, tk, g).x;
#if PR_SHADOWS == PR_SHADOWS_HARD
            if (clearance < 0.0) return PR_LIGHT_BLOCKED;
#else
            visibility = min(visibility, soft_light(clearance, run_before + tk * run));
            if (visibility <= 0.0) return PR_LIGHT_BLOCKED;
#endif
        }
    }
    run_before += t_end * run;
#endif
    return PR_LIGHT_ON;
}

// Soft shadows: the light ray past the top of the height range (from `top`, along `dir`, `run_before`
// UV units from its start), where nothing blocks it but an occluder as high as the top still
// covers part of the disc. On, one sample per step as march_light's, until no height (none is
// above 1) could dim it by more than 1/128 below what `visibility` says, and for at most half the
// run before the top; not for a light whose disc is partly under the base surface's horizon
// (lower than its diameter, 2 degrees by default: the horizon dims it, soft_horizon). Such a light
// rises over a top-high plateau by less than the disc for ever: unbounded, frames took 3 times as
// long at 1.5 degrees.
// (The march used to end at the top, and such an occluder cast no penumbra outside its hard
// shadow.)
void soft_past_top(vec3 top, vec3 dir, float run_before, inout float visibility, UvGrad g)
{
#if defined(PR_SHADOWS) && PR_SHADOWS == PR_SHADOWS_SOFT
    float run = length(dir.xy);
    if (!(run > 0.0) || !(dir.z > 0.0) || visibility <= 0.0 || soft_light(dir.z, run) < 1.0) return;
    vec2 size = vec2(textureSize(s_height, 0));
    float per_t = max(texel_samples() * length(dir.xy * size), float(max(u_march.x, 1)) * dir.z);
    float dt = 1.0 / max(per_t, 1e-30);
    int bound = march_sample_bound(2, size);
    float run_limit = max(1.5 * run_before, run_before + 4.0 / max(size.x, size.y));
    const float bias = 2e-3;
    for (int i = 1; i <= bound; ++i) {
        vec3 p = top + (float(i) * dt) * dir;
        float total = run_before + float(i) * dt * run;
        if (total > run_limit || soft_light(p.z - 1.0 + bias, total) >= visibility - 1.0 / 128.0) break;
#ifdef PR_HEIGHT_FROM_CONE
        float h = light_cone_at(p.xy, false).x;
#else
        float h = height_at(p.xy, g);
#endif
        visibility = min(visibility, soft_light(p.z + bias - h, total));
    }
#endif
}

// Whether a light along texture-space direction `l_tex` rises above the base surface's horizon
// (against its run: l_tex's length goes as one over the object's scale).
bool light_above_horizon(vec3 l_tex)
{
    return l_tex.z > 1e-6 * length(l_tex.xy);
}

// The light march's start at `tex`: on the height field. The cone marchers' refinement may end a
// little under the surface (a sample under it where the secant meets it within relief's
// precision), which on a steep wall of boxes is far under the height at that uv: straight up
// from there the wall itself blocked a light overhead (0.4 % of the pixels of builtin:boxes, on
// walls facing the eye). The march starts on the surface at that uv.
vec3 light_start(vec3 tex)
{
#ifdef PR_HEIGHT_FROM_CONE
    tex.z = max(tex.z, light_cone_at(tex.xy, false).x);
#endif
    return tex;
}

// The light seen from `tex` on the height field (texture space), as soft_light's offset across the
// disc (disc_share gives the share of its area).
float light_visibility(vec3 tex, vec3 l_tex, UvGrad g)
{
#ifdef PR_SHADOWS
    // Light at or below the base surface's horizon: a light ray that does not rise stays in the
    // height range for ever (or comes from under the surface, through the object's body), so
    // it is blocked. (It used to count as unblocked: bump flanks facing such a light stayed lit,
    // and a sphere's night side showed them, shadows on or off.) A soft light's disc partly
    // over the horizon lights that part (soft_light_ray).
    l_tex = soft_light_ray(l_tex);
    if (!light_above_horizon(l_tex)) return 0.0;
    tex = light_start(tex);
    float t_end = max((1.0 - tex.z) / l_tex.z, 0.0);
    float visibility = soft_horizon(l_tex), run = 0.0;
    if (visibility <= 0.0) return 0.0;
    if (t_end > 0.0 && march_light(tex, l_tex, t_end, 1.0 - tex.z, run, visibility, g) == PR_LIGHT_BLOCKED) return 0.0;
    soft_past_top(tex + t_end * l_tex, l_tex, run, visibility, g);
    return visibility;
#else
    return 1.0;
#endif
}

// The light direction in the texture space of the frame (texture_frame).
vec3 light_in_texture_space(TextureFrame f, vec3 light_dir)
{
    if (f.scale == 0.0) return vec3(0.0, 0.0, 1.0);
    vec3 l_tex = f.inv * (f.scale * light_dir);
    // World length of one UV unit along the light's horizontal direction (the mean of the axes'
    // for a light along the normal), for the soft penumbra's angle: a clearance of one height unit
    // is `depth` in the world.
    float uv_run = length(l_tex.xy);
    float world_per_uv = uv_run > 1e-6 * abs(l_tex.z) ? length(l_tex.x * f.t_axis + l_tex.y * f.b_axis) / uv_run
                                                      : 0.5 * (length(f.t_axis) + length(f.b_axis));
    g_soft_scale = f.depth / max(world_per_uv, 1e-30);
    g_soft_light_slope = clamp(g_soft_scale * l_tex.z / max(uv_run, 1e-30), -1e6, 1e6);
    g_soft_slope = g_soft_light_slope;
    return l_tex;
}
