// Cone and relaxed-cone maps on the CPU (docs/cone-maps.md).
//
// For every texel p the generator looks for the texel q that limits p's cone: kind cone takes
// c = min over higher texels q of |q - p| / (h_q - h_p) (UV units, wrap-around distances), kind
// relaxed takes the min of relaxed_constraint() over the same texels. Both searches are
// branch-and-bound over a quadtree of maxima (MaxPyramid): a node whose maximum is not above h_p
// holds no candidate, and a node whose lower bound dist_min / (max - h_p) cannot lower the
// *rounded* result any more is skipped. The bound is a true lower bound for both kinds (the
// relaxed constraint of q is never below q's cone constraint), and every comparison is monotone in
// double precision, so the result is exactly the rounded minimum over all texels, whatever order
// the nodes are visited in: threads, the GPU path and the brute-force test agree bit for bit.
#include "maps/conemap.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>

namespace pr {

ConeKind parse_cone_kind(const std::string& name, const std::string& option)
{
    if (name == "cone") return ConeKind::Cone;
    if (name == "relaxed") return ConeKind::Relaxed;
    throw Error(option, "unknown cone-map kind '" + name + "' (expected cone or relaxed)");
}

std::string cone_kind_name(ConeKind kind) { return kind == ConeKind::Cone ? "cone" : "relaxed"; }

ConeFormat parse_cone_format(const std::string& name, const std::string& option)
{
    if (name == "rg8") return ConeFormat::Rg8;
    if (name == "rg16") return ConeFormat::Rg16;
    throw Error(option, "unknown cone-map format '" + name + "' (expected rg8 or rg16)");
}

std::string cone_format_name(ConeFormat format) { return format == ConeFormat::Rg8 ? "rg8" : "rg16"; }

std::string cone_map_label(ConeKind kind, const HeightField& field)
{
    return (kind == ConeKind::Relaxed ? "relaxed cone map of " : "cone map of ") +
           (field.name.empty() ? std::string("the height map") : field.name);
}

bool parse_cone_backend_gpu(const std::string& name, const std::string& option)
{
    if (name == "cpu") return false;
    if (name == "gpu") return true;
    throw Error(option, "unknown cone-map backend '" + name + "' (expected cpu or gpu)");
}

int cone_format_steps(ConeFormat format) { return format == ConeFormat::Rg8 ? 255 : 65535; }

std::uint32_t cone_height_steps(float h, ConeFormat format)
{
    return std::uint32_t(std::lround(std::clamp(h, 0.0f, 1.0f) * float(cone_format_steps(format))));
}

const HeightField& cone_source_field(const HeightField& field, ConeFormat format, HeightField& storage)
{
    if (format != ConeFormat::Rg8) return field;
    storage = field;
    storage.bits = 8;
    const float steps = float(cone_format_steps(format));
    for (float& t : storage.texels) t = float(cone_height_steps(t, format)) / steps; // as read_cone_png reads R
    return storage;
}

namespace {

// 1 - 2^-20: the relative margin on c (exact in double).
constexpr double kMargin = 1.0 - 1.0 / 1048576.0;

// (k / steps)^2 with one rounding.
double steps_squared(int k, int steps)
{
    return double(std::int64_t(k) * k) / double(std::int64_t(steps) * steps);
}

} // namespace

int cone_ratio_steps(double c, ConeFormat format)
{
    const int steps = cone_format_steps(format);
    if (!(c < 1.0)) return steps; // cap (and +inf: nothing above)
    if (!(c > 0.0)) return 0;
    const double target = c * kMargin;
    int k = std::clamp(int(std::floor(std::sqrt(target) * steps)), 0, steps);
    while (k < steps && steps_squared(k + 1, steps) <= target) ++k;
    while (k > 0 && steps_squared(k, steps) > target) --k;
    return k;
}

float cone_steps_to_ratio(int k, ConeFormat format)
{
    const double exact = double(k) / double(cone_format_steps(format));
    float r = float(exact);
    if (double(r) > exact) r = std::nextafter(r, 0.0f);
    return r;
}

std::uint32_t cone_ratio_to_steps(float ratio, ConeFormat format)
{
    return std::uint32_t(std::lround(std::clamp(ratio, 0.0f, 1.0f) * double(cone_format_steps(format))));
}

const std::vector<float>& cone_ratio_table(ConeFormat format)
{
    const auto make = [](ConeFormat f) {
        std::vector<float> table(std::size_t(cone_format_steps(f)) + 1);
        for (std::size_t k = 0; k < table.size(); ++k) table[k] = cone_steps_to_ratio(int(k), f);
        return table;
    };
    static const std::vector<float> rg8 = make(ConeFormat::Rg8);
    static const std::vector<float> rg16 = make(ConeFormat::Rg16);
    return format == ConeFormat::Rg8 ? rg8 : rg16;
}

std::vector<float> ratios_for_bilinear(const std::vector<float>& ratios, int width, int height)
{
    if (width <= 0 || height <= 0 || ratios.size() != std::size_t(width) * std::size_t(height))
        throw std::invalid_argument("ratios_for_bilinear: size mismatch");
    const std::size_t w = std::size_t(width), h = std::size_t(height);
    // Separable: the minimum over 3 texels along x (wrapping), then along y.
    std::vector<float> rows(ratios.size()), out(ratios.size());
    for (std::size_t y = 0; y < h; ++y)
        for (std::size_t x = 0; x < w; ++x) {
            const float* row = &ratios[y * w];
            rows[y * w + x] = std::min({row[(x + w - 1) % w], row[x], row[(x + 1) % w]});
        }
    for (std::size_t y = 0; y < h; ++y)
        for (std::size_t x = 0; x < w; ++x)
            out[y * w + x] = std::min({rows[((y + h - 1) % h) * w + x], rows[y * w + x], rows[((y + 1) % h) * w + x]});
    return out;
}

MaxPyramid build_max_pyramid(const HeightField& field)
{
    MaxPyramid p;
    int w = field.width, h = field.height;
    p.widths.push_back(w);
    p.heights.push_back(h);
    p.offsets.push_back(0);
    p.data.reserve(field.texels.size() + field.texels.size() / 2 + std::size_t(2 * (w + h)) + 64); // all levels
    p.data = field.texels;
    while (w > 1 || h > 1) {
        const int nw = (w + 1) / 2, nh = (h + 1) / 2;
        const std::size_t src = p.offsets.back();
        const std::size_t dst = p.data.size();
        p.data.resize(dst + std::size_t(nw) * std::size_t(nh));
        for (int j = 0; j < nh; ++j)
            for (int i = 0; i < nw; ++i) {
                float m = -std::numeric_limits<float>::infinity();
                for (int y = 2 * j; y < std::min(2 * j + 2, h); ++y)
                    for (int x = 2 * i; x < std::min(2 * i + 2, w); ++x)
                        m = std::max(m, p.data[src + std::size_t(y) * std::size_t(w) + std::size_t(x)]);
                p.data[dst + std::size_t(j) * std::size_t(nw) + std::size_t(i)] = m;
            }
        w = nw;
        h = nh;
        p.widths.push_back(w);
        p.heights.push_back(h);
        p.offsets.push_back(dst);
    }
    return p;
}

namespace {

int wrap(int i, int n)
{
    const int r = i % n;
    return r < 0 ? r + n : r;
}

// Bilinear height at texel-centre coordinates (x, y) (texel i's centre at i), repeat wrap. The
// operations and their order are those of shaders/conemap.comp.
double bilinear(const HeightField& f, double x, double y)
{
    const double x0 = std::floor(x), y0 = std::floor(y);
    const double fx = x - x0, fy = y - y0;
    const int xi = int(x0), yi = int(y0);
    const int ix = xi >= 0 && xi < f.width ? xi : wrap(xi, f.width);
    const int iy = yi >= 0 && yi < f.height ? yi : wrap(yi, f.height);
    const int ix1 = ix + 1 == f.width ? 0 : ix + 1, iy1 = iy + 1 == f.height ? 0 : iy + 1;
    const std::size_t w = std::size_t(f.width);
    const double h00 = f.texels[std::size_t(iy) * w + std::size_t(ix)];
    const double h10 = f.texels[std::size_t(iy) * w + std::size_t(ix1)];
    const double h01 = f.texels[std::size_t(iy1) * w + std::size_t(ix)];
    const double h11 = f.texels[std::size_t(iy1) * w + std::size_t(ix1)];
    const double a = h00 + (h10 - h00) * fx;
    const double b = h01 + (h11 - h01) * fx;
    return a + (b - a) * fy;
}

} // namespace

double relaxed_constraint(const HeightField& f, int px, int py, int dx, int dy, double stop, int& budget,
                          double at_q)
{
    constexpr double kNone = std::numeric_limits<double>::infinity();
    const double hp = f.texels[std::size_t(py) * std::size_t(f.width) + std::size_t(px)];
    const double hq = f.texels[std::size_t(wrap(py + dy, f.height)) * std::size_t(f.width) +
                               std::size_t(wrap(px + dx, f.width))];
    if (!(hq > hp) || (dx == 0 && dy == 0)) return kNone;
    const double inv_len = 1.0 / std::sqrt(double(dx * dx + dy * dy)); // steps of one texel
    const double tq = std::sqrt(double(dx * dx) / (double(f.width) * double(f.width)) +
                                double(dy * dy) / (double(f.height) * double(f.height))); // UV
    // Past q, one texel per step; at most the whole map twice over (the ray then has gone down
    // to h_p or its value passed `stop` long before on any sane map).
    const int max_steps = 2 * (f.width + f.height);
    // Two rays through q's surface point, each followed past q until it leaves the surface; the
    // value at its last step still in it (q's own at first) is its constraint. (A ray leaves the
    // surface somewhere between that step and the first one out of it, and so do the rays a hair
    // under it, which the family through the texels' centres leaves out: the value at the step
    // out let a cone reach up to a texel past a thin wall's far side, and a ray grazing the
    // wall's top crossed all of it in one step: a wall 4 texels thick in a 2048 map seen low over
    // the plane, 27 outline pixels wrong at 256 x 192 against the relief marcher's 4.) The ray from p's
    // column at height 1 is the relaxed cone's own (GPU Gems 3). The level one, at h_q, is the
    // limit of the rays that come in low: one a hair under it goes into whatever stands at h_q
    // there and out again where that ends. A cone wider than where it comes out lets such a ray
    // step over all of it: a ridge a texel thin and 0.3 high, seen low over the plane, lost its
    // top along a whole row (124 outline pixels wrong, against 3 with the relief marcher; the ray
    // from height 1 falls through such a ridge to h_p and set no constraint; found by an
    // exploratory session, thirtieth). Level first: it ends after a step or two but on plateaus.
    double inside = at_q;
    double level = kNone;
    for (int k = 1; k <= max_steps; ++k) {
        if (budget <= 0) return at_q; // (the other ray's value is not known: no more than its least)
        --budget;
        const double lambda = 1.0 + double(k) * inv_len;
        const double h = bilinear(f, double(px) + lambda * double(dx), double(py) + lambda * double(dy));
        if (h < hq) {
            level = inside;
            break;
        }
        if (lambda * tq >= stop * (hq - hp)) break; // (no smaller value follows: none)
        inside = (lambda * tq) / (hq - hp);
    }
    // The ray from height 1. Its value counts below the level ray's only: that is its `stop`.
    stop = std::min(stop, level);
    const double drop = 1.0 - hq; // height lost per unit of lambda (lambda = 1 at q)
    inside = at_q;
    for (int k = 1; k <= max_steps; ++k) {
        if (budget <= 0) return std::min(inside, level);
        --budget;
        const double lambda = 1.0 + double(k) * inv_len;
        const double z = 1.0 - lambda * drop;
        if (!(z > hp)) return level;
        const double h = bilinear(f, double(px) + lambda * double(dx), double(py) + lambda * double(dy));
        if (h < z) return std::min(inside, level); // the ray left the surface since the step before: E
        // The value lambda * tq / (z - hp) grows along the ray: stop once it cannot matter. (The
        // product form differs from the quotient by rounding only; `stop` has slack for that.)
        if (lambda * tq >= stop * (z - hp)) return level;
        inside = (lambda * tq) / (z - hp);
    }
    return level;
}

namespace {

struct Node {
    int level, i, j;
    double bound;
};

// One texel's search. Returns k (the ratio in format steps).
class Searcher {
public:
    // `seeds`: where the cone searches start (cone_seeds_cpu); null for the seeds' own searches.
    Searcher(const HeightField& f, const MaxPyramid& pyr, ConeKind kind, ConeFormat format, int budget,
             int node_budget, int best_first_budget, const ConeSeeds* seeds)
        : f_(f), pyr_(pyr), kind_(kind), format_(format), steps_(cone_format_steps(format)), seeds_(seeds),
          budget_(budget > 0 ? budget : std::numeric_limits<int>::max()),
          node_budget_(node_budget > 0 ? node_budget : std::numeric_limits<int>::max()),
          best_first_budget_(std::max(best_first_budget, 0)),
          inv_w2_(1.0 / (double(f.width) * double(f.width))),
          inv_h2_(1.0 / (double(f.height) * double(f.height))), top_(pyr.levels() - 1),
          global_max_(pyr.at(top_, 0, 0))
    {
        stack_.reserve(std::size_t(4 * pyr.levels() + 8));
    }

