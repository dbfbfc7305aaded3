// Prism silhouettes, stage 3: march the view ray through this fragment's prism, from where it
// enters (this face) to where it leaves the prism, found exactly per fragment by intersecting
// the ray with the prism's eight planar triangles (the same ones the geometry shader emits,
// rebuilt from the mesh buffers), or, with PR_PRISM_EXIT_VERTEX, from per-vertex distances to
// the prism's planes in texture space, interpolated (the seed's draft; prism.geom). A ray that leaves without meeting the height field is
// discarded: that is what makes the outline true. A hit writes its real depth.
#include "common/shared.h"
// The hit tolerance, in the height range (main sets it per fragment): PR_PRISM_HIT_EPSILON, or a
// quarter of the pixel's footprint where that is finer.
float g_hit_epsilon = PR_PRISM_HIT_EPSILON;
#define PR_HIT_EPSILON g_hit_epsilon
#if !defined(PR_PRISM_WALK) && defined(PR_SHADOWS)
#define PR_HEIGHT_FLIP 1 // (the light's march from the slab's bottom, main)
#endif
#include "common/height.glsl"
#include "common/lighting.glsl"
#include "common/counters.glsl"
#include "march/relief.glsl"
// (The embedder expands each file once, whatever the #if around it: include unconditionally.)
#include "march/cone.glsl"
#include "march/maxmip.glsl"
#include "common/shadow.glsl"
#include "prism/shell.glsl"

in vec3 v_world;
in vec3 v_tex;
#ifdef PR_PRISM_EXIT_VERTEX
in vec3 v_dir_tex;
in vec4 v_dist_sides;
in float v_dist_top;
#endif

layout(location = 0) out vec4 o_color;
// The hit is never in front of the face that was rasterized: depth (reversed: 1 at the near
// plane, Camera::projection) only falls, which keeps early depth rejection against what is
// already drawn.
layout(depth_less) out float gl_FragDepth;

// MeshVertex (src/mesh/mesh.hpp) is 16 floats: four texels (floats as bits).
layout(binding = PR_TEX_VERTICES) uniform usamplerBuffer t_vertices;

// Texel `k` (0..3) of vertex `index`.
vec4 vertex_texel(uint index, int k)
{
    return uintBitsToFloat(texelFetch(t_vertices, int(4u * index) + k));
}

struct BaseVertex {
    vec3 position;
    vec3 normal;
    vec2 uv;
    vec3 tangent;
    vec3 bitangent;
    uint weld;
};

BaseVertex base_vertex(uint index)
{
    vec4 p_nx = vertex_texel(index, 0), ny_nz_uv = vertex_texel(index, 1), tangent = vertex_texel(index, 2),
         b_weld = vertex_texel(index, 3);
    BaseVertex v;
    v.position = p_nx.xyz;
    v.normal = vec3(p_nx.w, ny_nz_uv.xy);
    v.uv = ny_nz_uv.zw;
    v.tangent = tangent.xyz;
    v.bitangent = b_weld.xyz;
    v.weld = floatBitsToUint(b_weld.w);
    return v;
}

// Fills corner_world/corner_tex (shell.glsl) and `from_a` for prism `prim`; returns its vertices.
void load_prism(uint prim, out BaseVertex bv[3], out bool from_a[3])
{
    uvec3 tri = triangle_indices(prim);
    for (int i = 0; i < 3; ++i) {
        bv[i] = base_vertex(tri[i]);
        vec3 world, n;
        shell_vertex(bv[i].position, bv[i].normal, world, n);
        corner_world[i] = shell_corner(world, n, 0.0);
        corner_world[i + 3] = shell_corner(world, n, 1.0);
        corner_tex[i] = vec3(bv[i].uv, 0.0);
        corner_tex[i + 3] = vec3(bv[i].uv, 1.0);
        corner_normal[i] = n;
    }
    for (int e = 0; e < 3; ++e) from_a[e] = diagonal_from_a(bv[e].weld, bv[(e + 1) % 3].weld);
}

// One march from `tex_in` to `tex_out` in texture space (linear in the ray parameter between
// them). Steps: --steps per full height range (as the base-surface techniques, so equal --steps
// means equal step length), and at least texel_samples() per texel along the uv path (one per two
// texels at the default --steps 32), so grazing rays near the silhouette do not step over bumps. March and refinement are apart: the walk
// brackets the hit prism by prism and refines once, after its loop (llvmpipe would run the
// refinement's loop in every prism of every lane's walk).
// The segment's ray is not kept in it: the walk carries a segment from pass to pass (for the lanes
// that hit, llvmpipe keeps it while the others walk on), and segment_ray() builds the ray again.
struct Segment {
    Bracket br;     // br.hit: the ray meets the height field in this segment
    bool linear;    // marched linearly (max-mip under a tear)
};

// The march ray from `tex_in` to `tex_out` in texture space: the parabola through them and the
// chord's middle moved by `bend` (path_bend), at points linear in the view ray's parameter.
MarchRay segment_ray(vec3 tex_in, vec3 tex_out, vec3 bend)
{
    vec3 seg = tex_out - tex_in;
    // Its length in texels of the height map (u_displace.zw: the map's size); a bent path's is
    // about its length through its middle, at most the chord's and twice the bend's.
    float texels = length(seg.xy * u_displace.zw) + 2.0 * length(bend.xy * u_displace.zw);
    // Bounded (a prism's uv may span many repeats of the map), but not below what texel_samples()
    // per texel takes over four lengths of the map: merged triangles (flat_merge.hpp, at most two
    // repeats long) are sampled in full. (Bounded by 4 * --steps + 64 alone, a segment across the
    // merged plane took a sample every 7 texels of a 1024-texel map and stepped over thin walls.)
    // Bounded before the conversion to int, which a prism's uv a million repeats long overflows.
    int bound = march_sample_bound(4, u_displace.zw);
    // (A bent path may fall and rise again: its height range, at most |seg.z| + 2 |bend.z|.)
    float rise = abs(seg.z) + 2.0 * abs(bend.z);
    int steps = int(min(ceil(max(float(u_march.x) * rise, texel_samples() * texels)), float(bound)));
    steps = max(steps, 1);
    return MarchRay(tex_in, seg, 1.0, steps, 4.0 * bend);
}

// `first`: the sample at tex_in, as the marcher takes it (cone_at() for the cone marchers, else
// the height in x), which is the last one of the segment before; with `pending` there is none
// (the first segment, or a UV seam lies between), and the march takes it as its first. `below`,
// `decide`: the walk under a torn surface (march_linear_from, march/linear.glsl). `last`: the
// last sample the march took.
Segment march_segment(vec3 tex_in, vec3 tex_out, vec3 bend, vec3 first, bool pending, bool decide, inout bool below,
                      out vec3 last)
{
    last = first;
    // Geometry (the outline and the depth) uses height level 0, as the reference does
    // (contract); filtering it by mip level would move the surface, not just smooth its look.
    UvGrad g = UvGrad(vec2(0.0), vec2(0.0));
    MarchRay ray = segment_ray(tex_in, tex_out, bend);
#if defined(PR_PRISM_TEARS) && PR_MARCHER == PR_MARCH_MAX_MIP
    // Under a torn surface the max pyramid (of h, seen from above) does not hold: a linear march.
    // (Max-mip only: a sample of its own at a seam.)
    float h0 = first.x;
    if (decide) {
        h0 = height_at(tex_in.xy, g);
        below = tex_in.z < h0 - PR_HIT_EPSILON;
        pending = false;
    }
    if (below) {
        float h_end;
        Bracket br = march_linear_from(ray, g, h0, pending, false, below, h_end);
        last = vec3(h_end, 0.0, 0.0);
        return Segment(br, true);
    }
#endif
#if PR_MARCHER == PR_MARCH_CONE || PR_MARCHER == PR_MARCH_RELAXED_CONE
    return Segment(march_cone_from(ray, first, pending, decide, below, last), false);
#elif PR_MARCHER == PR_MARCH_MAX_MIP
    // Its own traversal (last: unused), which follows straight lines: two, through the path's true
    // middle (the hit's texture coordinates follow them too, main), the second only where the
    // first finds nothing (torus and rock: 68.21 and 64.44 height samples per fragment before,
    // 65.86 and 61.86; the same pictures). The bracket is in the whole segment's parameter.
    vec3 middle = 0.5 * (tex_in + tex_out) + bend;
    Bracket near = march_max_mip(segment_ray(tex_in, middle, vec3(0.0)));
    Bracket br = near.hit ? near : march_max_mip(segment_ray(middle, tex_out, vec3(0.0)));
    float from = near.hit ? 0.0 : 0.5;
    br.t_above = from + 0.5 * br.t_above;
    br.t_below = from + 0.5 * br.t_below;
    return Segment(br, false);
#else
    float h_end;
    Bracket br = march_linear_from(ray, g, first.x, pending, decide, below, h_end);
    last = vec3(h_end, 0.0, 0.0);
    return Segment(br, false);
#endif
}

