// Cone and relaxed-cone maps, one invocation per texel (docs/cone-maps.md). This is the search of
// the CPU generator (src/maps/conemap.cpp, class Searcher, relaxed_constraint), node for node in
// the same order but without its stack (below), in double precision with `precise` (no fused
// multiply-add), so both give the same integer steps k: every comparison is monotone, the bound
// of a quadtree node never exceeds the constraint of a texel inside it, so pruning never changes
// the rounded minimum, and where a budget stops a search early both stop at the same node.
// PR_CONE_KIND: 0 cone (conservative at texel centres), 1 relaxed (GPU Gems 3, ch. 18).
#ifndef PR_CONE_KIND
#define PR_CONE_KIND 0
#endif
#define PR_CONE_MAX_LEVELS 16

layout(local_size_x = 64) in;

// Max pyramid (maps::MaxPyramid): all levels, level 0 = the height texels, bottom row first.
// The same maxima grouped by parent: for each level l below the top, one vec4 per node of level
// l + 1 with its four children's maxima (order x + 2 y; -1 for a child outside the map), so that
// a node's children come in one load (render/conemap_gpu.cpp).
// Both as buffer textures (r32f, rgba32f), where they fit: llvmpipe fetches a texel for all
// lanes at once and loads a storage buffer one lane and one component at a time; as storage
// buffers where they do not (PR_CONE_BUFFERS: more texels than GL_MAX_TEXTURE_BUFFER_SIZE).
#ifdef PR_CONE_BUFFERS
layout(std430, binding = 0) readonly buffer Pyramid { float b_pyramid[]; };
layout(std430, binding = 2) readonly buffer Groups { vec4 b_groups[]; };
float pyramid_at(int i) { return b_pyramid[i]; }
vec4 group_at(int i) { return b_groups[i]; }
#else
layout(binding = 0) uniform samplerBuffer t_pyramid;
layout(binding = 1) uniform samplerBuffer t_groups;
float pyramid_at(int i) { return texelFetch(t_pyramid, i).r; }
vec4 group_at(int i) { return texelFetch(t_groups, i); }
#endif
// Result: the ratio in format steps k (ratio = k / u_steps), one per texel; where a search ran
// out of nodes, bit 31 (the cone search) or 30 (the relaxed search) set, k then the other
// search's (0 where both ran out), and the search's state in b_resume.
layout(std430, binding = 1) writeonly buffer Steps { uint b_steps[]; };
// The searches that ran out of nodes, where the CPU goes on with them (save_search; read by
// render/conemap_gpu.cpp as maps::ConeSearchState): b_resume_count counts them all, the first
// u_resume_capacity are written, kResumeWords words each.
layout(std430, binding = 3) buffer Resume { uint b_resume_count; uint b_resume[]; };
const uint kResumeWords = 17u;
// The seeds (maps::ConeSeeds): the texel that set the cone of every fourth texel of every fourth
// row, written by the seed passes (u_seeding), where every search then starts; kind relaxed, the
// relaxed seeds after them (from u_seed_size.x * u_seed_size.y on). Each as x | y << 16 (the map
// has at most 32768 texels a side): llvmpipe divides integers lane by lane.
layout(std430, binding = 4) buffer Seeds { uint b_seeds[]; };
const int kSeedShift = 2, kCoarseSeedShift = 4; // maps::kSeedShift, maps::kCoarseSeedShift
const uint kNoSeed = 0xffffffffu;               // maps::kNoConeSeed