    // The ratio of texel (px, py) in format steps: kind relaxed is never below kind cone. A
    // relaxed search that runs to its end needs no cone search for that: a texel's relaxed
    // constraint is never below its cone constraint, so the minimum over all texels is not either.
    // Only where a budget stops it early, and what is left counts by the nodes' lower bounds
    // (which may lie below every constraint in the node), does the cone search set the floor.
    int search(int px, int py)
    {
        bool cut = false;
        if (kind_ == ConeKind::Cone) return search(px, py, false, cut);
        const int relaxed = search(px, py, true, cut);
        return cut ? std::max(relaxed, search(px, py, false, cut)) : relaxed;
    }

    // `cut`: set when a budget stopped the search early. Depth first, as the GPU's search; where
    // the node budget runs out, the nodes left go on best first (smallest bound first) for up to
    // best_first_budget_ more (CPU only: the GPU path hands such texels back to
    // cone_steps_of_texels). The depth-first search leaves the near siblings of the nodes it went
    // down into, whose bounds are small: counted by those, on a ramp or a hill 512 texels across
    // a third of the texels stored less than half their ratio (found by an exploratory session).
    // Best first, the smallest bound left only grows, and what is left when it stops counts by
    // that (the heap's top): the widest cone that many nodes prove.
    int search(int px, int py, bool relaxed, bool& cut)
    {
        const float hp = f_.texels[std::size_t(py) * std::size_t(f_.width) + std::size_t(px)];
        if (!(hp < global_max_)) return steps_; // nothing is higher: the cap
        stack_.clear();
        stack_.push_back({top_, 0, 0, 0.0});
        int budget = budget_;
        const double best = !seeds_ || (relaxed && seeds_->relaxed.empty())
                                ? 1.0
                                : seeded_best(px, py, hp, kSeedShift, relaxed, budget);
        return run(px, py, hp, relaxed, cone_ratio_steps(best, format_), best, budget, 0, cut);
    }

