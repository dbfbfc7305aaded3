// Base-surface techniques (contract): the polygon is the top of the height range and the
// techniques carve inward by `depth` along the normal, in the metric tangent frame
// (T = dP/du, B = dP/dv unnormalized; height axis depth * N). Texture space is (u, v, s) with
// s = 1 at the polygon and s = h(u, v) on the surface.
// The reference technique draws tessellated, displaced triangles through the same shaders and
// shades them like `normal` (the height map's normal at the fragment's uv).
#include "common/shared.h"
#include "common/height.glsl"
#include "common/lighting.glsl"
#include "common/counters.glsl"
#include "march/relief.glsl"
// (The embedder expands each file once, whatever the #if around it: include unconditionally.)
#include "march/cone.glsl"
#include "common/shadow.glsl"

in vec3 v_world_pos;
in vec3 v_normal;
in vec2 v_uv;
in vec3 v_tangent;
in vec3 v_bitangent;

layout(location = 0) out vec4 o_color;

#if PR_TECHNIQUE == PR_TECH_REFERENCE && defined(PR_SHADOWS)
// The reference's shadows: the true displaced geometry's own, from shadow maps of it drawn from
// the light (Renderer::ensure_shadow_map). Hard: one map along the light, read at the nearest
// texel. Soft: one map from each of PR_SHADOW_LAYERS directions spread evenly over the light's
// disc, each standing for its share of the disc (a cell of angular radius r / sqrt(maps)): the
// light seen through that cell is filtered from its map over the cell's footprint at the distance
// of the occluders (percentage-closer soft shadows: a blocker search over the footprint at the
// farthest they can be, then a filter over the footprint at their mean distance; the maps are
// orthographic, so a footprint is the cell's tangent times the distance, without perspective).
// One look-up per map drew the 16 directions' shadows as 16 sharp copies under a large light.
// A point is moved off its triangle towards the light by about a texel of the maps and compared a
// texel nearer, so that a surface does not shadow itself; the filter's taps compare against the
// triangle's plane (its depth across the map). Points outside a map (none: each spans the points
// the image shows) are lit from its direction.
// (The maps have one level each: their look-ups, in the loop's varying control flow, need no
// derivatives.)
layout(binding = PR_TEX_SHADOW_MAP) uniform sampler2DArrayShadow s_shadow_map;
layout(binding = PR_TEX_SHADOW_DEPTH) uniform sampler2DArray s_shadow_depth;

// Taps evenly over the unit disc (a sunflower spiral of 12); each map turns them by its own angle,
// so that the maps' taps fall between each other's.
const int REFERENCE_TAPS = 12;
const vec2 REFERENCE_DISC[REFERENCE_TAPS] = vec2[](
    vec2(0.2041, 0.0000), vec2(-0.2607, 0.2388), vec2(0.0399, -0.4547), vec2(0.3286, 0.4286),
    vec2(-0.6030, -0.1067), vec2(0.5712, -0.3634), vec2(-0.1911, 0.7107), vec2(-0.3644, -0.7016),
    vec2(0.7906, 0.2887), vec2(-0.8224, 0.3395), vec2(0.3965, -0.8472), vec2(0.2930, 0.9341));