// The hit's fraction of a marched segment (its ray: segment_ray()), refined as the marcher does,
// or -1 when the ray stays above the height field there.
float refine_segment(Segment sg, MarchRay ray)
{
    if (!sg.br.hit) return -1.0;
    UvGrad g = UvGrad(vec2(0.0), vec2(0.0));
#if defined(PR_PRISM_TEARS) && PR_MARCHER == PR_MARCH_MAX_MIP
    if (sg.linear) return refine_binary(ray, sg.br, u_march.y, g);
#endif
#if PR_MARCHER == PR_MARCH_LINEAR
    return interpolate_bracket(sg.br);
#elif PR_MARCHER == PR_MARCH_CONE || PR_MARCHER == PR_MARCH_RELAXED_CONE
    return refine_cone(ray, sg.br, g);
#elif PR_MARCHER == PR_MARCH_MAX_MIP
    return sg.br.t_below; // exact: no refinement
#else
    return refine_binary(ray, sg.br, u_march.y, g);
#endif
}

// Barycentric weights of `uv` in the uv triangle (a, b, c); false (and the centre) when that
// triangle is degenerate.
bool uv_weights(vec2 uv, vec2 a, vec2 b, vec2 c, out vec3 w)
{
    vec2 d1 = b - a, d2 = c - a, dp = uv - a;
    float den = d1.x * d2.y - d1.y * d2.x;
    bool ok = abs(den) > 1e-20;
    w = ok ? vec3(0.0, (dp.x * d2.y - dp.y * d2.x) / den, (d1.x * dp.y - d1.y * dp.x) / den)
           : vec3(0.0, 1.0 / 3.0, 1.0 / 3.0);
    w.x = 1.0 - w.y - w.z;
    return ok;
}

// Barycentric weights of the world point `x` in the current prism's layer at height `h` (the
// triangle of its corners moved h of the way up their normals, as prism_tex_at maps it), taken
// in that triangle's plane; the centre where the layer has no area.
vec3 layer_weights(vec3 x, float h)
{
    vec3 q0 = corner_world[0] + h * u_displace.x * corner_normal[0];
    vec3 e1 = corner_world[1] + h * u_displace.x * corner_normal[1] - q0;
    vec3 e2 = corner_world[2] + h * u_displace.x * corner_normal[2] - q0;
    vec3 p = x - q0, n = cross(e1, e2);
    float den = dot(n, n);
    if (!(den > 0.0)) return vec3(1.0 / 3.0);
    float w1 = dot(cross(p, e2), n) / den, w2 = dot(cross(e1, p), n) / den;
    return vec3(1.0 - w1 - w2, w1, w2);
}

// The texture-space point (u, v, height) of the world point `x` in the current prism
// (load_walk_prism, load_prism): the solution (b, h) of sum_i b_i * (bottom_i + h * depth * N_i) = x, by one
// step of Newton's method from `guess`, a point near it (the planar faces' coordinates: a second
// step changed no metric). The prism's map is affine in b at each height and in h along each
// normal line, but not in both: where the normals part, each layer is the base triangle grown
// with the height, a straight world ray's texture-space path bends, and the faces' planar
// triangles are only near the map's own sides (docs/prism.md, item 3). `slope`: the rate at which
// the point's (b1, b2, h) change along `dir` (the map's inverse Jacobian times dir), and in w 1,
// or 0 where the guess stands (below).
vec3 prism_tex_at(vec3 x, vec3 guess, vec3 dir, out vec4 slope)
{
    vec3 b;
    bool mapped = uv_weights(guess.xy, corner_tex[0].xy, corner_tex[1].xy, corner_tex[2].xy, b);
    float h = guess.z;
    vec3 d0 = u_displace.x * corner_normal[0];
    vec3 f1 = u_displace.x * corner_normal[1] - d0, f2 = u_displace.x * corner_normal[2] - d0;
    // The map's columns d/db1, d/db2, d/dh at (b, h), and the residual; Cramer's rule. All over the
    // shell's depth: the determinant grows as the object's scale cubed, and left float range for
    // objects near the ends of the scales the walk draws (2.8e-9 to 4.4e13 across). (A power of
    // two from the columns themselves, as frame_scale in height.glsl, cost 3-10 % of the frame on
    // llvmpipe.)
    vec3 c1 = corner_world[1] - corner_world[0] + h * f1, c2 = corner_world[2] - corner_world[0] + h * f2;
    vec3 c3 = d0 + b.y * f1 + b.z * f2;
    vec3 r = x - corner_world[0] - (h * d0 + b.y * c1 + b.z * c2);
    float k = u_displace.x > 0.0 ? 1.0 / u_displace.x : 1.0;
    c1 *= k;
    c2 *= k;
    c3 *= k;
    r *= k;
    vec3 k1 = cross(c2, c3), k2 = cross(c3, c1), k3 = cross(c1, c2);
    float det = dot(c1, k1);
    bool solvable = abs(det) > 1e-20;
    float inv = solvable ? 1.0 / det : 0.0;
    vec3 step = vec3(dot(r, k1), dot(r, k2), dot(r, k3)) * inv;
    // The residual holds the rounding of x and the corners, floats of the size of the eye's and
    // the object's coordinates; the step's height is that over the depth, a texel's fraction only
    // where the depth is a fair fraction of the triangles. A height step within it is rounding:
    // the guess's height stands, as it does on a bottom (the base triangle, where the map is the
    // faces' own planar one). (At --depth 1e-4 the rounding, a few 1e-7 of the eye's distance,
    // lifted an exit through a bottom over a floor of height 0 by 4e-3 of the range, 40 times the
    // hit tolerance: the march missed the floor there and the ray left through the bottom, and
    // a fifth of the sphere's outline went missing with builtin:bumps; found by an exploratory
    // session, thirtieth.)
    vec3 sizes = max(max(abs(x), abs(u_eye.xyz)), abs(corner_world[0]));
    float rounding = 1e-6 * max(max(sizes.x, sizes.y), sizes.z) * k;
    step.z = guess.z == 0.0 || abs(step.z) <= rounding ? 0.0 : step.z;
    b = vec3(b.x - step.x - step.y, b.y + step.x, b.z + step.y);
    vec2 uv = corner_tex[0].xy * b.x + corner_tex[1].xy * b.y + corner_tex[2].xy * b.z;
    // (A triangle without area in uv gives no weights to start from: the guess. A step of a
    // quarter of the triangle or of the height range is no correction but the map near a fold,
    // where its Jacobian vanishes: a noisy mesh's tight creases; a UV sphere of 120 x 60 quads
    // with each vertex's radius jittered by 8 % drew 114 pixels outside the reference's outline
    // at 192 x 144 without this, 87 with it, 88 with the straight march.)
    bool near = solvable && max(max(abs(step.x), abs(step.y)), abs(step.z)) < 0.25;
    vec3 kdir = k * dir;
    slope = mapped && near ? vec4(vec3(dot(kdir, k1), dot(kdir, k2), dot(kdir, k3)) * inv, 1.0) : vec4(0.0);
    return mapped && near ? vec3(uv, clamp(h + step.z, 0.0, 1.0)) : guess;
}