    // A seed (ConeSeeds): the texel whose constraint set the cone (`relaxed`: the relaxed cone) of
    // texel (px, py) in its search, depth first and stopped by the node budget alone (the best
    // found by then); kNoConeSeed where none is lower than the cap. The search starts from nothing
    // for the seeds of every fourth column and row of the grid (`coarse`), from those for the
    // others.
    std::uint32_t seed_of(int px, int py, bool coarse, bool relaxed)
    {
        argmin_ = kNoConeSeed;
        const float hp = f_.texels[std::size_t(py) * std::size_t(f_.width) + std::size_t(px)];
        if (!(hp < global_max_)) return kNoConeSeed;
        stack_.clear();
        stack_.push_back({top_, 0, 0, 0.0});
        int budget = budget_;
        const double best = coarse ? 1.0 : seeded_best(px, py, hp, kCoarseSeedShift, relaxed, budget, &argmin_);
        bool cut = false;
        depth_first_only_ = true;
        run(px, py, hp, relaxed, cone_ratio_steps(best, format_), best, budget, 0, cut);
        depth_first_only_ = false;
        return argmin_;
    }

    // A depth-first search the GPU stopped where its node budget ran out, from where it stopped:
    // its nodes left to visit become this search's stack, in the order the CPU's own depth-first
    // search holds them at that point (each level's list above the lists of the levels over it,
    // each list with the child to visit next on top), each bound computed as the CPU computes it,
    // and the search goes on from its next visit, which finds the node budget spent. So the
    // result is the one search(px, py, state.relaxed, cut) gives, without its depth-first part.
    int resume(const ConeSearchState& state, bool& cut)
    {
        const int px = int(state.texel % std::uint32_t(f_.width)), py = int(state.texel / std::uint32_t(f_.width));
        const float hp = f_.texels[std::size_t(state.texel)];
        const int m = state.last_level;
        stack_.clear();
        for (int level = top_ - 1; level >= 0; --level) {
            if (!(state.filled & (1u << level))) continue; // (the lowest is m - 1: m's children)
            const int shift = level + 1 - m;
            const int pi = state.last_i >> shift, pj = state.last_j >> shift;
            const std::uint32_t list = state.lists[std::size_t(level)];
            for (int n = int(list & 7u) - 1; n >= 0; --n) {
                const std::uint32_t q = (list >> (3u + 2u * std::uint32_t(n))) & 3u;
                const int ci = 2 * pi + int(q & 1u), cj = 2 * pj + int(q >> 1u);
                stack_.push_back({level, ci, cj, node_distance(level, ci, cj, px, py) / rise(pyr_.at(level, ci, cj), hp)});
            }
        }
        const int k = cone_ratio_steps(state.best, format_);
        return run(px, py, hp, state.relaxed, k, state.best, state.march_budget, node_budget_, cut);
    }

private:
    // The search loop over stack_, from k (its best c so far `best`), `budget` march steps left
    // and `visits` nodes visited.
    int run(int px, int py, float hp, bool relaxed, int k, double best, int budget, int visits, bool& cut)
    {
        double threshold = steps_squared(k, steps_); // a candidate c lowers k only if c * m < this
        int limit = node_budget_;
        bool heap = false; // stack_ is a min-heap of bounds: the best-first part
        const auto later = [](const Node& a, const Node& b) { return a.bound > b.bound; };
        while (!stack_.empty()) {
            if (++visits > limit) {
                if (!heap && best_first_budget_ > 0 && !depth_first_only_) {
                    std::erase_if(stack_, [&](const Node& n) { return n.bound * kMargin >= threshold; });
                    std::make_heap(stack_.begin(), stack_.end(), later);
                    heap = true;
                    visits = 0;
                    limit = best_first_budget_;
                    continue;
                }
                // Out of nodes: what is left counts by its lower bounds (conservative).
                cut = true;
                const double rest = rest_bound(best, threshold);
                if (rest < best) k = cone_ratio_steps(rest, format_);
                break;
            }
            if (heap) {
                if (stack_.front().bound * kMargin >= threshold) break; // nothing left can lower k
                std::pop_heap(stack_.begin(), stack_.end(), later);
            }
            const Node n = stack_.back();
            stack_.pop_back();
            if (n.bound * kMargin >= threshold) continue; // k went down since it was pushed
            if (n.level == 0) {
                double c = n.bound; // kind cone: the bound of a texel is its constraint
                bool bound_only = false;
                if (relaxed) {
                    const int sx = signed_offset(n.i - px, f_.width);
                    const int sy = signed_offset(n.j - py, f_.height);
                    c = relaxed_constraint(f_, px, py, sx, sy, threshold / kMargin * (1.0 + 1e-9), budget, n.bound);
                    if (budget <= 0) {
                        // Out of budget: what is left counts by its lower bounds.
                        cut = true;
                        c = rest_bound(c, threshold);
                        stack_.clear();
                        bound_only = true;
                    }
                }
                if (c < best) {
                    best = c;
                    // (A seed is a texel whose constraint set the result; a bound is none: the
                    // seed stays the one found before, as the GPU's search keeps it.)
                    if (!bound_only) argmin_ = std::uint32_t(n.j) * std::uint32_t(f_.width) + std::uint32_t(n.i);
                    k = cone_ratio_steps(best, format_);
                    threshold = steps_squared(k, steps_);
                    if (k == 0) return 0;
                }
                continue;
            }
            // Children, smallest bound popped first.
            Node kids[4];
            int count = 0;
            const int cl = n.level - 1;
            const int cw = pyr_.widths[std::size_t(cl)], ch = pyr_.heights[std::size_t(cl)];
            for (int cj = 2 * n.j; cj < std::min(2 * n.j + 2, ch); ++cj)
                for (int ci = 2 * n.i; ci < std::min(2 * n.i + 2, cw); ++ci) {
                    const double dmax = rise(pyr_.at(cl, ci, cj), hp);
                    if (!(dmax > 0.0)) continue;
                    const double bound = node_distance(cl, ci, cj, px, py) / dmax;
                    if (bound * kMargin >= threshold) continue;
                    kids[count++] = {cl, ci, cj, bound};
                }
            if (heap) {
                for (int c = 0; c < count; ++c) {
                    stack_.push_back(kids[c]);
                    std::push_heap(stack_.begin(), stack_.end(), later);
                }
                continue;
            }
            // Push in decreasing bound (at most 4: insertion order by hand).
            for (int c = 1; c < count; ++c)
                for (int d = c; d > 0 && kids[d - 1].bound < kids[d].bound; --d) std::swap(kids[d - 1], kids[d]);
            for (int c = 0; c < count; ++c) stack_.push_back(kids[c]);
        }
        return k;
    }

