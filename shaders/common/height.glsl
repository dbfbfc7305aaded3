// Height and colour sampling. Every fetch inside a marcher goes through height_at(), which uses
// textureGrad with the gradients of the *entry* uv taken once before the loop: inside a loop
// (non-uniform control flow) implicit derivatives are undefined and cause seams of wrong mip
// levels (the seed's note on derivative artifacts).
layout(binding = PR_TEX_HEIGHT) uniform sampler2D s_height;
layout(binding = PR_TEX_COLOR) uniform sampler2D s_color;

struct UvGrad {
    vec2 dx; // d(uv)/dx in texture space per pixel
    vec2 dy;
};

// Height samples taken by this fragment (contract: one fetch of the height or cone texture in a
// marcher, refinement included). Written to the counters buffer by instrumented variants.
int g_height_samples = 0;

#ifdef PR_HEIGHT_FROM_CONE
// Cone marchers: every height the search sees comes from the cone map's R (level 0), so the
// linear, cone and binary stages agree on one surface.
#if (defined(PR_MARCHER) && PR_MARCHER == PR_MARCH_RELAXED_CONE) || \
    (defined(PR_TECHNIQUE) && PR_TECHNIQUE == PR_TECH_RELAXED_CONE)
// A relaxed map comes with the cone map as the two layers of one texture (layer 0 relaxed,
// layer 1 conservative: src/render/renderer.cpp, make_cone_pair_texture), for rising rays
// (march/cone.glsl, cone_at); heights and slopes read layer 0 (both hold the same heights).
#define PR_CONE_IS_RELAXED 1
layout(binding = PR_TEX_CONE) uniform sampler2DArray s_cone;
#define PR_CONE_COORD(uv) vec3(uv, 0.0)
#else
#define PR_CONE_IS_RELAXED 0
layout(binding = PR_TEX_CONE) uniform sampler2D s_cone;
#define PR_CONE_COORD(uv) (uv)
#endif
#endif

// 1 while the prism walk marches a ray *under* the surface (through a tear, prism.frag), or the
// light's march from the back of an open sheet goes: heights read as 1 - h and the ray's height
// is flipped too, so "comes out above h" is "meets 1 - h from above" and one marcher serves both.
// (PR_HEIGHT_FLIP: the prism's exact and vertex exits, for the light's march alone.)
#if defined(PR_PRISM_TEARS) || defined(PR_HEIGHT_FLIP)
float g_height_flip = 0.0;
#endif

float height_at(vec2 uv, UvGrad g)
{
    ++g_height_samples;
#ifdef PR_HEIGHT_FROM_CONE
    float h = textureLod(s_cone, PR_CONE_COORD(uv), 0.0).r;
#else
    float h = textureGrad(s_height, uv, g.dx, g.dy).r;
#endif
#if defined(PR_PRISM_TEARS) || defined(PR_HEIGHT_FLIP)
    return abs(g_height_flip - h);
#else
    return h;
#endif
}

// The least samples per texel a march takes along its path (the prism's segments, the light's
// march): one per two texels at the default --steps 32, and --steps / 64 above it (64: one per
// texel; 1024: 16), so that --steps raises the accuracy of grazing rays too, which cross many
// texels for little height (a wall one texel thick seen side-on was stepped over at any --steps).
float texel_samples() { return max(0.5, float(u_march.x) / 64.0); }

// The most samples one stretch of a march takes: `per_steps` times --steps, plus 64, or
// texel_samples() per texel over four lengths of the map's longer side (`size`, texels), whichever
// is more (the prism's segments: 4; the light's march: 2).
int march_sample_bound(int per_steps, vec2 size)
{
    return max(per_steps * max(u_march.x, 1) + 64, int(4.0 * texel_samples() * max(size.x, size.y)));
}

// A colour texture is a compile-time choice (PR_COLOR_TEXTURE, Renderer::program_for), not a
// uniform's: llvmpipe runs the code behind every branch for all fragments, taken or not, and the
// prism's colour level and fetch cost 11 % of its frame on the blob without a colour texture.
#ifdef PR_COLOR_TEXTURE
bool has_color_texture() { return true; }
#else
bool has_color_texture() { return false; }
#endif

