// Cone and relaxed-cone maps, one invocation per texel (docs/cone-maps.md). This is the CPU
// generator of src/maps/conemap.cpp (class Searcher, relaxed_constraint) line for line, in double
// precision with `precise` (no fused multiply-add), so both give the same integer steps k: every
// comparison is monotone, the bound of a quadtree node never exceeds the constraint of a texel
// inside it, so pruning never changes the rounded minimum and the visiting order does not matter.
// PR_CONE_KIND: 0 cone (conservative at texel centres), 1 relaxed (GPU Gems 3, ch. 18).
#ifndef PR_CONE_KIND
#define PR_CONE_KIND 0
#endif
#define PR_CONE_MAX_LEVELS 16
#define PR_CONE_STACK 72

layout(local_size_x = 64) in;

// Max pyramid (maps::MaxPyramid): all levels, level 0 = the height texels, bottom row first.
layout(std430, binding = 0) readonly buffer Pyramid { float b_pyramid[]; };
// Result: the ratio in format steps k (ratio = k / u_steps), one per texel.
layout(std430, binding = 1) writeonly buffer Steps { uint b_steps[]; };

layout(location = 0) uniform ivec2 u_size;  // texels
layout(location = 1) uniform int u_levels;  // pyramid levels (the last is 1x1)
layout(location = 2) uniform int u_steps;   // 255 or 65535
layout(location = 3) uniform uint u_first;  // first texel of this dispatch
layout(location = 4) uniform uint u_count;  // texels in this dispatch
layout(location = 5) uniform int u_budget;  // kind relaxed: march steps per texel (ConeBuildOptions)
layout(location = 6) uniform int u_node_budget; // nodes per search (ConeBuildOptions::node_budget)
layout(location = 8) uniform int u_level_w[PR_CONE_MAX_LEVELS];
layout(location = 24) uniform int u_level_h[PR_CONE_MAX_LEVELS];
layout(location = 40) uniform int u_level_offset[PR_CONE_MAX_LEVELS];

const double kMargin = 1.0lf - 1.0lf / 1048576.0lf; // 1 - 2^-20, exact

float node_max(int level, int i, int j) { return b_pyramid[u_level_offset[level] + j * u_level_w[level] + i]; }
float height_at(int x, int y) { return b_pyramid[y * u_size.x + x]; }

// GLSL leaves % of negative operands undefined: only non-negative ones here.
int wrap_index(int i, int n)
{
    return i >= 0 ? i % n : n - 1 - (-1 - i) % n;
}

double steps_squared(int k)
{
    return double(uint(k) * uint(k)) / double(uint(u_steps) * uint(u_steps));
}

int ratio_steps(double c)
{
    if (!(c < 1.0lf)) return u_steps;
    if (!(c > 0.0lf)) return 0;
    precise double target = c * kMargin;
    int k = clamp(int(floor(sqrt(target) * double(u_steps))), 0, u_steps);
    while (k < u_steps && steps_squared(k + 1) <= target) ++k;
    while (k > 0 && steps_squared(k) > target) --k;
    return k;
}

int axis_distance(int p, int a, int b, int n)
{
    if (p >= a && p <= b) return 0;
    if (p < a) return min(a - p, p + n - b);
    return min(p - b, a + n - p);
}

int signed_offset(int d, int n)
{
    d = wrap_index(d, n);
    return 2 * d > n ? d - n : d;
}

#if PR_CONE_KIND == 1
double bilinear(double x, double y)
{
    precise double x0 = floor(x), y0 = floor(y);
    precise double fx = x - x0, fy = y - y0;
    int xi = int(x0), yi = int(y0);
    int ix = xi >= 0 && xi < u_size.x ? xi : wrap_index(xi, u_size.x);
    int iy = yi >= 0 && yi < u_size.y ? yi : wrap_index(yi, u_size.y);
    int ix1 = ix + 1 == u_size.x ? 0 : ix + 1, iy1 = iy + 1 == u_size.y ? 0 : iy + 1;
    double h00 = double(height_at(ix, iy)), h10 = double(height_at(ix1, iy));
    double h01 = double(height_at(ix, iy1)), h11 = double(height_at(ix1, iy1));
    precise double a = h00 + (h10 - h00) * fx;
    precise double b = h01 + (h11 - h01) * fx;
    precise double r = a + (b - a) * fy;
    return r;
}

// maps::relaxed_constraint with a budget: the ray from p's column at height 1 through q's surface
// point, one texel per step past q, on bilinear heights; its value where it leaves the surface,
// or +inf (returned as -1) when it reaches h_p or passes `stop` first; out of budget, a lower
// bound (the value at the last step, else `lower`).
double relaxed_constraint(int px, int py, int dx, int dy, double stop, inout int budget, double lower)
{
    double hp = double(height_at(px, py));
    double hq = double(height_at(wrap_index(px + dx, u_size.x), wrap_index(py + dy, u_size.y)));
    if (!(hq > hp) || (dx == 0 && dy == 0)) return -1.0lf;
    precise double inv_len = 1.0lf / sqrt(double(dx * dx + dy * dy));
    precise double tq = sqrt(double(dx * dx) / (double(u_size.x) * double(u_size.x)) +
                             double(dy * dy) / (double(u_size.y) * double(u_size.y)));
    precise double drop = 1.0lf - hq;
    int max_steps = 2 * (u_size.x + u_size.y);
    for (int k = 1; k <= max_steps; ++k) {
        if (budget <= 0) return lower;
        --budget;
        precise double lambda = 1.0lf + double(k) * inv_len;
        precise double z = 1.0lf - lambda * drop;
        if (!(z > hp)) return -1.0lf;
        precise double along = lambda * tq;
        precise double limit = stop * (z - hp);
        if (along >= limit) return -1.0lf;
        precise double value = along / (z - hp);
        lower = value;
        precise double sx = double(px) + lambda * double(dx);
        precise double sy = double(py) + lambda * double(dy);
        if (bilinear(sx, sy) < z) return value;
    }
    return -1.0lf;
}
#endif