layout(location = 0) uniform ivec2 u_size;  // texels
layout(location = 1) uniform int u_levels;  // pyramid levels (the last is 1x1)
layout(location = 2) uniform int u_steps;   // 255 or 65535
layout(location = 3) uniform uint u_first;  // first texel of this dispatch
layout(location = 4) uniform uint u_count;  // texels in this dispatch
layout(location = 5) uniform int u_budget;  // kind relaxed: march steps per texel (ConeBuildOptions)
layout(location = 6) uniform int u_node_budget; // nodes per search (ConeBuildOptions::node_budget)
layout(location = 7) uniform uint u_resume_capacity; // entries b_resume holds
layout(location = 8) uniform int u_level_w[PR_CONE_MAX_LEVELS];
layout(location = 24) uniform int u_level_h[PR_CONE_MAX_LEVELS];
layout(location = 40) uniform int u_level_offset[PR_CONE_MAX_LEVELS];
layout(location = 56) uniform int u_group_offset[PR_CONE_MAX_LEVELS]; // children of level l + 1's nodes
layout(location = 72) uniform ivec2 u_seed_size; // the seeds' grid
// 0: this dispatch searches texels; 2: the coarse seeds (u_first and u_count count them), 1: the
// others (they count all the grid's seeds: the coarse ones, found already, return at once).
layout(location = 73) uniform int u_seeding;
layout(location = 74) uniform int u_seed_relaxed; // 1: the seed passes find the relaxed seeds
// 1: the texel dispatches' lanes take the texels in blocks of 4 x 2 (u_size.x a multiple of 4,
// u_size.y even; u_first a multiple of 2 u_size.x), 0: in rows. Neighbours search alike, and
// llvmpipe runs eight lanes at a time until the longest search of the eight ends.
layout(location = 75) uniform int u_blocks;
// The texel dispatches' pieces (pairs of rows with u_blocks, else runs of 64 texels) go to the
// groups in the order piece * u_spread modulo the dispatch's whole pieces (u_spread coprime to
// their count; 1: in order). llvmpipe gives each of its threads one contiguous share of a
// dispatch's groups, and a dispatch ends when the costliest share does: spread like this, each
// share takes rows from all over the dispatch, and the shares cost alike (render/conemap_gpu.cpp,
// spread_step).
layout(location = 76) uniform uint u_spread;

const double kMargin = 1.0lf - 1.0lf / 1048576.0lf; // 1 - 2^-20, exact

float node_max(int level, int i, int j) { return pyramid_at(u_level_offset[level] + j * u_level_w[level] + i); }
float height_at(int x, int y) { return pyramid_at(y * u_size.x + x); }
// The maxima of node (level, i, j)'s four children (level >= 1).
vec4 children_max(int level, int i, int j) { return group_at(u_group_offset[level - 1] + j * u_level_w[level] + i); }

// i modulo n in [0, n) (n > 0, any i). Without %: x86 has no vector integer division, so llvmpipe
// divides lane by lane (the relaxed march wraps its candidates' offsets; its samples wrap in the
// sampler, bilinear). The quotient from
// a double product with 1/n, corrected by one either way (|i| < 2^31, so the product is off by
// far less than one), gives the exact remainder. (A double division there instead, each call:
// the relaxed GPU build of builtin:bumps@512 about 5 % slower on llvmpipe, the same map.)
int wrap_index(int i, int n)
{
    int q = int(floor(double(i) * (1.0lf / double(n))));
    int r = i - q * n;
    r += r < 0 ? n : 0;
    r -= r >= n ? n : 0;
    return r;
}

double steps_squared(int k)
{
    return double(k) * double(k) / (double(u_steps) * double(u_steps)); // (exact products)
}

// maps::cone_ratio_steps: the ratio c in format steps k, and its threshold steps_squared(k) (a
// candidate lowers k only where its c * kMargin is under it). floor(sqrt(target) * steps) is off
// from the real product by under 2e-11 of a step (double precision, k <= 65535), so it can miss
// the CPU's k only where that product is that close to a whole number n, and then both are n - 1
// or n: one correction each way gives what the CPU's loops give. The three squares are computed
// up front (llvmpipe runs every branch for all lanes anyway; the threshold is one of them): with
// two corrections each way and the threshold computed apart, relaxed builds took 2-5 % longer.
int ratio_steps(double c, out double threshold)
{
    if (!(c < 1.0lf)) {
        threshold = 1.0lf;
        return u_steps;
    }
    if (!(c > 0.0lf)) {
        threshold = 0.0lf;
        return 0;
    }
    precise double target = c * kMargin;
    int k = clamp(int(floor(sqrt(target) * double(u_steps))), 0, u_steps);
    double at = steps_squared(k), above = steps_squared(k + 1), below = steps_squared(k - 1);
    if (k < u_steps && above <= target) {
        threshold = above;
        return k + 1;
    }
    if (k > 0 && at > target) {
        threshold = below;
        return k - 1;
    }
    threshold = at;
    return k;
}