    // From h_p up to h, in the format's height steps, as the map stores heights (R: every texel
    // of the field is a whole number of them, cone_source_field), so that a ratio is conservative
    // against the stored heights exactly. The difference of the float texels, each rounded by up
    // to 3e-8, was up to 0.4 % off a rise of one 16-bit step, more than the margin on c (2^-20):
    // a 96x1 map with a rise of 1493 steps stored a ratio 1.1e-6 above the exact one (found by
    // an exploratory session, sixteenth session). The same in shaders/conemap.comp.
    double rise(float h, float hp) const
    {
        return double(std::int64_t(cone_height_steps(h, format_)) - std::int64_t(cone_height_steps(hp, format_))) /
               double(steps_);
    }
    // The least constraint on texel p (height hp) of the seeds of the four seed texels around it
    // on the grid of every 2^shift-th texel (ConeSeeds at kSeedShift, the coarse seeds at
    // kCoarseSeedShift: the nearest at or below and left of p, the next ones right and up,
    // wrapping), capped at 1: where its search starts; `which` gets the seed that gave it, if any.
    // Computed as the search computes a texel's constraint: `relaxed`, the relaxed seeds' relaxed
    // constraints, each marched only where its cone constraint could lower the result, within the
    // march `budget` (decremented); where that runs out, the seeds marched before it count.
    double seeded_best(int px, int py, float hp, int shift, bool relaxed, int& budget,
                       std::uint32_t* which = nullptr) const
    {
        const std::vector<std::uint32_t>& grid = relaxed ? seeds_->relaxed : seeds_->texels;
        const int spacing = 1 << shift, stride = 1 << (shift - kSeedShift); // grid texels per seed here
        const int gw = (f_.width + spacing - 1) / spacing, gh = (f_.height + spacing - 1) / spacing;
        const int gx = px >> shift, gy = py >> shift;
        double best = 1.0;
        for (int q = 0; q < 4; ++q) {
            const int sx = gx + (q & 1) < gw ? gx + (q & 1) : 0, sy = gy + (q >> 1) < gh ? gy + (q >> 1) : 0;
            const std::uint32_t t = grid[std::size_t(sy * stride) * std::size_t(seeds_->width) + std::size_t(sx * stride)];
            if (t == kNoConeSeed) continue;
            const double dmax = rise(f_.texels[t], hp);
            if (!(dmax > 0.0)) continue;
            const int tx = int(t % std::uint32_t(f_.width)), ty = int(t / std::uint32_t(f_.width));
            double c = node_distance(0, tx, ty, px, py) / dmax;
            if (relaxed) {
                const double threshold = steps_squared(cone_ratio_steps(best, format_), steps_);
                if (!(c * kMargin < threshold)) continue;
                c = relaxed_constraint(f_, px, py, signed_offset(tx - px, f_.width), signed_offset(ty - py, f_.height),
                                       threshold / kMargin * (1.0 + 1e-9), budget, c);
                if (budget <= 0) break; // (a lower bound only)
            }
            if (c < best) {
                best = c;
                if (which) *which = t;
            }
        }
        return best;
    }
    // min(c, the lower bound of every node still on the stack that could lower the result): the
    // ratio when a budget stops the search early.
    double rest_bound(double c, double threshold) const
    {
        for (const Node& n : stack_)
            if (n.bound * kMargin < threshold) c = std::min(c, n.bound);
        return c;
    }
    static int signed_offset(int d, int n)
    {
        d = wrap(d, n);
        return 2 * d > n ? d - n : d;
    }
    // Shortest wrapped distance (texels) from p to a texel range [a, b] on an axis of n texels.
    static int axis_distance(int p, int a, int b, int n)
    {
        if (p >= a && p <= b) return 0;
        if (p < a) return std::min(a - p, p + n - b);
        return std::min(p - b, a + n - p);
    }
    // Smallest UV distance from texel p to the texels of node (level, i, j).
    double node_distance(int level, int i, int j, int px, int py) const
    {
        const int x0 = i << level, y0 = j << level;
        const int x1 = std::min(((i + 1) << level), f_.width) - 1;
        const int y1 = std::min(((j + 1) << level), f_.height) - 1;
        const int dx = axis_distance(px, x0, x1, f_.width);
        const int dy = axis_distance(py, y0, y1, f_.height);
        return std::sqrt(double(dx * dx) * inv_w2_ + double(dy * dy) * inv_h2_);
    }