// The bend of the ray's texture-space path over `span` of its parameter, from its slopes at the
// two ends (prism_tex_at): the middle's offset from the chord of the parabola with those slopes,
// (slope_in - slope_out) * span / 8, in (u, v, height) (march/linear.glsl, MarchRay.curve). From
// the true middle instead (a third step of Newton's method per prism), the frame was about 5 %
// slower on llvmpipe and the pictures within 2 dB of these either way (the cube under a shell a
// tenth of its size deep 1.7 dB closer to the reference, the torus 2.5 dB further), but for a
// 12-triangle sphere under a shell a third of its radius deep (7.5 dB closer at 35 degrees).
// Straight where either end keeps its guess.
vec3 path_bend(vec4 slope_in, vec4 slope_out, float span)
{
    vec3 d = (slope_in.xyz - slope_out.xyz) * (0.125 * span * slope_in.w * slope_out.w);
    return vec3((corner_tex[1].xy - corner_tex[0].xy) * d.x + (corner_tex[2].xy - corner_tex[0].xy) * d.y, d.z);
}

// A march's ends in the current prism at their true places (prism_tex_at) for the ray
// origin + t * dir from t_in to t_out: `tex_in` and `tex_out` come in as the faces' planar
// coordinates there and go out as the true ones (`tex_in` as it came where `keep_in`: a place
// found otherwise, the eye's or a hit's). Returns the path's bend between them (path_bend).
vec3 true_ends(vec3 origin, vec3 dir, float t_in, float t_out, bool keep_in, inout vec3 tex_in, inout vec3 tex_out)
{
    vec4 slope_in, slope_out;
    vec3 m_in = prism_tex_at(origin + t_in * dir, tex_in, dir, slope_in);
    tex_out = prism_tex_at(origin + t_out * dir, tex_out, dir, slope_out);
    tex_in = keep_in ? tex_in : m_in;
    return path_bend(slope_in, slope_out, t_out - t_in);
}

#ifdef PR_PRISM_WALK
#ifdef PR_PRISM_TEARS
// Pixels where a walk went into the object through a tear (pass 1 writes, pass 2 reads).
layout(binding = PR_IMAGE_TEARS, r32ui) uniform uimage2D u_tears;
layout(binding = PR_IMAGE_TEAR_TILES, r32ui) uniform uimage2D u_tear_tiles;
#endif


// The edge of the current prism's top cap nearest a top exit with barycentric weights `w`, and in
// `lambda` the exit's place along it (0 at corner e, 1 at corner e + 1). The walk tries the
// neighbour across it, and goes on only if the ray goes into that neighbour's top (item 10 of
// docs/prism.md).
int top_exit_edge(vec3 w, out float lambda)
{
    // Edge e runs from corner e to corner e + 1; its opposite corner (e + 2) % 3 weighs least.
    int e = w.z < w.x ? (w.z < w.y ? 0 : 2) : (w.x < w.y ? 1 : 2);
    float a = e == 0 ? w.x : (e == 1 ? w.y : w.z), b = e == 0 ? w.y : (e == 1 ? w.z : w.x);
    lambda = clamp(b / max(a + b, 1e-20), 0.0, 1.0);
    return e;
}

// The point where the walk enters the current prism (just loaded) across its edge `edge`, at
// `along` from the edge's first corner (the prism before ran that edge the other way) and at
// height `z`: the same point in this prism's own uv (a seam may change it).
vec3 entry_point(int edge, float along, float z)
{
    // (Selects, not corner_tex[edge]: an index unknown at compile time would send the whole
    // array to memory on some compilers, llvmpipe's among them.)
    vec2 from = edge == 0 ? corner_tex[0].xy : (edge == 1 ? corner_tex[1].xy : corner_tex[2].xy);
    vec2 to = edge == 0 ? corner_tex[1].xy : (edge == 1 ? corner_tex[2].xy : corner_tex[0].xy);
    return vec3(mix(from, to, along), z);
}

// Whether a UV seam lies between the end of the last segment, `tex_out`, and the start of the
// next, `tex_in` (the uv jumps by more than whole repeats): the last sample is then not the next
// segment's first (march_segment: `pending`), and on a torn mesh the ray's side of the surface
// (`below`) is decided anew by the far side's height (`decide`). Meshes without seams
// (PR_PRISM_SEAMLESS) have none.
bool at_seam(vec3 tex_in, vec3 tex_out)
{
#ifdef PR_PRISM_SEAMLESS
    return false;
#else
    vec2 jump = tex_in.xy - tex_out.xy;
    jump -= round(jump);
    return any(greaterThan(abs(jump), vec2(1e-4)));
#endif
}

#ifdef PR_SHADOWS
// How far under the far side's surface, in its height range, the light's ray must be at a seam
// to go on under it (light_walk): the ray's true place there, one Newton step from the planar
// one, errs by more than the march's bias (2e-3) in the sheared prisms at a cube's corners.
const float kLightSeamMargin = 1e-2;

// Self-shadowing with the walk (called where the march in the hit's texture frame finds shadow,
// main below): the light ray from the hit goes from prism to prism as the view ray does (its
// exits found in the world, its march in each prism's texture space), so it meets the heights
// the mesh shows around the hit, and no others. Its prisms have their tops at 1 whatever the
// shell (g_full_tops): a tight top bounds the heights around its own vertex only, and a low light
// ray out through one could still meet a wall further on. The light is on where the ray leaves
// through a top or a side without a neighbour, off where it goes under a bottom cap. The ray's
// parameter starts at the eye's distance behind the hit, not at 0, so that the walk's
// tolerances, relative to it as the view walk's are, keep their size. Returns the visibility, or
// -1 where the walk gives no answer: lost, or past its limit of prisms.
//
// On a torn mesh (PR_PRISM_TEARS) the light's ray goes through the tears as the view's does: where
// it crosses a UV seam under the far side's surface it goes on under it (`below`, the heights
// turned over, as the view walk's march), until a seam takes it out again; under the surface it
// is blocked where it meets the surface from below, where it goes out through a bottom into a
// closed mesh's body (from under an open sheet it goes on) and through a top. `under`: the hit is the surface's back, seen through a tear (the view walk's `below`),
// and the light's ray starts under it. (Until the forty-first session such a back was dark
// whatever the light, and a ray that crossed a seam under the far side's surface was blocked
// there: bump tops along a tetrahedron's edges, each face a UV island of its own, were black where
// the reference, lit through the tear's crack, is lit: 26.5 dB against 39.6 without shadows;
// found by an exploratory session.)
float light_walk(uint prim, vec3 tex, vec3 hit, vec3 light_dir, bool under)
{
    UvGrad g = UvGrad(vec2(0.0), vec2(0.0));
    bool from_a[3];
    float visibility = 1.0;
    float run = 0.0; // UV units gone (the soft penumbra's distance)
    bool below = under;
    vec3 tex_in = below ? tex : light_start(tex), tex_out = tex_in;
    float start = max(distance(hit, u_eye.xyz), 1e-30);
    vec3 origin = hit - start * light_dir;
    float t_in = start;
    int entry_edge = -1;
    float entry_along = 0.0;
    bool blocked = false;
    bool ended = false; // out of the shell, or blocked
    g_full_tops = true;
    // At most 64 prisms (the view walk's limit is larger, up to 4096 around a vertex of high
    // valence: a light low over a disc of 20,000 slivers took 46 s a frame at 256x192, against 8 s
    // for the texture plane's march alone); past them the walk gives no answer.
    for (int k = 0; k < min(u_walk.x, 64) && !ended; ++k) {
        load_walk_prism(prim, from_a);
        bool seam = false; // crossed into this prism across a UV seam
        if (entry_edge >= 0) {
            vec3 came_out = tex_out;
            tex_in = entry_point(entry_edge, entry_along, tex_out.z);
            seam = at_seam(tex_in, came_out);
        }
        // The start may lie on a face of its prism (its bottom, where the height is 0): the exits
        // count from a little behind it (the faces the ray goes in by never count).
        float t_min = k == 0 ? start - 1e-4 * distance(corner_world[0], corner_world[3]) : t_in * (1.0 - 1e-6);
        bool top_entry;
        vec3 w_top;
        ExitFace ex = nearest_exit(origin, light_dir, t_min, from_a, 1e-5, walk_orientation, t_in,
                                   entry_edge < 0 ? -1 : 2 + entry_edge, top_entry, w_top);
        if (ex.face < 0) break; // lost: no answer
        tex_out = vec3(ex.tex.xy, clamp(ex.tex.z, 0.0, 1.0));
        // Marched between the ray's true places in the prism's texture space, as the view's march
        // (prism_tex_at; straight between them); the first starts at the hit's own.
        vec3 m_in = tex_in, m_out = tex_out;
        true_ends(origin, light_dir, t_in, ex.t, k == 0, m_in, m_out);
        vec3 d = m_out - m_in;
#ifdef PR_PRISM_TEARS
        // Across a seam the far side's height at the ray's true place says which side of its
        // surface the ray is on (by a margin, kLightSeamMargin; at the planar place, a curved
        // prism's side put rays under surfaces they pass over).
        if (seam) below = m_in.z + kLightSeamMargin < height_at(m_in.xy, g);
        // Under the surface: the march through the heights turned over (as the back of an open
        // sheet's, main), the soft light's slope turned with them, and back after it (the slope
        // marched may be raised over the light's: soft_light_ray). (One march for both: llvmpipe
        // runs each arm of a branch for all its lanes where they differ.)
        float soft_slope = g_soft_slope, soft_light_slope = g_soft_light_slope;
        if (below) turned_light(d);
        g_height_flip = below ? 1.0 : 0.0;
        blocked = march_light(below ? vec3(m_in.xy, 1.0 - m_in.z) : m_in, below ? vec3(d.xy, -d.z) : d, 1.0, abs(d.z),
                              run, visibility, g) == PR_LIGHT_BLOCKED;
        g_height_flip = 0.0;
        g_soft_slope = soft_slope;
        g_soft_light_slope = soft_light_slope;
#else
        blocked = march_light(m_in, d, 1.0, abs(d.z), run, visibility, g) == PR_LIGHT_BLOCKED;
#endif
        // Out through a top, at 1: above every height (from under the surface it went through
        // it, where its march missed that: a box's top at 1). Under the base surface: the
        // object's body, or the sheet, is in the way; but from under an open mesh's sheet (through
        // a tear) it goes on into the open space under it.
        bool open_below = below && (u_march.w & PR_FLAG_OPEN_SHELL) != 0;
        blocked = blocked || (ex.face == 1 && !open_below) || (below && ex.face == 0);
        ended = blocked || ex.face <= 1;
        // Out through a top: soft light goes on past it, in this prism's frame.
        if (ex.face == 0 && !blocked && !below) soft_past_top(m_out, d, run, visibility, g);
        if (ended) break;
        uvec3 across = prism_across;
        int edge = ex.face - 2;
        uint next = edge == 0 ? across.x : (edge == 1 ? across.y : across.z);
        ended = next == 0xffffffffu; // out through the shell's side
        if (ended) break;
        prim = next >> 2u;
        entry_edge = int(next & 3u);
        entry_along = clamp(1.0 - ex.lambda, 0.0, 1.0); // the neighbour runs the edge the other way
        t_in = max(ex.t, start);
    }
    g_full_tops = false;
    return !ended ? -1.0 : (blocked ? 0.0 : visibility);
}
#endif