// `face`: the triangle's normal from the position's derivatives (taken in uniform control flow,
// before the caller's branch on the light's side).
float reference_visibility(vec3 world, vec3 face, vec3 light_dir)
{
    face = dot(face, face) > 0.0 ? normalize(face) : vec3(0.0);
    if (dot(face, light_dir) < 0.0) face = -face;
    vec4 moved = vec4(world + u_shadow_bias.x * face, 1.0);
    int maps = int(u_shadow_bias.z);
    // Each map's share of the disc: its angular radius (tangent).
    float cell = u_light_dir.w * inversesqrt(float(max(maps, 1)));
    float lit = 0.0;
    for (int k = 0; k < maps; ++k) {
        // The map's direction (its depth grows away from the light): one behind the point's own
        // triangle is blocked by it, which the map, looked up a texel and a half off the
        // triangle, does not see (a flat sheet under a light 5 degrees up, 30 across, got 0.90
        // of the light where 0.71 of the disc is over its horizon; found by a review).
        mat3 m = mat3(u_shadow[k]);
        vec3 row_x = vec3(m[0][0], m[1][0], m[2][0]), row_y = vec3(m[0][1], m[1][1], m[2][1]);
        vec3 row_z = vec3(m[0][2], m[1][2], m[2][2]);
        if (dot(face, row_z) > 0.0) continue;
        vec4 clip = u_shadow[k] * moved;
        vec3 p = vec3(clip.xy / clip.w * 0.5 + 0.5, clip.z / clip.w);
        if (any(lessThan(p, vec3(0.0))) || any(greaterThan(p, vec3(1.0)))) {
            lit += 1.0;
            continue;
        }
        float bias = u_shadow_bias.y;
        if (maps == 1) {
            lit += texture(s_shadow_map, vec4(p.xy, float(k), p.z - bias));
            continue;
        }
        // World units to the map's: across it (0..1 over the map) and along the light (depth).
        float to_map = 0.5 * length(row_x), to_depth = length(row_z);
        // The triangle's plane in the map: its depth's slope across the map, from the face's
        // normal in the map's frame (at most 10: 84 degrees from the light, for faces edge-on to
        // it). Taps off the point compare against the plane there, not the point's own depth,
        // so that a surface sloping away from the light does not shadow itself.
        vec3 f = vec3(dot(row_x, face), dot(row_y, face), dot(row_z, face)) /
                 vec3(length(row_x), length(row_y), to_depth);
        float fz = min(f.z, -0.1 * length(f.xy));
        vec2 slope = -f.xy / fz * (to_depth / to_map);
        float a = float(k) * 2.39996323; // the taps turned by the golden angle per map
        mat2 turn = mat2(cos(a), sin(a), -sin(a), cos(a));
        // The blocker search: over the cell's footprint at the map's near plane (the farthest an
        // occluder can be), and at the point itself.
        float reach = cell * (p.z / to_depth) * to_map;
        float blockers = 0.0, blocker_depth = 0.0;
        for (int j = -1; j < REFERENCE_TAPS; ++j) {
            vec2 disc = j < 0 ? vec2(0.0) : turn * REFERENCE_DISC[j];
            float d = texture(s_shadow_depth, vec3(p.xy + reach * disc, float(k))).r;
            if (d < p.z + dot(slope, reach * disc) - bias) {
                blockers += 1.0;
                blocker_depth += d;
            }
        }
        if (blockers == 0.0) {
            lit += 1.0;
            continue;
        }
        // The filter: over the cell's footprint at the occluders' mean distance.
        float gap = max(p.z - blocker_depth / blockers, 0.0);
        float spread = cell * (gap / to_depth) * to_map;
        float seen = texture(s_shadow_map, vec4(p.xy, float(k), p.z - bias));
        for (int j = 0; j < REFERENCE_TAPS; ++j) {
            vec2 disc = turn * REFERENCE_DISC[j];
            vec2 o = spread * disc;
            seen += texture(s_shadow_map, vec4(p.xy + o, float(k), p.z + dot(slope, o) - bias));
        }
        lit += seen / float(REFERENCE_TAPS + 1);
    }
    return lit / float(max(maps, 1));
}
#endif


// The rasterized triangle's normal (not of unit length) from the position's derivatives, taken
// at a power of two that brings them to a largest component in [1, 2) (scale_to_unit): their
// cross product, the pixel's footprint squared, vanished for objects 1e-20 across (forty-first
// session). Call in uniform control flow.
vec3 face_normal()
{
    vec3 fx = dFdx(v_world_pos), fy = dFdy(v_world_pos);
    vec3 a = max(abs(fx), abs(fy));
    float k = scale_to_unit(max(max(a.x, a.y), a.z));
    return cross(k * fx, k * fy);
}