    const HeightField& f_;
    const MaxPyramid& pyr_;
    ConeKind kind_;
    ConeFormat format_;
    int steps_;
    const ConeSeeds* seeds_;
    std::uint32_t argmin_ = kNoConeSeed; // the texel that set `best` last (seed_of)
    bool depth_first_only_ = false;      // seed_of: no best-first part
    int budget_;
    int node_budget_;
    int best_first_budget_;
    double inv_w2_, inv_h2_;
    int top_;
    float global_max_;
    std::vector<Node> stack_;
};

} // namespace

int cone_cpu_items(int width, int height)
{
    const std::int64_t spans = (std::int64_t(std::max(width, 0)) + kConeSpan - 1) / kConeSpan;
    return int(std::min<std::int64_t>(spans * std::max(height, 0), std::numeric_limits<int>::max()));
}

unsigned cone_cpu_threads(const ConeBuildOptions& options, int items)
{
    const unsigned threads = options.threads > 0 ? unsigned(options.threads) : std::thread::hardware_concurrency();
    return std::clamp(threads, 1u, unsigned(std::max(1, items)));
}

namespace {

// Runs `per_item(searcher, i)` for i in [0, count) on options.threads threads (each with its
// Searcher), handing items out from an atomic counter; `progress` gets the fraction done. Stops
// at the next item when options.cancel turns true or an item throws (rethrown here).
template <class PerItem>
void for_each_item(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind, const ConeBuildOptions& options,
                   const ConeSeeds* seeds, int count, PerItem per_item)
{
    const unsigned threads = cone_cpu_threads(options, count);
    std::atomic<int> next{0}, done{0};
    std::mutex mutex;
    std::condition_variable finished;
    unsigned running = threads;
    std::exception_ptr failure;
    const auto cancelled = [&] { return options.cancel && options.cancel->load(std::memory_order_relaxed); };

    const auto work = [&]() {
        try {
            Searcher searcher(field, pyramid, kind, options.format, options.relaxed_budget, options.node_budget,
                              options.best_first_budget, seeds);
            for (int i = next++; i < count; i = next++) {
                if (cancelled()) break;
                per_item(searcher, i);
                ++done;
            }
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!failure) failure = std::current_exception();
            next = count; // the others stop at their next item
        }
        std::lock_guard lock(mutex);
        if (--running == 0) finished.notify_all();
    };
    std::vector<std::thread> pool;
    try {
        for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work);
    } catch (const std::system_error&) {
        // The system refused a thread (limits, memory): go on with those that started, or with
        // this thread alone (a joinable std::thread must never be destroyed unjoined).
        std::unique_lock lock(mutex);
        running -= threads - unsigned(pool.size());
        if (pool.empty()) {
            running = 1;
            lock.unlock();
            work();
        }
    }
    {
        std::unique_lock lock(mutex);
        while (!finished.wait_for(lock, std::chrono::milliseconds(100), [&] { return running == 0; }))
            if (options.progress) {
                lock.unlock();
                options.progress(double(done.load()) / double(count));
                lock.lock();
            }
    }
    for (auto& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    if (cancelled()) throw ConeBuildCancelled();
}

// `per_span(searcher, row, begin, end)` for the items [begin, end) of each of `rows` rows of
// `length` items, in spans of at most kConeSpan (cone_cpu_items), on options.threads threads.
template <class PerSpan>
void for_each_span(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind, const ConeBuildOptions& options,
                   const ConeSeeds* seeds, int rows, int length, PerSpan per_span)
{
    const int spans = cone_cpu_items(length, 1); // per row
    for_each_item(field, pyramid, kind, options, seeds, cone_cpu_items(length, rows), [&](Searcher& searcher, int item) {
        const int begin = (item % spans) * kConeSpan;
        per_span(searcher, item / spans, begin, std::min(length, begin + kConeSpan));
    });
}

} // namespace