// The gradients the height reads take (the base-surface techniques, from a pixel's uv gradients
// `g`): isotropic, as long as the footprint's shorter side in texels (the smaller singular value
// of the pixel's map to texels), so the level chosen never averages the heights over more texels
// than a pixel spans in any direction. With the pixel's own gradients GL takes the longer side:
// across a map much wider than tall (or a grazing view) the short side's heights were averaged
// away where the picture magnifies them, and relief and pom drew the grooves of a 2048 x 64 map
// flat, 12.8 dB against the reference where a 32 x 64 map of the same surface gave 26.2 (found
// by an exploratory session, thirty-sixth). The long side may alias, as the cone marchers' level 0
// does everywhere.
UvGrad height_grad(UvGrad g)
{
    vec2 size = vec2(textureSize(s_height, 0));
    vec2 a = g.dx * size, b = g.dy * size;
    float p = dot(a, a), q = dot(b, b), r = dot(a, b);
    float half_diff = 0.5 * (p - q);
    // The larger singular value, and the smaller as |det| over it (no cancellation where one side
    // is many times the other); 0 where the pixel spans no texel.
    float major = sqrt(0.5 * (p + q) + sqrt(half_diff * half_diff + r * r));
    float minor = major > 0.0 ? abs(a.x * b.y - a.y * b.x) / major : 0.0;
    if (!(minor < 1e30)) return g; // (a footprint past float range: the pixel's own, as GL takes it)
    return UvGrad(vec2(minor / size.x, 0.0), vec2(0.0, minor / size.y));
}

vec3 albedo_at(vec2 uv, UvGrad g)
{
    if (has_color_texture()) return textureGrad(s_color, uv, g.dx, g.dy).rgb;
    return u_base_color.rgb;
}

// The texture the normal reads heights from: for the cone marchers the cone map (its R holds the
// same heights), which the march has just read around the hit — on llvmpipe, reading the
// height map there instead cost 2 % of the prism's frame in cache misses.
#ifdef PR_HEIGHT_FROM_CONE
#define PR_SLOPE_TEXTURE s_cone
#define PR_SLOPE_COORD(uv) PR_CONE_COORD(uv)
#else
#define PR_SLOPE_TEXTURE s_height
#define PR_SLOPE_COORD(uv) (uv)
#endif

// Slopes of the height field (dh/du, dh/dv per UV unit) at uv, from level-0 texels: the three
// qualities of the seed. Not counted as marcher samples (shading, not search).
vec2 height_slopes(vec2 uv)
{
    vec2 size = vec2(textureSize(PR_SLOPE_TEXTURE, 0).xy);
    vec2 texel = 1.0 / size;
#if PR_NORMAL_QUALITY == PR_NORMAL_GATHER
    // 4 texels around uv in one fetch: w=(0,0) z=(1,0) x=(0,1) y=(1,1). Cheapest, coarsest
    // (the slope is constant across each texel quad).
    vec4 q = textureGather(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(uv), 0);
    vec2 d = vec2((q.y - q.x) + (q.z - q.w), (q.x - q.w) + (q.y - q.z)) * 0.5;
    return d * size;
#elif PR_NORMAL_QUALITY == PR_NORMAL_CENTRAL
    float hl = textureLod(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(uv - vec2(texel.x, 0.0)), 0.0).r;
    float hr = textureLod(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(uv + vec2(texel.x, 0.0)), 0.0).r;
    float hd = textureLod(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(uv - vec2(0.0, texel.y)), 0.0).r;
    float hu = textureLod(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(uv + vec2(0.0, texel.y)), 0.0).r;
    return vec2(hr - hl, hu - hd) * 0.5 * size;
#else
    // Sobel: 3x3 neighbourhood of bilinear taps one texel apart, smoothest and most robust to
    // 8-bit stair steps. The eight taps it weighs all filter texels of the 4x4 block around uv
    // with the same weights, so four gathers of that block give them (eight bilinear fetches
    // before: 32 texel reads and eight filterings).
    vec2 p = uv * size - 0.5;
    vec2 f = fract(p);
    vec2 centre = (floor(p) + 1.0) * texel; // the gathers' 2x2 blocks start at floor(p) - 1 and + 1
    // Gather order: x = (0,1), y = (1,1), z = (1,0), w = (0,0) within each 2x2 block.
    vec4 g00 = textureGatherOffset(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(centre), ivec2(-1, -1), 0);
    vec4 g10 = textureGatherOffset(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(centre), ivec2(1, -1), 0);
    vec4 g01 = textureGatherOffset(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(centre), ivec2(-1, 1), 0);
    vec4 g11 = textureGatherOffset(PR_SLOPE_TEXTURE, PR_SLOPE_COORD(centre), ivec2(1, 1), 0);
    // Rows of the block, texels floor(p) + (-1..2, j - 1) for j = 0..3 (no arrays: an array
    // indexed in a loop that the compiler does not unroll would live in memory).
    vec4 r0 = vec4(g00.w, g00.z, g10.w, g10.z), r1 = vec4(g00.x, g00.y, g10.x, g10.y);
    vec4 r2 = vec4(g01.w, g01.z, g11.w, g11.z), r3 = vec4(g01.x, g01.y, g11.x, g11.y);
    // The bilinear taps one texel apart: a[j] holds taps (-1, 0, +1) of row j - 1.
    vec3 a0 = mix(mix(r0.xyz, r0.yzw, f.x), mix(r1.xyz, r1.yzw, f.x), f.y);
    vec3 a1 = mix(mix(r1.xyz, r1.yzw, f.x), mix(r2.xyz, r2.yzw, f.x), f.y);
    vec3 a2 = mix(mix(r2.xyz, r2.yzw, f.x), mix(r3.xyz, r3.yzw, f.x), f.y);
    float gx = (a0.z + 2.0 * a1.z + a2.z) - (a0.x + 2.0 * a1.x + a2.x);
    float gy = (a2.x + 2.0 * a2.y + a2.z) - (a0.x + 2.0 * a0.y + a0.z);
    return vec2(gx, gy) / 8.0 * size;
#endif
}