#endif

// The displaced surface's axes dS/du and dS/dv at the hit as the reference's triangles have
// them: the prism's layer at the hit's height `h` (its corners moved along their normals to it),
// linear in uv over the triangle, plus `slope_du` and `slope_dv`, the height's slopes along the
// normal. False for a uv triangle with no area (or axes past the float range). The vertices'
// averaged tangents, which the shading takes, are no such thing where the mesh has creases: on
// the bundled cube they lean with the welded corner normals, up to 55 degrees from the face.
bool layer_axes(float h, vec3 slope_du, vec3 slope_dv, out vec3 du, out vec3 dv)
{
    vec2 e1 = corner_tex[1].xy - corner_tex[0].xy, e2 = corner_tex[2].xy - corner_tex[0].xy;
    float det = e1.x * e2.y - e2.x * e1.y;
    vec3 lift = vec3(h * u_displace.x);
    vec3 c0 = corner_world[0] + lift * corner_normal[0];
    vec3 c1 = corner_world[1] + lift * corner_normal[1] - c0, c2 = corner_world[2] + lift * corner_normal[2] - c0;
    // [c1 c2] = [du dv] [e1 e2]
    du = (c1 * e2.y - c2 * e1.y) / det + slope_du;
    dv = (c2 * e1.x - c1 * e2.x) / det + slope_dv;
    vec3 m = max(abs(du), abs(dv));
    return det != 0.0 && max(max(m.x, m.y), m.z) < 1e30;
}

// The colour map's level at the hit, as GL's isotropic filtering takes it for the pixel's
// footprint: the rays one pixel right and one up (offset at the hit's view depth, from the
// projection's focal lengths) meet the displaced surface's tangent plane through the hit
// (spanned by `t` = dS/du and `b` = dS/dv: layer_axes), and their points' offsets, in that
// frame, are the uv gradients (those of the reference's triangles there: a wall facing the eye is
// read sharp). The reference's colour is filtered by its triangles' implicit derivatives; the
// prism's, read at level 0, aliased in minified views
// (against the reference, with builtin:bricks for colour: the torus at 160x120 24.3 dB, now 29.7;
// the plane seen 8 degrees up 27.2, now 35.4; plane_and_torus.json 29.2, now 38.0).
// Implicit derivatives of the hit's uv are no use here: the walk's control flow leaves them
// undefined, and they jump at every edge of a bump. (Until the thirty-fourth session the plane
// was the shading's, of the vertices' averaged tangents: on the cube it leaned with the corner
// normals, read coarse levels, and past its horizon the texture's mean: checker 28.9 dB at
// constant height, found by an exploratory session.)
float hit_color_lod(vec3 hit, vec3 t_axis, vec3 b_axis)
{
    // In UV units: off = du t + dv b (off lies in the plane), by the 2x2 normal equations, all
    // over a power of two that brings the frame's largest component to [1, 2) (as frame_scale:
    // the determinant grows as the object's scale to the fourth, and overflowed past 1e9, which
    // read the coarsest level: found by a review).
    vec3 largest = max(abs(t_axis), abs(b_axis));
    float k = scale_to_unit(max(max(largest.x, largest.y), largest.z));
    t_axis *= k;
    b_axis *= k;
    vec3 n = cross(t_axis, b_axis);
    vec3 to_hit = hit - u_eye.xyz;
    float view_depth = -(u_view * vec4(hit, 1.0)).z;
    vec2 pixel = (2.0 * view_depth) * u_viewport.zw / vec2(u_proj[0][0], u_proj[1][1]); // world, at the hit's depth
    vec3 ray_x = to_hit + pixel.x * vec3(u_view[0][0], u_view[1][0], u_view[2][0]);
    vec3 ray_y = to_hit + pixel.y * vec3(u_view[0][1], u_view[1][1], u_view[2][1]);
    float along = dot(to_hit, n);
    // Grazing: a ray past the plane's horizon (or along it) has no footprint there: the coarsest level.
    if (!(dot(ray_x, n) * along > 0.0 && dot(ray_y, n) * along > 0.0)) return 64.0;
    vec3 off_x = (ray_x * (along / dot(ray_x, n)) - to_hit) * k;
    vec3 off_y = (ray_y * (along / dot(ray_y, n)) - to_hit) * k;
    float tt = dot(t_axis, t_axis), tb = dot(t_axis, b_axis), bb = dot(b_axis, b_axis);
    float det = tt * bb - tb * tb;
    vec2 px = vec2(dot(off_x, t_axis), dot(off_x, b_axis)), py = vec2(dot(off_y, t_axis), dot(off_y, b_axis));
    vec2 size = vec2(textureSize(s_color, 0)) / det;
    vec2 dx = vec2(bb * px.x - tb * px.y, tt * px.y - tb * px.x) * size;
    vec2 dy = vec2(bb * py.x - tb * py.y, tt * py.y - tb * py.x) * size;
    float texels = max(dot(dx, dx), dot(dy, dy)); // squared
    // (A degenerate frame: inf or NaN; the coarsest level.)
    return texels < 1e30 ? 0.5 * log2(max(texels, 1e-30)) : 64.0;
}