ConeSeeds cone_seed_grid(const HeightField& field, ConeKind kind)
{
    ConeSeeds seeds;
    seeds.width = (field.width + kConeSeedSpacing - 1) / kConeSeedSpacing;
    seeds.height = (field.height + kConeSeedSpacing - 1) / kConeSeedSpacing;
    const std::size_t count = std::size_t(seeds.width) * std::size_t(seeds.height);
    seeds.texels.assign(count, kNoConeSeed);
    if (kind == ConeKind::Relaxed) seeds.relaxed.assign(count, kNoConeSeed);
    return seeds;
}

std::pair<double, double> cone_seed_pass_progress(ConeKind kind, bool relaxed_seeds, bool coarse)
{
    constexpr double coarse_part = 1.0 / double(1 << (2 * (kCoarseSeedShift - kSeedShift))); // of a kind's seeds
    const double all = kind == ConeKind::Relaxed ? 5.0 : 1.0;
    const double from = (relaxed_seeds ? 1.0 : 0.0) + (coarse ? 0.0 : (relaxed_seeds ? 4.0 : 1.0) * coarse_part);
    const double share = (relaxed_seeds ? 4.0 : 1.0) * (coarse ? coarse_part : 1.0 - coarse_part);
    return {from / all, share / all};
}

ConeSeeds cone_seeds_cpu(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                         const ConeBuildOptions& options)
{
    ConeSeeds seeds = cone_seed_grid(field, kind);
    constexpr int stride = 1 << (kCoarseSeedShift - kSeedShift); // the coarse seeds' spacing on the grid
    const int coarse_rows = (seeds.height + stride - 1) / stride;
    const int coarse_columns = (seeds.width + stride - 1) / stride;
    // The cone seeds, then (kind relaxed) the relaxed ones; of each, the coarse seeds (every
    // stride-th seed of every stride-th row) a row at a time, from nothing, then the others from
    // them.
    ConeBuildOptions part = options;
    const auto pass_progress = [&](bool relaxed, bool coarse) {
        if (!options.progress) return;
        const auto [from, share] = cone_seed_pass_progress(kind, relaxed, coarse);
        part.progress = [&options, from, share](double f) { options.progress(from + share * f); };
    };
    for (const bool relaxed : {false, true}) {
        if (relaxed && kind == ConeKind::Cone) break;
        std::vector<std::uint32_t>& out = relaxed ? seeds.relaxed : seeds.texels;
        pass_progress(relaxed, true);
        for_each_span(field, pyramid, kind, part, nullptr, coarse_rows, coarse_columns,
                      [&](Searcher& searcher, int row, int begin, int end) {
                          const int sy = row * stride;
                          for (int sx = begin * stride; sx < end * stride; sx += stride)
                              out[std::size_t(sy) * std::size_t(seeds.width) + std::size_t(sx)] =
                                  searcher.seed_of(sx << kSeedShift, sy << kSeedShift, true, relaxed);
                      });
        pass_progress(relaxed, false);
        for_each_span(field, pyramid, kind, part, &seeds, seeds.height, seeds.width,
                      [&](Searcher& searcher, int sy, int begin, int end) {
                          for (int sx = begin; sx < end; ++sx)
                              if (sx % stride != 0 || sy % stride != 0)
                                  out[std::size_t(sy) * std::size_t(seeds.width) + std::size_t(sx)] =
                                      searcher.seed_of(sx << kSeedShift, sy << kSeedShift, false, relaxed);
                      });
    }
    return seeds;
}