void main()
{
    float depth = u_displace.x;
    vec3 n_geom = normalize(v_normal);
    if (!gl_FrontFacing) n_geom = -n_geom; // seen from behind: carve into the visible side
    vec3 t_axis = v_tangent;
    vec3 b_axis = v_bitangent;
    UvGrad g_color = UvGrad(dFdx(v_uv), dFdy(v_uv)); // the colour map's
    UvGrad g = height_grad(g_color);                  // the heights'
    vec3 view = v_world_pos - u_eye.xyz; // eye to fragment, world units

    vec2 uv = v_uv;
    float t_hit = 0.0; // along `view`: the hit is v_world_pos + t_hit * view

    float s_hit = 1.0; // texture-space height of the point shown (1: the polygon)
    // The texture frame, for the view ray and the light's (each soft strip's) directions.
    TextureFrame frame = texture_frame(t_axis, b_axis, n_geom, depth);
#if PR_TECHNIQUE == PR_TECH_OFFSET || PR_TECHNIQUE == PR_TECH_STEEP || \
    PR_TECHNIQUE == PR_TECH_POM || PR_TECHNIQUE == PR_TECH_RELIEF || \
    PR_TECHNIQUE == PR_TECH_CONE || PR_TECHNIQUE == PR_TECH_RELAXED_CONE
    // The view ray in texture space: solve view = d.x T + d.y B + d.z (depth N).
    if (depth > 0.0 && frame.scale != 0.0) {
        vec3 d = frame.inv * (frame.scale * view);
        // Descent per unit of height: at s the ray is at uv + (1 - s) * slope. A ray parallel to
        // the surface would never descend; clamp so uv stays finite at grazing angles.
        float descent = max(-d.z, 1e-6 * length(d.xy) + 1e-12);
        vec2 slope = d.xy / descent;
#if PR_TECHNIQUE == PR_TECH_OFFSET
        // Offset limiting (Welsh 2004): the parallax offset (1 - h) * slope scaled by cos(theta),
        // which bounds it by (1 - h) * depth in world units at grazing angles.
        float h = height_at(uv, g);
        float cos_theta = max(-dot(unit_vector(view), n_geom), 0.0);
        uv += (1.0 - h) * slope * cos_theta;
        t_hit = 0.0;
        s_hit = h;
#else
        MarchRay ray = MarchRay(vec3(uv, 1.0), vec3(slope, -1.0), 1.0, max(u_march.x, 1), vec3(0.0));
#if PR_TECHNIQUE == PR_TECH_CONE || PR_TECHNIQUE == PR_TECH_RELAXED_CONE
        float s_t = 1.0;
        march_cone_patches(ray, s_t);
#else
        Bracket b = march_linear(ray, g);
        float s_t = b.hit ? b.t_below : 1.0;
#if PR_TECHNIQUE == PR_TECH_POM
        if (b.hit) s_t = interpolate_bracket(b);
#elif PR_TECHNIQUE == PR_TECH_RELIEF
        if (b.hit) s_t = refine_binary(ray, b, u_march.y, g);
#endif
#endif
        uv += s_t * slope;
        t_hit = s_t / descent;
        s_hit = 1.0 - s_t;
#endif
    }
#endif

#if PR_TECHNIQUE == PR_TECH_FLAT
    vec3 n = n_geom;
#elif PR_TECHNIQUE == PR_TECH_REFERENCE
    // The true displaced surface: seen from behind (an open mesh from below, a closed one from
    // inside) its back, whose normal is the front's turned round. (The turned base normal in
    // height_normal() would tilt the bumps' slopes the wrong way: the surface carved into the
    // back, which is what the base-surface techniques draw there, not this one.)
    vec3 n = height_normal(uv, t_axis, b_axis, normalize(v_normal), depth);
    if (!gl_FrontFacing) n = -n;
#else
    vec3 n = height_normal(uv, t_axis, b_axis, n_geom, depth);
#endif
    vec3 to_eye = -unit_vector(view);
    vec3 light_dir = normalize(u_light_dir.xyz);
    float visibility = 1.0;
#if defined(PR_SHADOWS) && PR_TECHNIQUE == PR_TECH_REFERENCE
    vec3 face = face_normal();
    if (dot(n, light_dir) > 0.0) visibility = reference_visibility(v_world_pos, face, light_dir);
#elif defined(PR_SHADOWS) && PR_TECHNIQUE != PR_TECH_FLAT
#if PR_TECHNIQUE == PR_TECH_NORMAL || PR_TECHNIQUE == PR_TECH_OFFSET || PR_TECHNIQUE == PR_TECH_STEEP
    // The point shown is not on the height field: the polygon (normal), a point shifted by the
    // offset of another texel's height (offset), the first sample under the surface (steep). The
    // light march starts on the surface at the uv shown, or it starts under the surface and
    // everything is in shadow (offset's bumps were black pits under a light overhead, steep's
    // slopes speckled) or over it and nothing is (normal never cast a shadow).
    if (depth > 0.0 && dot(n, light_dir) > 0.0) s_hit = height_at(uv, g);
#elif PR_TECHNIQUE == PR_TECH_POM || PR_TECHNIQUE == PR_TECH_RELIEF
    // POM's hit, interpolated between the samples on either side of the surface, lies inside a
    // steep wall: straight up from there the wall blocked a light overhead (22 pixels of a box's
    // walls facing the eye, found by an exploratory session). Relief's, the middle of its last
    // bracket, may lie a hair inside one too: a soft light's march, which goes on under the
    // surface, found the wall over it (a light 0.006 degrees off the normal darkened 246 wall
    // pixels of builtin:boxes at 256 x 192; thirty-second session). The light march starts on the
    // surface at that uv, as prism:linear's, prism:relief's and the cone marchers' do.
    if (depth > 0.0 && dot(n, light_dir) > 0.0) s_hit = max(s_hit, height_at(uv, g));
#endif
    if (depth > 0.0 && dot(n, light_dir) > 0.0) {
        // (Soft: a ray for each strip of the disc, shadow.glsl.)
        visibility = 0.0;
        int strips = soft_strips();
        for (int k = 0; k < strips; ++k) {
            vec3 strip = soft_strip(k, strips);
            vec3 ray_dir = soft_strip_dir(light_dir, n_geom, strip);
            vec3 l_tex = light_in_texture_space(frame, ray_dir);
            visibility += strip_share(strip, light_visibility(vec3(uv, s_hit), l_tex, g));
        }
    }
#endif
    vec3 color = shade_blinn_phong(albedo_at(uv, g_color), n, light_dir, to_eye, visibility);
    o_color = vec4(color, 1.0);

#ifdef PR_DEPTH_WRITE
    // Depth of what is shown (--depth-write). A variant of its own: writing gl_FragDepth at all
    // turns off early depth rejection, so the plain variants never touch it.
    // No further than `depth` under the face's own plane: the displaced surface lies within that
    // (P + depth (h - midlevel) N, N a unit normal), while the march's frame takes the smooth
    // normal, which at a hard edge's welded corners leans far from the face: a ray nearly along
    // the frame's plane carved far behind the object, and with --midlevel 1 a wall 0.3 behind a
    // cube showed through 391 pixels along its outline (found by an exploratory session,
    // twenty-ninth; cli.depth_write_stays_within_the_shell).
    vec3 face = face_normal();
    float into = abs(dot(view, face)) * inversesqrt(max(dot(face, face), 1e-37)); // |view . face normal|
    float t_shown = into > 0.0 ? min(t_hit, depth / into) : t_hit;
    vec4 clip = u_view_proj * vec4(v_world_pos + t_shown * view, 1.0);
    // At least the smallest normal float: the carved point can lie past the far plane (a grazing
    // ray runs on through the repeating uv, beyond the shell's sphere), and a depth of 0 (the far
    // plane's, reversed: Camera::projection) failed the depth test against the clear value:
    // pixels of the polygon went missing.
    gl_FragDepth = clamp(clip.z / clip.w, uintBitsToFloat(0x00800000u), 1.0);
#endif

    count_fragment();
}
