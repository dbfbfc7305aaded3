// Max-pyramid traversal (quadtree displacement mapping: Tevs, Ihrke & Seidel 2008; Drobot 2009)
// with an exact ray / bilinear-patch intersection at the finest level. The pyramid bound to
// PR_TEX_CONE (src/render/renderer.cpp, make_max_pyramid_texture) holds, at level 0, the max of
// the 4 texels around each bilinear patch (patch (i, j) spans texel centres i..i+1, j..j+1,
// wrapping), and at level k the max over GL's floor(size / 2^k) cells, the last cell of a row
// taking the remainder. The ray skips every cell whose maximum it passes above; it descends
// into a cell it may touch, and at level 0 solves the quadratic z(t) = h(t) of the patch, so the
// hit needs no refinement. Coordinates: X = uv * size - 0.5 puts patch i at [i, i + 1).
#include "march/relief.glsl"
#include "march/patch.glsl"

#if defined(PR_MARCHER) && PR_MARCHER == PR_MARCH_MAX_MIP
layout(binding = PR_TEX_CONE) uniform sampler2D s_maxmip;

#ifndef PR_MAXMIP_MAX_ITERATIONS
#define PR_MAXMIP_MAX_ITERATIONS 1024
#endif

Bracket march_max_mip(MarchRay r)
{
    ivec2 size0 = textureSize(s_maxmip, 0);
    int top = textureQueryLevels(s_maxmip) - 1;
    vec2 scale = vec2(size0);
    // The texture repeats: whole repeats off the origin keep the coordinates small (UVs near 1000
    // put x near 500 000 texels, where the nudge below was lost to float rounding and the ray
    // stalled in a cell: IoU 0.64 and frames 17 times longer).
    vec2 x0 = (r.origin.xy - floor(r.origin.xy)) * scale - 0.5;
    vec2 dx = r.dir.xy * scale;
    // A nudge past a cell's border: a ten-thousandth of a cell (or of the ray), and at least a
    // few float steps of the largest coordinate the ray reaches (a segment across many repeats
    // of the texture: UVs 0..200 over one triangle).
    float reach = max(max(abs(x0.x), abs(x0.y)), max(abs(x0.x + r.t_end * dx.x), abs(x0.y + r.t_end * dx.y)));
    float step_t = 1.0 / max(max(abs(dx.x), abs(dx.y)), 1e-6);
    float float_step = reach / 8388608.0; // 2^-23 of it, in cells
    float eps_t = max(1e-4 * min(step_t, r.t_end), 4.0 * float_step * step_t);
    float t = 0.0;
    // It starts at the level whose cells are as long as the segment (a prism's segments span a few
    // texels): from the 1x1 top it took a fetch per level down to there, in each of the two
    // halves of every prism crossed (torus and rock, 1280x720: 65.86 and 61.86 height samples
    // per fragment from the top, 25.99 and 18.32 from here; the frame 40-45 % shorter).
    int level = clamp(int(ceil(log2(max(r.t_end * max(abs(dx.x), abs(dx.y)), 1.0)))), 0, top);
    for (int i = 0; i < PR_MAXMIP_MAX_ITERATIONS && t <= r.t_end; ++i) {
        vec2 x = x0 + t * dx;
        float z = r.origin.z + t * r.dir.z;
        ivec2 ix = ivec2(floor(x));
        ivec2 wrapped = ix - size0 * ivec2(floor(vec2(ix) / scale));
        ivec2 cells = max(size0 >> level, ivec2(1));
        ivec2 cell = min(wrapped >> level, cells - 1);
        vec2 tile = vec2(ix - wrapped);
        vec2 lo = tile + vec2(cell << level);
        vec2 hi = tile + vec2(cell.x == cells.x - 1 ? size0.x : (cell.x + 1) << level,
                              cell.y == cells.y - 1 ? size0.y : (cell.y + 1) << level);
        float t_leave = r.t_end;
        if (dx.x > 0.0) t_leave = min(t_leave, (hi.x - x0.x) / dx.x);
        if (dx.x < 0.0) t_leave = min(t_leave, (lo.x - x0.x) / dx.x);
        if (dx.y > 0.0) t_leave = min(t_leave, (hi.y - x0.y) / dx.y);
        if (dx.y < 0.0) t_leave = min(t_leave, (lo.y - x0.y) / dx.y);
        t_leave = max(t_leave, t);
        ++g_height_samples;
        float h_max = texelFetch(s_maxmip, cell, level).r;
        float z_leave = r.origin.z + t_leave * r.dir.z;
        if (min(z, z_leave) > h_max + PR_HIT_EPSILON) {
            // Above everything in this cell: go to the next one, one level coarser.
            if (t_leave >= r.t_end) break;
            t = min(t_leave + eps_t, r.t_end);
            level = min(level + 1, top);
            continue;
        }
        if (level > 0) {
            // A descending ray can first drop to the cell's maximum, but not past the cell: the
            // next one may be higher (that jump cost a pixel of the UV sphere at 512 px).
            if (r.dir.z < 0.0 && z > h_max) t = min(t + (z - h_max) / -r.dir.z, t_leave);
            --level;
            continue;
        }
        ++g_height_samples;
        // textureGather: x = (i0, j1), y = (i1, j1), z = (i1, j0), w = (i0, j0) around the patch.
        vec4 q = textureGather(s_height, (vec2(wrapped) + 1.0) / scale, 0);
        float th = patch_hit(vec4(q.w, q.z, q.x, q.y), x - vec2(ix), dx, z, r.dir.z, t_leave - t);
        if (th >= 0.0) return Bracket(true, t + th, t + th, 0.0, 0.0);
        if (t_leave >= r.t_end) break;
        // (Never past the end: a border within the nudge of it left the end untested, and a ray
        // that ends on the surface, a cap at height 0, lost its hit: a pixel of the rock at 512 px
        // once the traversal started lower, docs/cone-maps.md.)
        t = min(t_leave + eps_t, r.t_end);
        level = min(level + 1, top);
    }
    return Bracket(false, t, t, 0.0, 0.0);
}
#endif