ConeMap build_cone_map_cpu(const HeightField& given, ConeKind kind, const ConeBuildOptions& options)
{
    if (given.width < 1 || given.height < 1 ||
        given.texels.size() != std::size_t(given.width) * std::size_t(given.height))
        throw Error(given.name.empty() ? "height map" : given.name, "cannot build a cone map of an empty height field");
    HeightField rounded;
    const HeightField& field = cone_source_field(given, options.format, rounded);
    const MaxPyramid pyramid = build_max_pyramid(field);
    // The seeds first (their share of the progress: kConeSeedProgress).
    ConeBuildOptions part = options;
    if (options.progress) part.progress = [&](double f) { options.progress(kConeSeedProgress * f); };
    const ConeSeeds seeds = cone_seeds_cpu(field, pyramid, kind, part);
    if (options.progress)
        part.progress = [&](double f) { options.progress(kConeSeedProgress + (1.0 - kConeSeedProgress) * f); };
    ConeMap map;
    map.width = field.width;
    map.height = field.height;
    map.kind = kind;
    map.heights = field.texels;
    map.ratios.assign(field.texels.size(), 0.0f);
    for_each_span(field, pyramid, kind, part, &seeds, field.height, field.width,
                  [&](Searcher& searcher, int y, int begin, int end) {
                      for (int x = begin; x < end; ++x)
                          map.ratios[std::size_t(y) * std::size_t(field.width) + std::size_t(x)] =
                              cone_steps_to_ratio(searcher.search(x, y), options.format);
                  });
    if (options.progress) options.progress(1.0);
    return map;
}