int ratio_steps(double c)
{
    double threshold;
    return ratio_steps(c, threshold);
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
// Level 0 as a 2D texture (render/conemap_gpu.cpp), repeating: one textureGather at the corner
// between texels (x0, y0) and (x0 + 1, y0 + 1) brings the four, wrapped.
layout(binding = 2) uniform sampler2D t_heights;

double bilinear(double x, double y)
{
    precise double x0 = floor(x), y0 = floor(y);
    precise double fx = x - x0, fy = y - y0;
    // Gather order: x = (0, 1), y = (1, 1), z = (1, 0), w = (0, 0).
    vec4 q = textureGather(t_heights, (vec2(x0, y0) + 1.0) / vec2(u_size), 0);
    double h00 = double(q.w), h10 = double(q.z);
    double h01 = double(q.x), h11 = double(q.y);
    precise double a = h00 + (h10 - h00) * fx;
    precise double b = h01 + (h11 - h01) * fx;
    precise double r = a + (b - a) * fy;
    return r;
}

// maps::relaxed_constraint with a budget: the least over the level ray at h_q and the ray from
// p's column at height 1, both through q's surface point, one texel per step past q, on bilinear
// heights; each ray's value when it leaves the surface is its value at the last step still in it
// (`at_q`, q's cone constraint, at first); a ray that reaches h_p, or whose value passes `stop`
// first, sets none; none at all is +inf (returned as -1); out of budget, a lower bound.
double relaxed_constraint(int px, int py, int dx, int dy, double stop, inout int budget, double at_q)
{
    double hp = double(height_at(px, py));
    double hq = double(height_at(wrap_index(px + dx, u_size.x), wrap_index(py + dy, u_size.y)));
    if (!(hq > hp) || (dx == 0 && dy == 0)) return -1.0lf;
    precise double inv_len = 1.0lf / sqrt(double(dx * dx + dy * dy));
    precise double tq = sqrt(double(dx * dx) / (double(u_size.x) * double(u_size.x)) +
                             double(dy * dy) / (double(u_size.y) * double(u_size.y)));
    int max_steps = 2 * (u_size.x + u_size.y);
    // The level ray (infinite `level` is -1 as the result is).
    precise double inside = at_q;
    precise double level = -1.0lf;
    for (int k = 1; k <= max_steps; ++k) {
        if (budget <= 0) return at_q;
        --budget;
        precise double lambda = 1.0lf + double(k) * inv_len;
        precise double sx = double(px) + lambda * double(dx);
        precise double sy = double(py) + lambda * double(dy);
        if (bilinear(sx, sy) < hq) {
            level = inside;
            break;
        }
        precise double along = lambda * tq;
        precise double limit = stop * (hq - hp);
        if (along >= limit) break;
        inside = along / (hq - hp);
    }
    // The ray from height 1, which counts below the level ray's value only.
    if (level >= 0.0lf) stop = min(stop, level);
    precise double drop = 1.0lf - hq;
    inside = at_q;
    for (int k = 1; k <= max_steps; ++k) {
        if (budget <= 0) return level >= 0.0lf ? min(inside, level) : inside;
        --budget;
        precise double lambda = 1.0lf + double(k) * inv_len;
        precise double z = 1.0lf - lambda * drop;
        if (!(z > hp)) return level;
        precise double sx = double(px) + lambda * double(dx);
        precise double sy = double(py) + lambda * double(dy);
        if (bilinear(sx, sy) < z) return level >= 0.0lf ? min(inside, level) : inside;
        precise double along = lambda * tq;
        precise double limit = stop * (z - hp);
        if (along >= limit) return level;
        inside = along / (z - hp);
    }
    return level;
}
#endif

// The search without a stack. It visits the quadtree depth first, children in the CPU's order
// (smallest bound first; equal bounds: the later child in row order first), so the nodes left to
// visit are, at every level below the root, the not yet visited children of the node visited
// last at the level above: at most four, whose order and count pack into 11 bits (3 bits count,
// then 2 bits per child, the next one lowest). The node a list belongs to is an ancestor of the
// node visited last, so its place follows by a shift, and a child's bound is recomputed when it
// is visited (the same operations, so the same value). Nodes are visited in the CPU's order and
// counted as it counts them, so even a search stopped by the node budget gives the same result.
// (llvmpipe turns each access to a private array whose index varies per lane into a loop over
// the lanes: one list read and one write per node visited, instead of a sorted stack of
// doubles.)
uint s_list[PR_CONE_MAX_LEVELS];

// Lower bound of node (level, i, j), whose maximum is `nmax`, for texel p: its nearest texel's
// distance over its rise above h_p; -1 when it has no texel above h_p.
double node_bound(int level, int i, int j, float nmax, int px, int py, float hp, double inv_w2, double inv_h2)
{
    // The rise in the format's height steps, as the map stores R (src/maps/conemap.cpp, rise():
    // cone_height_steps, lround of the float product; floor(x + 0.5) is that for x < 2^23).
    precise float kn = floor(clamp(nmax, 0.0, 1.0) * float(u_steps) + 0.5);
    precise float kp = floor(clamp(hp, 0.0, 1.0) * float(u_steps) + 0.5);
    precise double dmax = double(int(kn) - int(kp)) / double(u_steps);
    if (!(dmax > 0.0lf)) return -1.0lf;
    int x0 = i << level, y0 = j << level;
    int x1 = min((i + 1) << level, u_size.x) - 1, y1 = min((j + 1) << level, u_size.y) - 1;
    int dx = axis_distance(px, x0, x1, u_size.x), dy = axis_distance(py, y0, y1, u_size.y);
    precise double bound = sqrt(double(dx * dx) * inv_w2 + double(dy * dy) * inv_h2) / dmax;
    return bound;
}

// The list of node (level, i, j)'s children (level - 1) that may lower the result, in visiting order.
uint child_list(int level, int i, int j, int px, int py, float hp, double inv_w2, double inv_h2, double threshold)
{
    int cl = level - 1;
    int cw = u_level_w[cl], ch = u_level_h[cl];
    vec4 cmax = children_max(level, i, j);
    double b[4];
    bool ok[4];
    for (int q = 0; q < 4; ++q) {
        int ci = 2 * i + (q & 1), cj = 2 * j + (q >> 1);
        ok[q] = ci < cw && cj < ch;
        b[q] = ok[q] ? node_bound(cl, ci, cj, cmax[q], px, py, hp, inv_w2, inv_h2) : -1.0lf;
        ok[q] = ok[q] && b[q] >= 0.0lf && b[q] * kMargin < threshold;
    }
    uint list = 0u, count = 0u;
    for (int q = 0; q < 4; ++q) {
        // Its place: the children that come before it.
        uint rank = 0u;
        for (int r = 0; r < 4; ++r)
            if (r != q && ok[r] && (b[r] < b[q] || (b[r] == b[q] && r > q))) ++rank;
        if (ok[q]) {
            list |= uint(q) << (3u + 2u * rank);
            ++count;
        }
    }
    return list | count;
}

// maps::Searcher::rest_bound: min(c, the bound of every node left to visit that could still
// lower the result), the ratio when a budget stops the search early: the lists of the levels in
// `filled`; the node visited last is (m, li, lj), and every list belongs to one of its ancestors.
double rest_bound(double c, double threshold, uint filled, int top, int m, int li, int lj, int px, int py, float hp,
                  double inv_w2, double inv_h2)
{
    for (int level = 0; level < top; ++level) {
        if ((filled & (1u << level)) == 0u) continue;
        uint list = s_list[level];
        int pi = li >> (level + 1 - m), pj = lj >> (level + 1 - m);
        vec4 cmax = children_max(level + 1, pi, pj);
        for (uint n = 0u; n < (list & 7u); ++n) {
            int q = int((list >> (3u + 2u * n)) & 3u);
            double b = node_bound(level, 2 * pi + (q & 1), 2 * pj + (q >> 1), cmax[q], px, py, hp, inv_w2, inv_h2);
            if (b * kMargin < threshold) c = min(c, b);
        }
    }
    return c;
}

// Where the node budget ran out: the search's state, for the CPU's search to go on from (best
// first, maps::Searcher::resume). Words: texel, relaxed, filled, the node visited last (level, i,
// j), best (two words), march steps left, the lists of levels 0-7 (two to a word: 16 bits each).
void save_search(uint texel, bool relaxed, uint filled, int m, int li, int lj, double best, int budget)
{
    uint e = atomicAdd(b_resume_count, 1u);
    if (e >= u_resume_capacity) return; // the CPU searches this texel again from the start
    uint at = e * kResumeWords;
    uvec2 b = unpackDouble2x32(best);
    b_resume[at] = texel;
    b_resume[at + 1u] = relaxed ? 1u : 0u;
    b_resume[at + 2u] = filled;
    b_resume[at + 3u] = uint(m);
    b_resume[at + 4u] = uint(li);
    b_resume[at + 5u] = uint(lj);
    b_resume[at + 6u] = b.x;
    b_resume[at + 7u] = b.y;
    b_resume[at + 8u] = uint(budget);
    for (int l = 0; l < PR_CONE_MAX_LEVELS; l += 2)
        b_resume[at + 9u + uint(l / 2)] = (s_list[l] & 0xffffu) | (s_list[l + 1] << 16u);
}

// Takes the next node to visit off the lists (depth first, the CPU's order): it becomes the node
// visited last (m, li, lj); its parent is (pi, pj) one level up, q its place there.
void pop_next(inout uint filled, inout int m, inout int li, inout int lj, out int pi, out int pj, out int q)
{
    int cur = findLSB(filled);
    uint list = s_list[cur];
    q = int((list >> 3u) & 3u);
    s_list[cur] = ((list & 7u) - 1u) | ((list >> 5u) << 3u);
    if ((list & 7u) == 1u) filled &= ~(1u << cur);
    int shift = cur + 1 - m;
    pi = li >> shift;
    pj = lj >> shift;
    li = 2 * pi + (q & 1);
    lj = 2 * pj + (q >> 1);
    m = cur;
}

// pop_next, and the bound of the node it takes (recomputed: the CPU's stack holds it).
double pop_bounded(inout uint filled, inout int m, inout int li, inout int lj, int px, int py, float hp, double inv_w2,
                   double inv_h2)
{
    int pi, pj, q;
    pop_next(filled, m, li, lj, pi, pj, q);
    return node_bound(m, li, lj, children_max(m + 1, pi, pj)[q], px, py, hp, inv_w2, inv_h2);
}

// Lists the children of node (m, li, lj) (m >= 1) that may lower the result, to visit next.
void push_children(int m, int li, int lj, int px, int py, float hp, double inv_w2, double inv_h2, double threshold,
                   inout uint filled)
{
    uint children = child_list(m, li, lj, px, py, hp, inv_w2, inv_h2, threshold);
    s_list[m - 1] = children;
    if ((children & 7u) != 0u) filled |= 1u << (m - 1);
}

// maps::Searcher::seeded_best: the least constraint on texel p of the seeds of the four seed
// texels around it on the grid of every 2^shift-th texel, capped at 1 (`which`: the seed that
// gave it, else unchanged), computed as node_bound computes a texel's; `relaxed`, of the relaxed
// seeds, each marched (relaxed_constraint) only where its cone constraint could lower the result,
// within the march budget; where that runs out, the seeds marched before count.
double seeded_best(int px, int py, float hp, int shift, bool relaxed, inout int budget, double inv_w2, double inv_h2,
                   inout uint which)
{
    int spacing = 1 << shift, stride = 1 << (shift - kSeedShift);
    int base = relaxed ? u_seed_size.x * u_seed_size.y : 0;
    int gw = (u_size.x + spacing - 1) >> shift, gh = (u_size.y + spacing - 1) >> shift;
    int gx = px >> shift, gy = py >> shift;
    double best = 1.0lf;
    for (int q = 0; q < 4; ++q) {
        int sx = gx + (q & 1), sy = gy + (q >> 1);
        sx = sx < gw ? sx : 0;
        sy = sy < gh ? sy : 0;
        uint t = b_seeds[base + sy * stride * u_seed_size.x + sx * stride];
        if (t == kNoSeed) continue;
        int tx = int(t & 0xffffu), ty = int(t >> 16u);
        double c = node_bound(0, tx, ty, height_at(tx, ty), px, py, hp, inv_w2, inv_h2);
        if (!(c >= 0.0lf)) continue;
#if PR_CONE_KIND == 1
        if (relaxed) {
            double threshold;
            ratio_steps(best, threshold);
            if (!(c * kMargin < threshold)) continue;
            c = relaxed_constraint(px, py, signed_offset(tx - px, u_size.x), signed_offset(ty - py, u_size.y),
                                   threshold / kMargin * (1.0lf + 1e-9lf), budget, c);
            if (c < 0.0lf) c = 1e300lf;
            if (budget <= 0) break; // (a lower bound only)
        }
#endif
        if (c < best) {
            best = c;
            which = t;
        }
    }
    return best;
}

// maps::Searcher::search: the ratio of texel (px, py) in format steps, for cones or relaxed cones.
// `ran_out_of_nodes` is set where the node budget ran out: the CPU's search goes on best first
// from there (save_search; render/conemap_gpu.cpp); `ran_out_of_steps` where the relaxed march
// budget did. `seeding` (maps::Searcher::seed_of): 2 and 1, a search from nothing (2) or from the
// coarse seeds (1) that only finds `argmin`, the texel (x | y << 16) whose constraint set the
// result (kNoSeed for none), stopping where the node budget runs out; 0, a texel's search, from
// the seeds.
int search(int px, int py, bool relaxed, int seeding, out bool ran_out_of_nodes, out bool ran_out_of_steps,
           out uint argmin)
{
    ran_out_of_nodes = false; // (an out parameter is undefined until written: the early return below)
    ran_out_of_steps = false;
    argmin = kNoSeed;
    float hp = height_at(px, py);
    int top = u_levels - 1;
    if (!(hp < node_max(top, 0, 0))) return u_steps;
    precise double inv_w2 = 1.0lf / (double(u_size.x) * double(u_size.x));
    precise double inv_h2 = 1.0lf / (double(u_size.y) * double(u_size.y));
    int budget = u_budget;
    double best = seeding == 2 ? 1.0lf
                               : seeded_best(px, py, hp, seeding == 1 ? kCoarseSeedShift : kSeedShift, relaxed, budget,
                                             inv_w2, inv_h2, argmin);
    double threshold;
    int k = ratio_steps(best, threshold);
    // The root is the first node visited (bound 0), and it is not a texel (the map has more
    // than one: a single texel is its own maximum and returned above).
    int visits = 1;
    int m = top, li = 0, lj = 0; // the node visited last
    s_list[top - 1] = child_list(top, 0, 0, px, py, hp, inv_w2, inv_h2, threshold);
    uint filled = (s_list[top - 1] & 7u) != 0u ? 1u << (top - 1) : 0u; // levels whose list is not empty
    // Out of a budget: what is left counts by its lower bounds (after the loop, which llvmpipe
    // runs in full for every lane: code in it costs on every pass).
    bool out_of_nodes = false;
    double out_of_steps = -1.0lf; // >= 0: the relaxed march budget ran out at this constraint
    double nbound;
    if (!relaxed) {
        // The cone search visits nodes in an inner loop until it comes to a texel to count, for
        // at most 16 passes, and counts it after that loop: llvmpipe runs every branch of a loop's
        // body for all lanes, and the count (steps in double precision) ran on every pass. Without
        // the bound of 16, lanes at a texel waited for the others' way down (`builtin:MAP@1024`,
        // s: pyramids 4.0-4.2 -> 4.3-4.4 unbounded, 2.7-2.8 with 16 (8: 2.9-3.1, 32: 2.7-2.9, 64:
        // 3.0-3.2), boxes 0.75 -> 0.57-0.61, bumps 2.2-2.3 -> 1.7-1.8). The relaxed search below
        // counts a texel on the pass that visits it: its long marches are most of its time, and
        // in such a loop ran 1.3-1.7 times as long (`builtin:MAP@512` with 1, 4 or 16 passes).
        while (k > 0 && filled != 0u) {
            bool at_texel = false;
            int passes = 0;
            while (!at_texel && filled != 0u && passes++ < 16) {
                if (++visits > u_node_budget) {
                    out_of_nodes = true;
                    break;
                }
                nbound = pop_bounded(filled, m, li, lj, px, py, hp, inv_w2, inv_h2);
                if (nbound * kMargin >= threshold) continue;
                if (m == 0)
                    at_texel = true;
                else
                    push_children(m, li, lj, px, py, hp, inv_w2, inv_h2, threshold, filled);
            }
            if (out_of_nodes) break;
            if (!at_texel) continue;
            if (nbound < best) {
                best = nbound;
                argmin = uint(li) | (uint(lj) << 16u);
                k = ratio_steps(best, threshold);
            }
        }
    }
#if PR_CONE_KIND == 1
    // A pass of the relaxed search lists the children of the next node where that is not a texel,
    // then marches the next node where that is one: the CPU's order, two nodes a pass where a
    // listing leads to a texel. llvmpipe runs both parts on every pass anyway (and the march on
    // nearly every one, for some lane: docs/cone-maps.md, "Where the lanes wait"); one node a
    // pass took 16-19 % more passes at 512^2 (`builtin:MAP@512`, counted on the CPU's order).
    // Alternated builds, two nodes a pass against one, the same maps: 1024^2 0.89-0.97 (bumps
    // 0.89, boxes 0.95, noise 0.97, pyramids 0.95, bricks 0.93), 512^2 0.90-1.05 (boxes 0.93,
    // bricks 0.90, bumps 1.00, noise 1.02, pyramids 1.05). Listing again after the march (three
    // nodes a pass): boxes 1.12, bumps 1.03.
    while (relaxed && k > 0 && filled != 0u) {
        if (findLSB(filled) != 0) {
            if (++visits > u_node_budget) {
                out_of_nodes = true;
                break;
            }
            nbound = pop_bounded(filled, m, li, lj, px, py, hp, inv_w2, inv_h2);
            if (nbound * kMargin < threshold) push_children(m, li, lj, px, py, hp, inv_w2, inv_h2, threshold, filled);
        }
        if (findLSB(filled) != 0) continue; // (none left, or not a texel)
        if (++visits > u_node_budget) {
            out_of_nodes = true;
            break;
        }
        nbound = pop_bounded(filled, m, li, lj, px, py, hp, inv_w2, inv_h2);
        if (nbound * kMargin >= threshold) continue;
        double c = relaxed_constraint(px, py, signed_offset(li - px, u_size.x), signed_offset(lj - py, u_size.y),
                                      threshold / kMargin * (1.0lf + 1e-9lf), budget, nbound);
        if (c < 0.0lf) c = 1e300lf;
        if (budget <= 0) {
            out_of_steps = c;
            break;
        }
        if (c < best) {
            best = c;
            argmin = uint(li) | (uint(lj) << 16u);
            k = ratio_steps(best, threshold);
        }
    }
#endif
    ran_out_of_nodes = out_of_nodes;
    ran_out_of_steps = out_of_steps >= 0.0lf;
    if (seeding != 0) return k;
    if (out_of_nodes) {
        save_search(uint(py) * uint(u_size.x) + uint(px), relaxed, filled, m, li, lj, best, budget);
    } else if (out_of_steps >= 0.0lf) {
        double rest = rest_bound(out_of_steps, threshold, filled, top, m, li, lj, px, py, hp, inv_w2, inv_h2);
        if (rest < best) k = ratio_steps(rest);
    }
    return k;
}

void main()
{
    uint index = gl_GlobalInvocationID.x;
    if (index >= u_count) return;
    uint argmin;
    bool cone_out = false, relaxed_out = false;
    if (u_seeding != 0) {
        // The coarse pass counts the coarse seeds (every stride-th of every stride-th row of the
        // grid), the other pass all of them.
        int stride = 1 << (kCoarseSeedShift - kSeedShift);
        int row = u_seeding == 2 ? (u_seed_size.x + stride - 1) / stride : u_seed_size.x;
        uint item = u_first + index;
        int sx = int(item % uint(row)), sy = int(item / uint(row));
        if (u_seeding == 2) {
            sx *= stride;
            sy *= stride;
        } else if ((sx & (stride - 1)) == 0 && (sy & (stride - 1)) == 0) {
            return; // (a coarse seed)
        }
        bool steps_out;
        search(sx << kSeedShift, sy << kSeedShift, u_seed_relaxed != 0, u_seeding, cone_out, steps_out, argmin);
        b_seeds[(u_seed_relaxed != 0 ? u_seed_size.x * u_seed_size.y : 0) + sy * u_seed_size.x + sx] = argmin;
        return;
    }
    uint piece = u_blocks != 0 ? 2u * uint(u_size.x) : 64u; // texels
    uint pieces = u_count / piece, at = index / piece;
    if (at < pieces) index = ((at * u_spread) % pieces) * piece + (index - at * piece);
    uint item = u_first + index;
    int px, py;
    if (u_blocks != 0) {
        uint pair = item / (2u * uint(u_size.x)), r = item - pair * 2u * uint(u_size.x);
        px = int((r >> 3u) * 4u + (r & 3u));
        py = int(pair * 2u + ((r >> 2u) & 1u));
    } else {
        px = int(item % uint(u_size.x));
        py = int(item / uint(u_size.x));
    }
    uint texel = uint(py) * uint(u_size.x) + uint(px);
#if PR_CONE_KIND == 1
    // maps::Searcher::search: the relaxed search, and the cone search for a floor only where a
    // budget cut the relaxed one short (a relaxed search run to its end is never below it). Where
    // one ran out of nodes, the low bits hold the other's k (or 0) and the CPU goes on with it.
    bool steps_out = false;
    int k = search(px, py, true, 0, relaxed_out, steps_out, argmin);
    if (relaxed_out) k = 0;
    if (relaxed_out || steps_out) {
        int kc = search(px, py, false, 0, cone_out, steps_out, argmin);
        k = max(k, cone_out ? 0 : kc);
    }
#else
    bool steps_out;
    int k = search(px, py, false, 0, cone_out, steps_out, argmin);
    if (cone_out) k = 0;
#endif
    b_steps[texel] = uint(k) | (cone_out ? 0x80000000u : 0u) | (relaxed_out ? 0x40000000u : 0u);
}