// A node packed in one uint (level: 4 bits, i and j: 14 bits each; sizes are at most 16384), so
// the stack is two private arrays, not four: llvmpipe turns each dynamically indexed private
// array access into a per-lane loop.
uint s_node[PR_CONE_STACK];
uint pack_node(int level, int i, int j) { return uint(level) << 28 | uint(i) << 14 | uint(j); }
double s_bound[PR_CONE_STACK];

// maps::Searcher::rest_bound: min(c, the bound of every node on the stack that could still lower
// the result), the ratio when a budget stops the search early.
double rest_bound(double c, double threshold, int sp)
{
    for (int r = 0; r < sp; ++r)
        if (s_bound[r] * kMargin < threshold) c = min(c, s_bound[r]);
    return c;
}

// maps::Searcher::search: the ratio of texel (px, py) in format steps, for cones or relaxed cones.
int search(int px, int py, bool relaxed)
{
    float hp = height_at(px, py);
    int top = u_levels - 1;
    if (!(hp < node_max(top, 0, 0))) return u_steps;
    precise double inv_w2 = 1.0lf / (double(u_size.x) * double(u_size.x));
    precise double inv_h2 = 1.0lf / (double(u_size.y) * double(u_size.y));
    int k = u_steps;
    double best = 1.0lf;
    double threshold = 1.0lf;
    int budget = u_budget;
    s_node[0] = pack_node(top, 0, 0); s_bound[0] = 0.0lf;
    int sp = 1;
    int visits = 0;
    while (sp > 0 && k > 0) {
        if (++visits > u_node_budget) {
            double rest = rest_bound(best, threshold, sp);
            if (rest < best) k = ratio_steps(rest);
            break;
        }
        --sp;
        uint node = s_node[sp];
        int level = int(node >> 28), ni = int((node >> 14) & 0x3fffu), nj = int(node & 0x3fffu);
        double nbound = s_bound[sp];
        if (nbound * kMargin >= threshold) continue;
        if (level == 0) {
            double c = nbound;
#if PR_CONE_KIND == 1
            if (relaxed) {
                c = relaxed_constraint(px, py, signed_offset(ni - px, u_size.x), signed_offset(nj - py, u_size.y),
                                       threshold / kMargin * (1.0lf + 1e-9lf), budget, nbound);
                if (c < 0.0lf) c = 1e300lf;
                if (budget <= 0) {
                    c = rest_bound(c, threshold, sp);
                    sp = 0;
                }
            }
#endif
            if (c < best) {
                best = c;
                k = ratio_steps(best);
                threshold = steps_squared(k);
            }
            continue;
        }
        int cl = level - 1;
        int cw = u_level_w[cl], ch = u_level_h[cl];
        // Children, smallest bound on top of the stack (insertion into the pushed run).
        int base = sp;
        for (int cj = 2 * nj; cj < min(2 * nj + 2, ch); ++cj)
            for (int ci = 2 * ni; ci < min(2 * ni + 2, cw); ++ci) {
                precise double dmax = double(node_max(cl, ci, cj)) - double(hp);
                if (!(dmax > 0.0lf)) continue;
                int x0 = ci << cl, y0 = cj << cl;
                int x1 = min((ci + 1) << cl, u_size.x) - 1, y1 = min((cj + 1) << cl, u_size.y) - 1;
                int dx = axis_distance(px, x0, x1, u_size.x), dy = axis_distance(py, y0, y1, u_size.y);
                precise double bound = sqrt(double(dx * dx) * inv_w2 + double(dy * dy) * inv_h2) / dmax;
                if (bound * kMargin >= threshold) continue;
                // Keep [base, sp) sorted by decreasing bound.
                int at = sp;
                while (at > base && s_bound[at - 1] < bound) {
                    s_node[at] = s_node[at - 1];
                    s_bound[at] = s_bound[at - 1];
                    --at;
                }
                s_node[at] = pack_node(cl, ci, cj); s_bound[at] = bound;
                ++sp;
            }
    }
    return k;
}

void main()
{
    uint index = gl_GlobalInvocationID.x;
    if (index >= u_count) return;
    uint texel = u_first + index;
    int px = int(texel % uint(u_size.x)), py = int(texel / uint(u_size.x));
    int k = search(px, py, false);
#if PR_CONE_KIND == 1
    k = max(k, search(px, py, true));
#endif
    b_steps[texel] = uint(k);
}