namespace {

// `per_index(searcher, i)` for i in [0, count), 64 at a time on options.threads threads, without
// calling options.progress (the caller's own progress goes on around it).
template <class PerIndex>
void for_each_search(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                     const ConeBuildOptions& options, const ConeSeeds& seeds, std::size_t count, PerIndex per_index)
{
    if (count == 0) return;
    ConeBuildOptions quiet = options;
    quiet.progress = nullptr;
    constexpr std::size_t kPerItem = 64;
    const int items = int((count + kPerItem - 1) / kPerItem);
    for_each_item(field, pyramid, kind, quiet, &seeds, items, [&](Searcher& searcher, int item) {
        const std::size_t end = std::min(count, std::size_t(item + 1) * kPerItem);
        for (std::size_t i = std::size_t(item) * kPerItem; i < end; ++i) per_index(searcher, i);
    });
}

} // namespace

void cone_steps_of_texels(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                          const ConeBuildOptions& options, const ConeSeeds& seeds,
                          const std::vector<std::uint32_t>& texels, std::vector<std::uint32_t>& steps)
{
    const std::uint32_t w = std::uint32_t(field.width);
    for_each_search(field, pyramid, kind, options, seeds, texels.size(), [&](Searcher& searcher, std::size_t i) {
        steps[texels[i]] = std::uint32_t(searcher.search(int(texels[i] % w), int(texels[i] / w)));
    });
}

void cone_steps_resumed(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                        const ConeBuildOptions& options, const ConeSeeds& seeds,
                        const std::vector<ConeSearchState>& states, std::vector<std::uint32_t>& k)
{
    k.assign(states.size(), 0u);
    for_each_search(field, pyramid, kind, options, seeds, states.size(), [&](Searcher& searcher, std::size_t i) {
        bool cut = false;
        k[i] = std::uint32_t(searcher.resume(states[i], cut));
    });
}

} // namespace pr