// World-space normal of the displaced surface S = P + T u + B v + N depth h(u,v) at uv:
// dS/du = T + N depth dh/du, dS/dv = B + N depth dh/dv (metric frame, contract). Oriented to
// the side of n_geom, so mirrored UVs (left-handed T, B) give the same result.
// `du`, `dv`: dS/du and dS/dv (the prism's colour level, prism.frag).
vec3 height_normal_frame(vec2 uv, vec3 t, vec3 b, vec3 n_geom, float depth, out vec3 du, out vec3 dv)
{
    vec2 s = height_slopes(uv) * depth;
    du = t + n_geom * s.x;
    dv = b + n_geom * s.y;
    // Both over their largest component first: |du x dv| grows as the object's scale squared and
    // its length() squares that again, which overflowed past a scale of about 3e9 (the shading
    // went black) and fell under the test below for objects under about 1e-5.
    vec3 m = max(abs(du), abs(dv));
    float k = max(max(m.x, m.y), m.z);
    vec3 n = cross(du / k, dv / k);
    float len = length(n);
    if (!(len > 1e-20)) return n_geom;
    n /= len;
    return dot(n, n_geom) < 0.0 ? -n : n;
}

vec3 height_normal(vec2 uv, vec3 t, vec3 b, vec3 n_geom, float depth)
{
    vec3 du, dv;
    return height_normal_frame(uv, t, b, n_geom, depth, du, dv);
}

// A power of two that brings `largest` (> 0) to [1, 2); 1 for 0.
float scale_to_unit(float largest)
{
    return largest > 0.0 ? exp2(-floor(log2(largest))) : 1.0;
}

// A power of two that brings the texture-space frame (t, b, n depth) to a largest component in
// [1, 2): inverse(s F) * (s v) is inverse(F) * v to the bit (powers of two scale exactly), and the
// frame's determinant, which grows as the object's scale cubed, stays in float range. Unscaled,
// it fell under the degenerate test (1e-30) for objects scaled by 1e-10 and overflowed past 1e13:
// the parallax techniques drew plain normal mapping there, and the light's march had no
// direction (found by an exploratory session, seventeenth session).
float frame_scale(mat3 frame)
{
    vec3 m = max(max(abs(frame[0]), abs(frame[1])), abs(frame[2]));
    return scale_to_unit(max(max(m.x, m.y), m.z));
}

// The texture frame (t, b, n * depth) at a point of the base surface, to solve for a direction's
// texture-space components (the view ray's, surface.frag; the light's, light_in_texture_space,
// once for all of a soft light's strips): its inverse, over a power of two that brings its
// largest component to [1, 2) (frame_scale: the solution does not change). A singular frame has
// `scale` 0.
struct TextureFrame {
    mat3 inv;
    float scale;
    vec3 t_axis, b_axis, n;
    float depth;
};

TextureFrame texture_frame(vec3 t_axis, vec3 b_axis, vec3 n, float depth)
{
    mat3 frame = mat3(t_axis, b_axis, n * depth);
    float scale = frame_scale(frame);
    frame *= scale;
    bool ok = abs(determinant(frame)) > 1e-30;
    return TextureFrame(ok ? inverse(frame) : mat3(1.0), ok ? scale : 0.0, t_axis, b_axis, n, depth);
}