void main()
{
    // A sample within the hit tolerance over the surface is a hit (the caps at constant heights
    // 0 and 1, which rays graze within rounding); a ray that passes over a wall's top within it
    // hits the wall, a band along it PR_PRISM_HIT_EPSILON of the height range wide. Where that is
    // wider than a quarter of a pixel at this fragment (a --depth far larger than the relief the
    // map uses, or a close-up), the tolerance is that quarter, down to 1e-6 of the range, above the
    // rounding of the ray's height (a map using 448/65535 of its range under --depth 150 drew a
    // band along its steps and a plane's open edge: 202 outline pixels wrong against a reference
    // of level 64, IoU 0.963; found by an exploratory session, forty-first). Measured at the
    // fragment, on the shell's outside (the walk from the eye draws on the far plane, where the
    // tolerance stays 1e-4, as before).
    {
        float view_depth = max(-(u_view * vec4(v_world, 1.0)).z, 0.0);
        float pixel = 2.0 * view_depth * u_viewport.w / max(u_proj[1][1], 1e-30); // world, at the entry
        g_hit_epsilon = clamp(0.25 * pixel / max(u_displace.x, 1e-30), 1e-6, PR_PRISM_HIT_EPSILON);
    }
    // (With PR_PRISM_FOLDED_WALL_ID on a folded prism's wall: prism.geom.)
    uint prim = uint(gl_PrimitiveID) & ~uint(PR_PRISM_FOLDED_WALL_ID);
    bool from_a[3];
    // The hit's triangle: uv, world normals, object-space tangents dP/du and dP/dv per vertex.
    vec2 frame_uv[3];
    vec3 frame_n[3], frame_t[3], frame_b[3];
#ifndef PR_PRISM_WALK
    BaseVertex bv[3];
    load_prism(prim, bv, from_a);
    for (int i = 0; i < 3; ++i) {
        frame_uv[i] = bv[i].uv;
        frame_n[i] = mat3(u_normal_matrix) * bv[i].normal;
        frame_t[i] = bv[i].tangent;
        frame_b[i] = bv[i].bitangent;
    }
#endif

    // The ray is eye + t * dir with t = 1 at this fragment (the entry).
    vec3 dir = v_world - u_eye.xyz;
#ifndef PR_PRISM_WALK
    // A shell thinner than 1e-4 of the eye's distance (--depth 0, or nearly; a hundredth of a
    // pixel at 45 degrees and 1000 pixels): the displaced surface is the base triangle within
    // that, and the hit is the entry. Marched, such a prism gave a black or empty image: its
    // faces coincide within rounding, so the exact exit found none beyond the entry's slack
    // (t > 1 + 1e-5) and the vertex exit's texture-space distances divided by a thickness of 0.
    float thickness = max(max(distance(corner_world[0], corner_world[3]), distance(corner_world[1], corner_world[4])),
                          distance(corner_world[2], corner_world[5]));
    bool thin = thickness < 1e-4 * length(dir);
#endif
    float t_in = 1.0, t_out = 1.0;
    vec3 tex_in = v_tex, tex_out = v_tex;
    vec3 bend = vec3(0.0); // of the hit segment's path in texture space (path_bend)
    bool marched_linear = false; // max-mip's hit segment marched linearly (under a tear)
    float s;
#ifdef PR_PRISM_WALK
    // Only the shell's outside is rasterized (prism.geom); from there the ray goes from prism to
    // prism through the side it leaves by, until it meets the height field or leaves the shell.
    s = -1.0;
    // Tears (closed meshes with UV seams: PR_PRISM_TEARS): where the two sides of a seam give
    // the edge different heights, the displaced surface is torn. A ray that crosses the seam
    // under the far side's surface goes on *below* it (g_height_flip), as the true surface lets
    // it; if it leaves through the bottom into the object, its pixel is marked, and a second pass
    // (PR_PRISM_INSIDE) starts at the far side's bottoms, from inside, where marked.
    bool below = false;
    bool went_in = false; // into the object through a tear (marked after the walk, not in its loop)
#ifdef PR_PRISM_INSIDE
    if (imageLoad(u_tears, ivec2(gl_FragCoord.xy)).r == 0u) discard;
    below = true;
#endif
#ifdef PR_PRISM_EYE_UNDER
    below = true; // the eye is under the surface (inside a bump): the walk from it starts there
#endif
    Segment hit_segment; // the last segment marched; br.hit when the walk found the surface in it
    hit_segment.br.hit = false;
    // The last sample the march took: the first of the next segment, unless `pending` (the
    // first segment, whose first sample the march takes itself, or one after a UV seam).
    vec3 last = vec3(0.0);
    bool pending = true;
    // A ray that leaves through a top cap may go into the neighbour's prism through the
    // neighbour's top: where the shell's top folds away from the eye, the rasterizer gives a
    // pixel on or near the shared edge to one cap only, possibly the one facing away, which is
    // not drawn, or (caps seen edge-on, slivers of a pixel) to neither. The walk tries the
    // neighbour across the top's nearest edge and keeps to it only if the ray does enter its top,
    // at the exit or after it (`via_top`, checked by the neighbour's exit pass). Never into the
    // prism it came from (`came_from`), which it has left: where a ray out through a side leaves
    // the neighbour's top near that side, the two took turns (their faces meet within the exits'
    // tolerances) to the walk's limit of prisms: 2 pixels of the cube at 1280x720, 1 of the
    // rock, and on the H200 those few walks of 266 prisms took 30 % of the cube's frame.
    bool via_top = false;
    uint came_from = 0xffffffffu;
    int hops = 0; // across tops the ray did not go into, since the last exit (below)
    const int kTopHops = 4;
#if !defined(PR_PRISM_FROM_EYE) && !defined(PR_PRISM_INSIDE) && !defined(PR_PRISM_EYE_UNDER)
#define PR_PRISM_TOP_RETRY
    // The fragment's top, where the ray crosses its plane a little outside the triangle (the
    // rasterizer snaps the cap's corners): the first pass finds no face crossed and takes the
    // nearest plane, which finds the way out nearly always. Where that walk finds no way out at
    // all, it starts again from the fragment's prism (`retry` 2), and goes on across the top's
    // nearest edge, as if it had come over that edge (the rock at 192x144 from 15 degrees,
    // azimuth 35: a see-through pinhole at (135, 66)). 0: not so; 1: so, not yet retried; 3:
    // retried. (Not where it leaves the shell through a top, as most misses near an outline
    // do: restarting those cost 8-11 % of the rock's frame on llvmpipe.)
    int retry = 0;
#endif
    // Each pass loads its prism first: what goes from one pass to the next is the prism's number
    // and where the ray comes in (`entry_edge`, `entry_along`, at height tex_out.z), not the
    // prism's corners — llvmpipe keeps every value that crosses the loop's back edge for all
    // lanes, and the prism's 45 values there cost more than loading it again. (The hit prism is
    // loaded once more after the walk, for the frame.)
    int entry_edge = -1;
    float entry_along = 0.0;
#ifdef PR_PRISM_FROM_EYE
    // The walk from the eye (prism_eye.vert): it starts in the prism that holds the eye, at the
    // eye (t = 0), whose place in that prism's texture space the renderer found.
    if (u_march.z < 0) discard;
    prim = uint(u_march.z);
    t_in = 0.0;
    tex_in = u_eye_tex.xyz;
    tex_out = tex_in;
#endif
    // A ray that crosses more prisms than u_walk.x without a hit is dropped: it runs almost
    // parallel to a very finely tessellated surface (docs/prism.md). The renderer allows 256
    // and twice the most prisms around one vertex, which a ray passing the vertex may cross.
    for (int k = 0; k < u_walk.x; ++k) {
        count_prism();
        load_walk_prism(prim, from_a);
        if (entry_edge >= 0) {
            tex_in = entry_point(entry_edge, entry_along, tex_out.z);
            pending = at_seam(tex_in, tex_out);
        }
        bool top_entry;
        vec3 w_top;
        // Where no face is crossed (in the first prism the rasterizer's snapped edge put the
        // fragment a little outside its face; later, the ray came in where the shell folds),
        // the nearest of the faces' planes (shell.glsl), which on a convex prism still finds the
        // way out.
        int entry_face = entry_edge < 0 ? -1 : (via_top ? 0 : 2 + entry_edge);
        float t_min = t_in * (1.0 - 1e-6);
#ifdef PR_PRISM_FROM_EYE
        // The eye may lie on a face of its prism (a mesh's symmetry plane, say): a ray that goes
        // out through that face crosses it at t = 0, give or take rounding. So the exits count
        // from a little behind the eye (the faces the ray goes in through never count), in the
        // first prism and in every one the ray enters still at the eye: on a prism's edge (the
        // normal line of a vertex: a cube seen along its diagonal, a sphere's pole from above) a
        // ray crosses several prisms around it at t = 0, and lost its way after the first
        // (speckles; garbage at the pole).
        float behind = 1e-4 * distance(corner_world[0], corner_world[3]) / length(dir);
        if (k == 0 || t_in <= behind) t_min = -behind;
#endif
        ExitFace ex = nearest_exit(u_eye.xyz, dir, t_min, from_a, 1e-5, walk_orientation, t_in, entry_face, top_entry, w_top);
        bool lost = ex.face < 0;
        bool hop = via_top && !top_entry;
#ifdef PR_PRISM_TOP_RETRY
        if (k == 0 && g_top_entering && !top_entry && abs(g_top_entry_t - t_in) <= 1e-4 * t_in) retry = 1;
        if (retry == 2) {
            hop = true;
            retry = 3;
            // (Where it crosses the top's plane, at the fragment: the neighbour's entry height.)
            tex_out = corner_tex[3] * w_top.x + corner_tex[4] * w_top.y + corner_tex[5] * w_top.z;
        }
#endif
        if (hop) {
            // It does not go in there. Where it goes in through the top's plane beyond one of
            // its edges, it may go in through the top across that edge: near a vertex, the top
            // it left and the one it goes into need not share an edge (the rock at midlevel 0:
            // a ray that left one top near a vertex went in just beyond the neighbour's edge,
            // and the pixel was a pinhole). Tried across the edge beyond which it crosses (the
            // top's nearest edge, as from the top it left), a few times around the vertex.
            lost = true;
            float hop_lambda;
            int hop_edge = top_exit_edge(w_top, hop_lambda);
            uvec3 hop_across = prism_across;
            uint next = hop_edge == 0 ? hop_across.x : (hop_edge == 1 ? hop_across.y : hop_across.z);
            if (g_top_entering && hops < kTopHops && next != 0xffffffffu && next >> 2u != came_from) {
                ++hops;
                via_top = true;
                came_from = prim;
                prim = next >> 2u;
                entry_edge = int(next & 3u);
                entry_along = clamp(1.0 - hop_lambda, 0.0, 1.0);
                continue;
            }
        }
#ifdef PR_PRISM_TOP_RETRY
        if (ex.face < 0 && retry == 1) { // (not a ray that leaves the shell through a top: most misses)
            retry = 2;
            prim = uint(gl_PrimitiveID) & ~uint(PR_PRISM_FOLDED_WALL_ID);
            came_from = 0xffffffffu;
            entry_edge = -1;
            via_top = false;
            hops = 0;
            t_in = 1.0; // (the pass hops or ends the walk: it marches nothing)
            pending = true;
            below = false;
            continue;
        }
#endif
        if (lost) break; // a miss
        bool moved = via_top && g_top_entry_t > t_in;
        if (moved) {
            // In through the top further on (the caps' planes part at their shared edge, and a
            // grazing ray crosses the gap outside the shell): the segment starts there, its first
            // sample its own (not the last one of the prism before, across the gap). The exits
            // counted from the old start: one before the new start (only the planes' fallback
            // could give it, the ray being outside the prism until then) has lost the way.
            t_in = g_top_entry_t;
            tex_in = corner_tex[3] * w_top.x + corner_tex[4] * w_top.y + corner_tex[5] * w_top.z;
            pending = true;
            if (ex.t < t_in) break;
        }
        t_out = ex.t;
        tex_out = vec3(ex.tex.xy, clamp(ex.tex.z, 0.0, 1.0));
        // Where the ray goes if the march finds no hit: out through a side into its neighbour,
        // or through the top towards the neighbour across its nearest edge (which the next pass
        // checks); through a bottom, or a side without a neighbour, it leaves the shell. (Found
        // before the march, so that the top's weights need not live through it.)
        float lambda = ex.lambda;
        int edge = ex.face >= 2 ? ex.face - 2 : (ex.face == 0 ? top_exit_edge(w_top, lambda) : -1);
        // (At a seam on a torn mesh the march decides `below`: it takes the sample there.)
#ifdef PR_PRISM_OPEN_ENTRY
        // An open mesh's walls (and the other faces of its listed prisms): a ray that comes in
        // under the surface goes on under it (the sheet has no body there), decided by the
        // first sample, as at a seam.
        bool decide = pending && (entry_edge >= 0 || k == 0) && !moved;
#elif defined(PR_PRISM_TEARS)
        // And from a folded prism's wall (prism.geom): the ray may come out of a tear's crack,
        // under this side's surface. Taken to be over it, it hit at once: a tight shell's folded
        // slivers at a cylinder's rim drew the cap there, where the reference sees into the crack
        // (docs/prism.md, item 9).
        bool decide = pending && (entry_edge >= 0 || (k == 0 && (uint(gl_PrimitiveID) & uint(PR_PRISM_FOLDED_WALL_ID)) != 0u)) && !moved;
#else
        bool decide = pending && entry_edge >= 0 && !moved;
#endif
        // (Not where it came in through a top: it is over the heights there, and a sample on the
        // top, where a height may equal it, could turn it under them.)
        // The march's ends at their true places in the prism's texture space (the faces' planar
        // texture coordinates, which the walk keeps to go from prism to prism, are only near
        // them: prism_tex_at), and its path the parabola with the true path's slopes there.
        // (The march's first sample is still the last one before, taken at the prism before's
        // m_out: the same world point, in that prism's map, which the side's planar triangles
        // leave a fraction of a texel from this one's. A sample of its own here changed no metric
        // of the 256 x 256 views of docs/prism.md item 3, for a sample more per prism crossed.)
        bool keep_in = false;
#ifdef PR_PRISM_FROM_EYE
        // The eye's own place, as the renderer found it (and kept off the surface by twice the
        // hit tolerance: eye_prism.hpp).
        keep_in = k == 0;
#endif
        vec3 m_in = tex_in, m_out = tex_out;
        bend = true_ends(u_eye.xyz, dir, t_in, t_out, keep_in, m_in, m_out);
        hit_segment = march_segment(m_in, m_out, bend, last, pending, decide, below, last);
        if (hit_segment.br.hit) {
            tex_in = m_in;
            tex_out = m_out;
            break;
        }
        uvec3 across = prism_across;
        uint next = edge == 0 ? across.x : (edge == 1 ? across.y : (edge == 2 ? across.z : 0xffffffffu));
        if (ex.face == 0 && next >> 2u == came_from) next = 0xffffffffu;
        if (next == 0xffffffffu) {
            went_in = below && ex.face == 1; // out through a bottom from under the surface
            break;
        }
        via_top = ex.face == 0;
        hops = 0;
        came_from = prim;
        prim = next >> 2u;
        entry_edge = int(next & 3u);
        entry_along = clamp(1.0 - lambda, 0.0, 1.0); // the neighbour runs the edge the other way
        t_in = t_out;
    }
    // The hit prism again (corners, uv and normals for the frame below).
    load_walk_prism(prim, from_a);
// (Not in the second pass itself, nor in the walks from inside the body, which start at the
// same bottoms the second pass would, nor on an open mesh, which has no inside: such a ray has
// left the sheet.)
#if defined(PR_PRISM_TEARS) && !defined(PR_PRISM_INSIDE) && !(defined(PR_PRISM_EYE_UNDER) && defined(PR_PRISM_BOTTOMS)) && \
    !defined(PR_PRISM_OPEN_ENTRY)
    if (went_in) {
        imageStore(u_tears, ivec2(gl_FragCoord.xy), uvec4(1u));
        imageStore(u_tear_tiles, ivec2(gl_FragCoord.xy) / PR_TEAR_TILE, uvec4(1u));
    }
#endif
    // The hit, refined once, under the surface if the walk was there.
#ifdef PR_PRISM_TEARS
    g_height_flip = below ? 1.0 : 0.0;
    s = refine_segment(hit_segment, segment_ray(below ? vec3(tex_in.xy, 1.0 - tex_in.z) : tex_in,
                                                below ? vec3(tex_out.xy, 1.0 - tex_out.z) : tex_out,
                                                below ? vec3(bend.xy, -bend.z) : bend));
    g_height_flip = 0.0;
#else
    s = refine_segment(hit_segment, segment_ray(tex_in, tex_out, bend));
#endif
    marched_linear = hit_segment.linear;
    // The frame at the hit (below): uv and normals of the hit prism, tangents from the vertex
    // buffer (two of a vertex's four texels).
    uvec3 index = triangle_indices(prim);
    for (int i = 0; i < 3; ++i) {
        frame_uv[i] = corner_tex[i].xy;
        frame_n[i] = corner_normal[i];
        frame_t[i] = vertex_texel(index[i], 2).xyz;
        frame_b[i] = vertex_texel(index[i], 3).xyz;
    }
#else
    bool below = false; // (read by the shadows below; the walk's own is declared above)
    if (thin) {
        s = 0.0;
    } else {
#ifdef PR_PRISM_EXIT_VERTEX
        // Interpolated distances to the texture-space prism's planes (prism.geom): the nearest is
        // the exit. Moving lambda along v_dir_tex moves lambda * dir in the world (same frame).
        float lambda = max(min(min(min(v_dist_sides.x, v_dist_sides.y), min(v_dist_sides.z, v_dist_sides.w)),
                               v_dist_top), 0.0);
        // Where the corners' frames differ much (the cube, whose welded normals are diagonal at
        // its corners), the interpolated distances run far past the prism: 5 % of the cube's
        // fragments marched to the loop's cap of 1025 samples, whatever --steps said (found by
        // an exploratory session, forty-sixth). So no further than where the ray is a shell's
        // thickness past the slab [0, 1] (p95 1025 -> 200 there; bounded at the slab itself,
        // the torus's frame took 15 % longer with the same samples per fragment).
        float slab = v_dir_tex.z < 0.0 ? (v_tex.z + 1.0) / -v_dir_tex.z
                                       : v_dir_tex.z > 0.0 ? (2.0 - v_tex.z) / v_dir_tex.z : lambda;
        lambda = min(lambda, slab);
        t_out = 1.0 + lambda;
        tex_out = v_tex + lambda * v_dir_tex;
#else
        prism_exit(dir, v_tex, from_a, t_out, tex_out);
        // Marched along the ray's own path between its true places, as the walk's (item 3 of
        // docs/prism.md; the entry is at t = 1).
        bend = true_ends(u_eye.xyz, dir, t_in, t_out, false, tex_in, tex_out);
#endif
        vec3 last;
        s = refine_segment(march_segment(tex_in, tex_out, bend, vec3(0.0), true, false, below, last),
                           segment_ray(tex_in, tex_out, bend));
        // These exits keep the slab (docs/prism.md item 12): a ray that comes in through a bottom
        // cap (from under an open sheet) is under the surface there and hits at its entry, and
        // what it shows is the surface's back: shaded as the walk shades a back (the normal
        // turned; the light's march through the field turned over). It was shaded as the front:
        // the plane seen from below, lit from above, came out lit where the reference is dark
        // (4.8 dB, now 47; found by an exploratory session, thirty-fifth). A bottom cap of an
        // open mesh only: walls entered under the surface are the slab's own, and a closed
        // mesh's bottoms show only from inside its body, through the cracks and holes these
        // exits leave (the vertex exit's on creases), where its images stay as they were.
        below = s >= 0.0 && tex_in.z < 1e-4 && tex_out.z > tex_in.z && (u_march.w & PR_FLAG_OPEN_SHELL) != 0;
    }
#endif
    if (s < 0.0) {
        count_fragment();
        discard;
    }
    vec3 tex = mix(tex_in, tex_out, s);
    vec3 curve = (4.0 * s * (1.0 - s)) * bend; // the path's parabola (march/linear.glsl)
#if PR_MARCHER == PR_MARCH_MAX_MIP
    // (Max-mip's two straight halves, march_segment.)
    if (!marched_linear) curve = (s < 0.5 ? 2.0 * s : 2.0 - 2.0 * s) * bend;
#endif
    tex += curve;
    vec3 hit = u_eye.xyz + mix(t_in, t_out, s) * dir;

    // Frame at the hit: barycentrics of its uv in the base triangle's uv triangle, or, where that
    // has no area (every uv on a line or at a point), of the hit itself in the prism's layer at its
    // height: the centre stood in for it, and such a triangle was shaded as one flat facet (an
    // open cylinder whose u is one number: 33 dB against the reference, 92 with proper uvs;
    // found by an exploratory session, thirty-sixth).
    vec3 w;
    if (!uv_weights(tex.xy, frame_uv[0], frame_uv[1], frame_uv[2], w)) w = layer_weights(hit, tex.z);
    vec3 n = normalize(frame_n[0] * w.x + frame_n[1] * w.y + frame_n[2] * w.z);
    vec3 t_axis = mat3(u_model) * (frame_t[0] * w.x + frame_t[1] * w.y + frame_t[2] * w.z);
    vec3 b_axis = mat3(u_model) * (frame_b[0] * w.x + frame_b[1] * w.y + frame_b[2] * w.z);
    UvGrad g = UvGrad(vec2(0.0), vec2(0.0));
    vec3 surface_du, surface_dv; // dS/du, dS/dv of the displaced surface at the hit
    vec3 shading_n = height_normal_frame(tex.xy, t_axis, b_axis, n, u_displace.x, surface_du, surface_dv);
    // The colour's footprint frame, while corner_world and the rest are still the hit prism's (the
    // light's walk below loads the prisms it crosses: the level was measured on the last of those;
    // found by a review).
    vec3 lod_du = surface_du, lod_dv = surface_dv;
    {
        vec3 layer_du, layer_dv;
        if (layer_axes(tex.z, surface_du - t_axis, surface_dv - b_axis, layer_du, layer_dv))
            lod_du = layer_du, lod_dv = layer_dv;
    }
    if (below) shading_n = -shading_n; // the back of the surface (through a tear; the slab's bottom)
    vec3 light_dir = normalize(u_light_dir.xyz);
    float visibility = 1.0;
#ifdef PR_SHADOWS
    if (dot(shading_n, light_dir) > 0.0) {
        // (Soft: a ray for each strip of the disc, shadow.glsl; `visibility` is each one's offset
        // across the disc, summed as the strips' shares in `lit`.)
        float lit = 0.0;
        int strips = soft_strips();
        TextureFrame light_frame = texture_frame(t_axis, b_axis, n, u_displace.x);
#ifdef PR_PRISM_WALK
        // (The hit prism's flags: shell.glsl's load_walk_prism reads the same texel.)
        bool frame_differs = (texelFetch(t_prisms, int(8u * prim) + 7).w & PR_PRISM_FRAME_DIFFERS) != 0u;
#endif
        for (int k = 0; k < strips; ++k) {
            vec3 strip = soft_strip(k, strips);
            vec3 ray_dir = soft_strip_dir(light_dir, n, strip);
            vec3 l_tex = light_in_texture_space(light_frame, ray_dir);
            // The back of the surface (`below`): under an open mesh's sheet is open space, lit from
            // that side; the light's march goes through the height field turned over (heights
            // 1 - h, the point's height and the light's rise turned too: g_height_flip), in the
            // hit's frame only (no walk). Under a closed mesh's surface is its body (the back is
            // seen through a tear, or from an eye inside a bump), which the light does not reach.
            // (Until the twenty-second session the back was never shadowed: the bundled plane seen
            // from below, under a light from below, 17.9 dB against the reference, which shadows
            // it.)
            vec3 from = tex;
            // The back of a closed mesh's surface (seen through a tear, or from an eye inside a
            // bump): its body is under it, and the texture plane's march does not light it.
            bool dark_back = false, turned = false;
#if defined(PR_PRISM_TEARS) || !defined(PR_PRISM_WALK)
            turned = below && (u_march.w & PR_FLAG_OPEN_SHELL) != 0;
            dark_back = below && !turned;
            if (turned) {
                from.z = 1.0 - from.z;
                l_tex = turned_light(l_tex);
                g_height_flip = 1.0;
#ifndef PR_PRISM_WALK
                // The slab's hit is its bottom cap (1 turned over: over every height): the march
                // starts on the surface's back at that uv, or nothing ever shaded it (found by a
                // review, thirty-fifth session).
                from.z = height_at(from.xy, g);
#endif
            }
#endif
#if PR_MARCHER == PR_MARCH_LINEAR || PR_MARCHER == PR_MARCH_RELIEF
            // The linear marcher's hit, interpolated between the samples on either side of the
            // surface, lies inside a steep wall: straight up from there the wall blocked a light
            // overhead (430 of 8712 pixels of builtin:boxes, on walls facing the eye). The light
            // march starts on the surface at that uv, as the cone marchers' does (shadow.glsl). The
            // relief marcher's, the middle of its last bracket, may lie inside one too: a soft
            // light within 0.01 degrees of the normal, whose march goes on under the surface, found
            // the wall over it and darkened 500 more wall pixels of builtin:boxes than the cone
            // marchers (twenty-third session; a lift of at most a few brackets' heights fixed a
            // part of them only).
            from.z = max(from.z, height_at(from.xy, g));
#endif
            // (Not for the back of a closed mesh: below.)
            visibility = dark_back ? 0.0 : light_visibility(from, l_tex, g);
#if defined(PR_PRISM_TEARS) || !defined(PR_PRISM_WALK)
            g_height_flip = 0.0;
#endif
#ifdef PR_PRISM_WALK
            // Where the texture plane around the hit shades it, the walk through the mesh's prisms
            // says whether the mesh does (light_walk): it takes away the shadows of heights no
            // triangle shows and of bumps the curved surface holds below the ray, and adds none. On
            // its own it added false ones: its exits' texture coordinates, interpolated on the flat
            // side triangles, lie up to 0.035 under a curved prism's surface, and a hit next to a
            // side face was blocked by its own first sample (dashed lines along the triangles'
            // diagonals in close-ups); past its limit of prisms a grazing light's shadows stopped
            // short on fine meshes; folded prisms (--midlevel 1) streaked (found by an exploratory
            // session). Where a neighbour's texture frame differs from the hit prism's (a crease, a
            // change of UV scale, a seam: frame_differs, set on the CPU), the texture plane is no
            // guide to the mesh, and the walk's answer stands, shadow or light: the UV sphere's
            // bumps above 60 degrees of latitude, where u narrows row by row, lost the tops of
            // their shadows (seen from over the pole, 26.4 -> 34.9 dB against the reference),
            // the cube's by its edges (25.3 -> 32.3; thirty-ninth session, found by an
            // exploratory session). The torus and the plane have no such prisms; on the rock and
            // the sphere 10-16 % of the frame with shadows.
            // (Soft: never above the part of the disc over the base surface's horizon,
            // which the march in the hit's frame counts and the walk does not; so only where that
            // march found less light than the horizon leaves.) The walk follows the ray the march
            // took: a soft light's raised over the horizon where its centre is under it
            // (soft_light_ray, which sets its offset and slope again; walked along the light's own,
            // which goes under the surface, a light a hair under the horizon brought back the
            // shadows of the map's wrapped copy past an open mesh's edge that one a hair over it
            // took away: 133 pixels of the plane's edge, found by a review). A light whose centre
            // is under the base surface's horizon, which the march in the hit's frame takes for
            // blocked (hard) or dims to the part of the disc over that horizon (soft), is walked
            // along its own ray too: a wall or a bump that stands out of a curved surface near its
            // terminator sees the light over the surface falling away, as the reference does (boxes
            // on the rock, hard: PSNR 21.0 -> 24.3; on the UV sphere, 192x144, light 1,0.2,-0.3:
            // hard 22.3 -> 27.3, soft 22.7 -> 28.5). On a flat sheet that ray goes under a bottom
            // cap and the light stays off; past an open sheet's edge it is on, as for the
            // reference. (Until the twenty-fourth session such walls were black.) For hard shadows
            // that is the walk above (l_walk is l_tex, horizon 1); a soft light's walk along its
            // own ray only adds light, and is not bounded by the flat horizon.
            vec3 l_walk = soft_light_ray(l_tex);
            float horizon = soft_horizon(l_walk);
            // The back of a closed mesh's surface, seen through a tear (the walk went under the
            // surface at a seam): not lit through the texture plane, whose heights turned over
            // stand for the body, but by the light's walk from under the surface, which goes out
            // through the tear's crack or meets the body (light_walk), along the light's own ray.
            // From the surface at the hit's uv, as above: the linear marchers' hit lies inside the
            // bracket, here under the surface. (Dark whatever the light until the forty-first
            // session. The same call as the front's below: a second copy of the walk cost about a
            // tenth of a shadowed frame on the blob on llvmpipe.)
#ifdef PR_PRISM_TEARS
            bool back = dark_back;
#else
            bool back = false;
#endif
            // The back of an open sheet (`turned`): where the march through the heights turned
            // over, in the hit's frame, finds shadow, the walk from under the surface says whether
            // the sheet casts it; its march met the map's copies that the texture plane wraps past
            // the sheet's open edge, as a front's does (a ramp's wrapped cliff seen from under the
            // plane's edge was left at the ambient level where the reference's light comes in
            // under the edge: 201 pixels, 38.5 dB without shadows and 21.6 with; found by an
            // exploratory session, fiftieth). It only takes shadow away, and only where the march
            // found the light blocked: the walk from under the surface leaves through a bottom
            // cap into the open space under the sheet with no soft light's run past it, so a
            // penumbra that the march found it would light (boxes seen and lit from under the
            // plane, soft: 40.5 -> 35.8 dB against the reference).
            bool open_back = turned && visibility <= 0.0;
            if (back || open_back || (!below && (frame_differs || visibility < horizon))) {
                // (The open back's slope, turned for its march, back to the light's own: the walk
                // turns it where it goes under the surface.)
                if (open_back) turned_light(l_tex);
                if (back || open_back) soft_light_own_ray();
                vec3 walk_dir = back || open_back || l_walk == l_tex
                                    ? ray_dir
                                    : unit_vector(t_axis * l_walk.x + b_axis * l_walk.y + n * (u_displace.x * l_walk.z));
                vec3 walk_from = back || open_back ? vec3(tex.xy, min(tex.z, height_at(tex.xy, g))) : from;
                float walked = light_walk(prim, walk_from, hit, walk_dir, back || open_back);
                if (back)
                    visibility = max(walked, 0.0);
                else if (walked >= 0.0 && open_back) // (along the light's own ray: no flat horizon bounds it)
                    visibility = max(visibility, walked);
                else if (walked >= 0.0)
                    visibility = frame_differs ? min(walked, horizon) : max(visibility, min(walked, horizon));
            }
#if PR_SHADOWS == PR_SHADOWS_SOFT
            // Where the disc is partly under the base surface's horizon, its centre under it or
            // less than its radius over it: the walk along the light's own ray, not bounded by
            // that horizon. (Only where the centre was under it until the fiftieth session: a
            // light 1e-7 over the plane's horizon darkened the bumps' flanks facing it to about
            // half, 25.8 dB against the reference where a light at 0 gave 40.5; found by an
            // exploratory session.)
            if (!below && horizon < 1.0) {
                soft_light_own_ray();
                visibility = max(visibility, light_walk(prim, from, hit, ray_dir, false));
            }
#endif
#endif
            lit += strip_share(strip, visibility);
        }
        visibility = lit;
    }
#endif
    count_fragment();
    vec3 albedo = u_base_color.rgb;
    if (has_color_texture()) {
        // (textureLod with that level: llvmpipe's textureGrad with the gradients cost more.)
        albedo = textureLod(s_color, tex.xy, hit_color_lod(hit, lod_du, lod_dv)).rgb;
    }
    o_color = vec4(shade_blinn_phong(albedo, shading_n, light_dir, -unit_vector(dir), visibility), 1.0);
    vec4 clip = u_view_proj * vec4(hit, 1.0);
#ifdef PR_PRISM_FROM_EYE
    if (clip.z > clip.w) discard; // between the eye and the near plane (or behind the eye): clipped, as geometry is
#endif
    gl_FragDepth = clamp(clip.z / clip.w, 0.0, gl_FragCoord.z);
}
