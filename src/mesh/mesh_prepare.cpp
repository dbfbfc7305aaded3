// From a polygon soup to render data (contract, "Geometry and sampling"): triangulation,
// welding by exact position, angle-weighted welded normals, UVs (the file's or box-projected),
// render vertices per (welded position, UV, tangent frame) and metric tangent frames.
#include "mesh/dense_index.hpp"
#include "mesh/raw_mesh.hpp"

#include "core/error.hpp"
#include "core/ray_crossing.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <span>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace pr {
namespace {

using glm::dvec2;
using glm::dvec3;
using std::size_t;
using std::uint32_t;
using std::uint64_t;

constexpr uint32_t kNone = 0xffffffffu;

// Bit pattern of a float with -0 folded into +0, so that equal coordinates weld.
uint32_t float_bits(float f)
{
    if (f == 0.0f) f = 0.0f;
    return std::bit_cast<uint32_t>(f);
}

struct PositionKey {
    uint32_t bits[3];
    bool operator==(const PositionKey& o) const
    {
        return bits[0] == o.bits[0] && bits[1] == o.bits[1] && bits[2] == o.bits[2];
    }
};
struct PositionHash {
    uint64_t operator()(const PositionKey& k) const
    {
        return mix64((uint64_t(k.bits[0]) << 32 | k.bits[1]) ^ mix64(k.bits[2]));
    }
};

// A welded position with a UV. Render vertices are these, further split where the faces
// around one of them have incompatible tangent frames (see "render vertices" below).
struct UvKey {
    uint32_t weld;
    uint32_t u;
    uint32_t v;
    bool operator==(const UvKey& o) const { return weld == o.weld && u == o.u && v == o.v; }
};
struct UvKeyHash {
    uint64_t operator()(const UvKey& k) const
    {
        return mix64(uint64_t(k.weld) ^ mix64(uint64_t(k.u) << 32 | k.v));
    }
};

struct Triangle {
    uint32_t corner[3]; // indices into RawMesh::corners
    uint32_t face;
};

double cross2(dvec2 a, dvec2 b)
{
    return a.x * b.y - a.y * b.x;
}

// Twice the signed area of the ring `r` of 2D points `q`.
double ring_area2(const std::vector<dvec2>& q, const std::vector<uint32_t>& r)
{
    double a = 0.0;
    for (size_t i = 0; i < r.size(); ++i) a += cross2(q[r[i]], q[r[(i + 1) % r.size()]]);
    return a;
}

// Ear clipping takes time of the order of the square of a polygon's corners, and of the cube at
// worst (a spiral strip of 4096 corners: 9 s): polygons of up to kEarClipCorners are clipped
// while the corners that all of a mesh's polygons visit, in the ear tests and the search for
// points they pass twice, add up to no more than MeshOptions::ear_clip_work (2^30, 1.2 s here;
// a 4096-corner star takes 30-50 ms of it). What is left of a concave polygon past either limit
// becomes a fan, which may cover area outside its outline; the caller warns. A strictly convex
// polygon costs nothing at any size: its fan, or from kEarRoundCorners on rounds of ears (below),
// as does one past kEarClipCorners that is convex to float precision (a fine circle whose
// neighbouring corners rounded to collinear or slightly reflex: it was fanned, with a warning
// that called it concave). (Before the fifteenth session polygons of up to 64 corners were
// clipped whatever they cost: up to 64^3 visits each, and the triangle limit lets a mesh hold
// 160,000 of them, some 4·10^10 visits at worst.)
constexpr size_t kEarClipCorners = 4096;
// Strictly convex polygons of this many corners or more are cut by rounds of ears, not fanned (below);
// smaller ones keep the fan from their first corner (quads and the like: the same triangles as
// before the seventeenth session).
constexpr size_t kEarRoundCorners = 8;

// Edge directions turn round a polygon this many times counter-clockwise (in the 2D points
// `q`, ring `r`): corners where the direction passes "east" (+x) turning left count +1, turning
// right -1. A convex polygon goes round once; a triangle listed 30,000 times in one face (all
// of its corners turning left, so it passed for convex and was cut by rounds of ears into
// triangles of both windings) 30,000 times, a pentagram twice.
long turns_round(const std::vector<dvec2>& q, const std::vector<uint32_t>& r)
{
    const auto upper = [](dvec2 e) { return e.y > 0.0 || (e.y == 0.0 && e.x > 0.0); }; // angle in [0, pi)
    long turns = 0;
    const size_t m = r.size();
    for (size_t i = 0; i < m; ++i) {
        const dvec2 e1 = q[r[(i + 1) % m]] - q[r[i]], e2 = q[r[(i + 2) % m]] - q[r[(i + 1) % m]];
        const double c = cross2(e1, e2);
        if (!upper(e1) && upper(e2) && c > 0.0) ++turns;
        if (upper(e1) && !upper(e2) && c < 0.0) --turns;
    }
    return turns;
}

// Twice the area of the convex hull of the points of ring `r` (Andrew's monotone chain).
double hull_area2(const std::vector<dvec2>& q, const std::vector<uint32_t>& r)
{
    std::vector<dvec2> s;
    s.reserve(r.size());
    for (uint32_t i : r) s.push_back(q[i]);
    std::sort(s.begin(), s.end(), [](dvec2 a, dvec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
    std::vector<dvec2> h(2 * s.size() + 1);
    size_t k = 0;
    for (size_t i = 0; i < s.size(); ++i) {
        while (k >= 2 && cross2(h[k - 1] - h[k - 2], s[i] - h[k - 2]) <= 0.0) --k;
        h[k++] = s[i];
    }
    for (size_t i = s.size() - 1, lower = k + 1; i-- > 0;) {
        while (k >= lower && cross2(h[k - 1] - h[k - 2], s[i] - h[k - 2]) <= 0.0) --k;
        h[k++] = s[i];
    }
    double a = 0.0;
    for (size_t i = 0; i + 1 < k; ++i) a += cross2(h[i], h[i + 1]);
    return a;
}

// What became of a polygon (triangulate_polygon).
enum class PolygonCut {
    Inside,           // triangles within its outline
    FannedPastLimits, // concave past the ear clipping's limits: a fan
    CrossesItself,    // its outline crosses itself (a bow tie): no inside to keep to
};

// Triangulates polygon `face` (n >= 3 corners, positions in `p`) into local corner triples.
// Ear clipping in the plane of the Newell normal, so concave polygons come out right; a convex
// polygon gives the fan from its first corner (from kEarRoundCorners corners on, rounds of ears).
// Concave ones past the limits above (`work_left` is what is left of the budget) fall back to a
// fan (FannedPastLimits); self-intersecting ones, which have no inside, come out as ear clipping
// or the fan leaves them (CrossesItself).
//
// A polygon whose outline passes twice through one point (a corner repeated, `1 2 3 4 1`, or two
// loops touching at a vertex, `1 2 3 4 5 3`) is first cut there into the loops it is made of,
// where both have positive area; a loop of fewer than three corners has none and is dropped. The
// ear test skips points that coincide with an ear's corners (so that the two sides of a keyhole
// bridge, whose loops are an outline and a hole of negative area, clip right), which let it clip
// across the touching point; what was left became a fan outside the outline.
PolygonCut triangulate_polygon(const std::vector<dvec3>& p, std::vector<std::array<uint32_t, 3>>& out,
                               size_t& work_left)
{
    const size_t n = p.size();
    out.clear();
    auto fan = [&](const std::vector<uint32_t>& ring) {
        for (size_t i = 1; i + 1 < ring.size(); ++i) out.push_back({ring[0], ring[i], ring[i + 1]});
    };
    std::vector<uint32_t> whole(n);
    for (size_t i = 0; i < n; ++i) whole[i] = uint32_t(i);
    if (n == 3) {
        fan(whole);
        return PolygonCut::Inside;
    }
    dvec3 normal(0.0);
    double magnitude = 0.0; // the largest coordinate: what float rounding is relative to
    for (size_t i = 0; i < n; ++i) {
        const dvec3& a = p[i];
        const dvec3& b = p[(i + 1) % n];
        normal +=
            dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        magnitude = std::max({magnitude, std::abs(a.x), std::abs(a.y), std::abs(a.z)});
    }
    const dvec3 an = glm::abs(normal);
    const int k = an.x >= an.y && an.x >= an.z ? 0 : (an.y >= an.z ? 1 : 2);
    if (an[k] == 0.0) {
        // No area in any plane: on a line (its triangles have none, and are dropped), or lobes
        // of opposite windings that cancel (a bow tie 1 2 4 3 on a square: its fan covers three
        // quarters of the square).
        fan(whole);
        for (const auto& t : out)
            if (glm::length(glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]])) > 0.0) return PolygonCut::CrossesItself;
        return PolygonCut::Inside;
    }
    // Axes (k+1, k+2) keep the orientation when normal[k] > 0; flip the second otherwise, so
    // the polygon is counter-clockwise in 2D.
    const double flip = normal[k] > 0.0 ? 1.0 : -1.0;
    std::vector<dvec2> q(n);
    for (size_t i = 0; i < n; ++i) q[i] = dvec2(p[i][(k + 1) % 3], flip * p[i][(k + 2) % 3]);
    const auto turn = [&](const std::vector<uint32_t>& r, size_t i) {
        const size_t m = r.size();
        return cross2(q[r[(i + 1) % m]] - q[r[i]], q[r[(i + 2) % m]] - q[r[(i + 1) % m]]);
    };

    // The budget: false once `visits` more corners would pass it.
    bool within_budget = true;
    const auto charge = [&](size_t visits) {
        if (!within_budget) return within_budget;
        if (visits > work_left) return within_budget = false;
        work_left -= visits;
        return true;
    };

    // Every other corner cut off as an ear, round after round on the corners left: triangles
    // of the polygon's own scale inside, slivers only along its rim, and no corner in more
    // than about two per round. The fan put every triangle around the first corner, a sliver
    // each, and a ray in the prism's walk crosses them one by one. In ring order each
    // triangle keeps the polygon's orientation. A corner that does not turn left (in a convex
    // polygon only where float rounding bent it, or on a straight side) is no ear's tip: its
    // triangle would have no area or the other winding; it waits for a later round, where its
    // neighbours lie farther off. A round that takes less than an eighth of the corners (long
    // straight sides, which make no progress that way) leaves the rest to the fan, which lies
    // inside the outline there.
    auto rounds_of_ears = [&](std::vector<uint32_t> ring) {
        std::vector<uint32_t> next;
        while (ring.size() > 3) {
            next.clear();
            size_t c = 0;
            while (c + 2 < ring.size()) {
                if (cross2(q[ring[c + 1]] - q[ring[c]], q[ring[c + 2]] - q[ring[c + 1]]) > 0.0) {
                    out.push_back({ring[c], ring[c + 1], ring[c + 2]});
                    next.push_back(ring[c]);
                    c += 2;
                } else {
                    next.push_back(ring[c++]);
                }
            }
            for (; c < ring.size(); ++c) next.push_back(ring[c]);
            const bool slow = (ring.size() - next.size()) * 8 < ring.size();
            ring.swap(next);
            if (slow) break;
        }
        fan(ring);
    };

    // Convex: every corner turns left and the outline goes round once. A strictly convex polygon
    // of fewer than kEarRoundCorners corners is its fan.
    auto strictly_convex = [&](const std::vector<uint32_t>& r) {
        for (size_t i = 0; i < r.size(); ++i)
            if (!(turn(r, i) > 0.0)) return false;
        return turns_round(q, r) == 1;
    };
    // Convex to float precision: the file's positions are floats, rounded by up to `d` (relative
    // to the largest coordinate) from where they were meant to be. On a circle of 200,000 corners
    // neighbours are 3e-5 apart and their corners bend by 1e-10, far below that: about half of
    // them turned right or not at all, and the circle was "a concave polygon too large to clip
    // ... triangulated as a fan, which may cover area outside its outline" (found by an
    // exploratory session). Such a polygon is convex when no corner turns right by more than
    // rounding can make it, the outline goes round once, and it covers its convex hull, but for
    // a rim as wide as the rounding (a real dent made of many small turns, each within the
    // rounding, does not).
    auto convex_to_float_precision = [&](const std::vector<uint32_t>& r) {
        const size_t m = r.size();
        const double d = 2.0 * magnitude * std::ldexp(1.0, -24); // 2D rounding of a point, with room
        double perimeter = 0.0;
        for (size_t i = 0; i < m; ++i) {
            const double e1 = glm::length(q[r[(i + 1) % m]] - q[r[i]]);
            const double e2 = glm::length(q[r[(i + 2) % m]] - q[r[(i + 1) % m]]);
            if (turn(r, i) < -(2.0 * d * (e1 + e2) + 4.0 * d * d)) return false;
            perimeter += e1;
        }
        if (turns_round(q, r) != 1) return false;
        return ring_area2(q, r) >= hull_area2(q, r) - 2.0 * (4.0 * d * perimeter + double(m) * 4.0 * d * d);
    };

    auto clip = [&](std::vector<uint32_t> ring) {
        auto is_ear = [&](size_t i) {
            const size_t m = ring.size();
            const uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
            if (cross2(q[b] - q[a], q[c] - q[b]) <= 0.0) return false; // reflex or flat
            for (size_t j = 0; j < m; ++j) {
                const uint32_t t = ring[j];
                if (t == a || t == b || t == c) continue;
                if (q[t] == q[a] || q[t] == q[b] || q[t] == q[c]) continue;
                if (cross2(q[b] - q[a], q[t] - q[a]) >= 0.0 &&
                    cross2(q[c] - q[b], q[t] - q[b]) >= 0.0 &&
                    cross2(q[a] - q[c], q[t] - q[c]) >= 0.0)
                    return false;
            }
            return true;
        };
        size_t i = 1;
        while (ring.size() > 3) {
            const size_t m = ring.size();
            bool found = false;
            for (size_t tries = 0; tries < m; ++tries, i = (i + 1) % m) {
                if (!charge(m)) break;
                if (is_ear(i)) {
                    out.push_back({ring[(i + m - 1) % m], ring[i], ring[(i + 1) % m]});
                    ring.erase(ring.begin() + std::ptrdiff_t(i));
                    if (i >= ring.size()) i = 0;
                    if (i == 0 && ring.size() > 1) i = 1;
                    found = true;
                    break;
                }
            }
            if (!found) break;
        }
        fan(ring);
    };

    // One loop: convex ones by rounds of ears at no cost, the others clipped within the limits,
    // or fanned past them (false, with the caller's warning, unless convex to float precision).
    bool fanned_concave = false;
    auto triangulate_ring = [&](std::vector<uint32_t> ring) {
        if (ring.size() < 3) return;
        if (strictly_convex(ring)) {
            if (ring.size() < kEarRoundCorners)
                fan(ring);
            else
                rounds_of_ears(std::move(ring));
        } else if (ring.size() > kEarClipCorners) {
            if (convex_to_float_precision(ring))
                rounds_of_ears(std::move(ring));
            else {
                fan(ring);
                fanned_concave = true;
            }
        } else {
            clip(std::move(ring));
        }
    };

    if (strictly_convex(whole)) {
        triangulate_ring(std::move(whole));
        return PolygonCut::Inside;
    }
    // Within the limits, ear clipping gives triangles of the outline's winding that add up to its
    // area, unless the outline crosses itself: then it has no inside, and some triangles lie
    // outside what each lobe encloses (found by an exploratory session, forty-first: a bow tie
    // drew without a word).
    const double area2 = ring_area2(q, whole); // (whole is moved from below)
    const auto outcome = [&] {
        if (!within_budget || fanned_concave) return PolygonCut::FannedPastLimits;
        double sum = 0.0, size = 0.0;
        for (const auto& t : out) {
            const double a = cross2(q[t[1]] - q[t[0]], q[t[2]] - q[t[0]]);
            sum += std::abs(a);
            size += std::abs(a) + glm::length(q[t[1]] - q[t[0]]) * 2.0 * magnitude * std::ldexp(1.0, -24);
        }
        return sum > area2 + 1e-6 * size ? PolygonCut::CrossesItself : PolygonCut::Inside;
    };

    // Points the outline passes more than once: equal positions get one id (by sorting).
    std::vector<uint32_t> order(whole), id(n);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        return p[a].x != p[b].x ? p[a].x < p[b].x : p[a].y != p[b].y ? p[a].y < p[b].y : p[a].z < p[b].z;
    });
    bool repeats = false;
    for (size_t i = 0, next_id = 0; i < n; ++i) {
        if (i > 0 && p[order[i]] != p[order[i - 1]]) ++next_id;
        repeats = repeats || (i > 0 && p[order[i]] == p[order[i - 1]]);
        id[order[i]] = uint32_t(next_id);
    }
    if (!repeats) {
        triangulate_ring(std::move(whole));
        return outcome();
    }
    // Cut into loops in one walk along the outline, on a stack of the corners of what is left:
    // where a point comes again, the corners since its earlier visit (on the stack) close a
    // loop, whose area follows from running sums of the stack's edges, and what is left is the
    // rest (its area the remainder). A cut pops the loop; the point stays on the stack for both.
    // Each corner is pushed and popped once, so the time is linear (each cut copied and measured
    // what was left of the outline: a triangle listed 30,000 times in one face took 30,000 such
    // copies of up to 90,000 corners). Trying an earlier visit of a point costs a visit of the
    // budget: a point visited many times on loops that are not cut (holes) tries them all.
    std::vector<uint32_t> stack, below(n, kNone), last(n, kNone); // below: the slot of the point's previous visit
    std::vector<double> along{0.0}; // along[s]: twice the area swept by the stack's edges up to slot s
    double left_area2 = ring_area2(q, whole);
    size_t left_corners = n;
    std::vector<std::vector<uint32_t>> loops;
    for (uint32_t v = 0; v < n; ++v) {
        bool cut = false;
        for (uint32_t s = last[id[v]]; s != kNone && !cut && charge(1); s = below[s]) {
            const size_t top = stack.size() - 1, corners = stack.size() - s;
            const double area2 = along[top] - along[s] + cross2(q[stack[top]], q[v]);
            if (corners < 3 || left_corners - corners < 3 || (area2 > 0.0 && left_area2 - area2 > 0.0)) {
                if (corners >= 3) loops.emplace_back(stack.begin() + std::ptrdiff_t(s), stack.end());
                for (size_t t = top; t > s; --t) last[id[stack[t]]] = below[t];
                stack.resize(s + 1);
                along.resize(s + 1);
                // The loop keeps the earlier visit's corner, the rest goes on from the later one's
                // (the same point; their texture coordinates may differ: the second petal of a
                // flower took the first petal's UV at its tip; found by a review).
                stack[s] = v;
                left_corners -= corners;
                left_area2 -= area2;
                cut = true;
            }
        }
        if (cut) continue;
        if (!stack.empty()) along.push_back(along.back() + cross2(q[stack.back()], q[v]));
        below[stack.size()] = last[id[v]];
        last[id[v]] = uint32_t(stack.size());
        stack.push_back(v);
    }
    loops.push_back(std::move(stack));
    for (std::vector<uint32_t>& loop : loops) triangulate_ring(std::move(loop));
    return outcome();
}

// Interior angle at corner `a` of triangle (a, b, c); atan2 stays accurate for thin corners.
double corner_angle(const dvec3& a, const dvec3& b, const dvec3& c)
{
    const dvec3 e1 = b - a, e2 = c - a;
    return std::atan2(glm::length(glm::cross(e1, e2)), glm::dot(e1, e2));
}

// Whether triangle (a, b, c), whose edges' cross product has length `cross_length`, has a normal
// of its own: in one so thin that float rounding of its corners decides its normal, the obtuse
// corner would weigh almost pi in an angle-weighted sum, which leaves it out.
bool normal_is_sound(const dvec3& a, const dvec3& b, const dvec3& c, double cross_length)
{
    const double longest2 = std::max({glm::dot(b - a, b - a), glm::dot(c - b, c - b), glm::dot(a - c, a - c)});
    return cross_length > 1e-7 * longest2;
}

// A triangle's metric frame from its edges e1, e2 (p1 - p0, p2 - p0) and their UV differences d1,
// d2 (P is linear in UV over a triangle: e1 = T du1 + B dv1, e2 = T du2 + B dv2), where its UVs
// span an area (a real frame; false where not: see the limit frames in prepare_mesh), with its
// `quality`: the UV area over the product of the UV extents (about 0.5 to 1 when well shaped).
bool real_metric_frame(const dvec3& e1, const dvec3& e2, const dvec2& d1, const dvec2& d2, dvec3& T, dvec3& B,
                       float& quality)
{
    const double det = cross2(d1, d2);
    const double scale = (std::fabs(d1.x) + std::fabs(d2.x)) * (std::fabs(d1.y) + std::fabs(d2.y));
    if (!(det != 0.0 && std::fabs(det) > 1e-7 * scale)) return false;
    T = (e1 * d2.y - e2 * d1.y) / det;
    B = (e2 * d1.x - e1 * d2.x) / det;
    const double lt = glm::length(T), lb = glm::length(B);
    if (!(std::isfinite(lt) && std::isfinite(lb) && lt > 0.0 && lb > 0.0)) return false;
    quality = float(std::fabs(det) / scale);
    return true;
}

// A real frame's weight beside its corner angle where a vertex's frames are averaged: triangles
// nearly flat in UV, whose frame grows without bound, weigh less.
float frame_shape(float quality)
{
    return std::min(1.0f, quality / 0.05f);
}

// Unit vector perpendicular to n (n unit).
dvec3 any_perpendicular(const dvec3& n)
{
    const dvec3 an = glm::abs(n);
    const dvec3 axis = an.x <= an.y && an.x <= an.z
                           ? dvec3(1, 0, 0)
                           : (an.y <= an.z ? dvec3(0, 1, 0) : dvec3(0, 0, 1));
    return glm::normalize(axis - n * glm::dot(n, axis));
}

// Box projection seen from outside (U to the right, V up, never mirrored): for each of the six
// axis directions, which coordinate becomes U and V and with which sign. Up is +Y for the four
// side directions; seen from +Y, up is -Z, and from -Y it is +Z.
struct BoxAxis {
    int u_axis;
    float u_sign;
    int v_axis;
    float v_sign;
};
constexpr BoxAxis kBoxAxes[6] = {
    {2, -1.0f, 1, 1.0f}, // +X: U = -z, V = y
    {2, 1.0f, 1, 1.0f},  // -X: U = z, V = y
    {0, 1.0f, 2, -1.0f}, // +Y: U = x, V = -z
    {0, 1.0f, 2, 1.0f},  // -Y: U = x, V = z
    {0, 1.0f, 1, 1.0f},  // +Z: U = x, V = y
    {0, -1.0f, 1, 1.0f}, // -Z: U = -x, V = y
};

std::string format_number(float x)
{
    std::ostringstream s;
    s << x;
    return s.str();
}

int box_direction(const dvec3& n)
{
    const dvec3 an = glm::abs(n);
    const int axis = an.x > an.y && an.x > an.z ? 0 : (an.y > an.z ? 1 : 2);
    return axis * 2 + (n[axis] >= 0.0 ? 0 : 1);
}

// Per face, the faces across its shared edges (one entry per edge): faces[offsets[f], offsets[f + 1]).
struct FaceNeighbours {
    std::vector<uint32_t> offsets;
    std::vector<uint32_t> faces;
    std::span<const uint32_t> of(size_t f) const
    {
        return {faces.data() + offsets[f], faces.data() + offsets[f + 1]};
    }
};

// The unit vector of box direction d (box_direction()).
dvec3 box_axis(int d)
{
    dvec3 a(0.0);
    a[d / 2] = d % 2 == 0 ? 1.0 : -1.0;
    return a;
}

// The welded position of corner k of a triangle: compacted weld id of its raw corner.
struct TriangleWelds {
    const std::vector<uint32_t>& compact;
    const std::vector<uint32_t>& weld_of;
    const std::vector<uint32_t>& corners;
    uint32_t operator()(const Triangle& t, int k) const { return compact[weld_of[corners[t.corner[k]]]]; }
};

// The faces across each shared edge of the faces for which generated(f) holds, from the other
// such faces: the one other triangle that has the edge too, if it lies in another face (a
// polygon's own diagonals do not count; nor do edges of three or more triangles). Edges are
// bucketed by their smaller end and sorted by the other within each bucket (as edge_adjacency
// does), so the time does not depend on how many triangles meet at a point or an edge: scanning
// the triangles around an edge's end, as it was done, took the square of their number where
// thousands met at both ends (30,000 copies of one triangle in one OBJ face: 21 s, found by an
// exploratory session).
template <class Generated>
FaceNeighbours generated_face_neighbours(const std::vector<Triangle>& tris, const TriangleWelds& welds,
                                         size_t weld_count, size_t face_count, Generated generated)
{
    std::vector<uint32_t> corner(tris.size() * 3); // welded position per triangle corner
    for (size_t i = 0; i < tris.size(); ++i)
        for (int k = 0; k < 3; ++k) corner[3 * i + size_t(k)] = welds(tris[i], k);
    const auto ends = [&](size_t edge) {
        const uint32_t a = corner[edge], b = corner[3 * (edge / 3) + (edge % 3 + 1) % 3];
        return std::pair{std::min(a, b), std::max(a, b)};
    };
    Buckets by_end = bucket_by_key(weld_count, corner.size(), [&](size_t e) { return ends(e).first; },
                                   [&](size_t e) { return generated(tris[e / 3].face); });
    const std::vector<uint32_t>& start = by_end.start;
    std::vector<uint32_t>& bucket = by_end.items;
    std::vector<uint32_t> across(tris.size() * 3, kNone); // the face across each triangle edge
    for (size_t w = 0; w < weld_count; ++w) {
        const auto first = bucket.begin() + start[w], last = bucket.begin() + start[w + 1];
        std::sort(first, last, [&](uint32_t x, uint32_t y) { return std::pair{ends(x).second, x} < std::pair{ends(y).second, y}; });
        for (auto it = first; it != last;) {
            auto same = it;
            while (same != last && ends(*same).second == ends(*it).second) ++same;
            if (same - it == 2) {
                const uint32_t x = *it, y = *(it + 1);
                const uint32_t fx = tris[x / 3].face, fy = tris[y / 3].face;
                if (fx != fy) {
                    across[x] = fy;
                    across[y] = fx;
                }
            }
            it = same;
        }
    }

    FaceNeighbours neighbours;
    neighbours.offsets.assign(face_count + 1, 0);
    for (size_t e = 0; e < across.size(); ++e) neighbours.offsets[tris[e / 3].face + 1] += across[e] != kNone;
    for (size_t f = 0; f < face_count; ++f) neighbours.offsets[f + 1] += neighbours.offsets[f];
    neighbours.faces.resize(neighbours.offsets[face_count]);
    std::vector<uint32_t> fill(neighbours.offsets.begin(), neighbours.offsets.end() - 1);
    for (size_t e = 0; e < across.size(); ++e)
        if (across[e] != kNone) neighbours.faces[fill[tris[e / 3].face]++] = across[e];
    return neighbours;
}

// The least cosine between a face's own normal and the axis of its box projection: 60 degrees,
// the texture stretched at most 2x (against 1.73x for the dominant axis).
constexpr double kMaxBoxTurn = 0.5;

// Tidies the charts of box projection (docs/mesh-input.md, "UVs"): the dominant axis alone leaves
// ragged chart boundaries and islands of a few faces where the surface turns near 45° to two axes,
// and every chart boundary is a UV seam (on a closed mesh, a tear of the displaced surface). A face
// may take another direction only if its normal is within 60° of that axis (the projection then
// stretches the texture at most 2×, against 1.73× for the dominant axis).
// - Small charts (fewer than max(16, faces / 64) faces) join the direction that most of their
//   boundary edges border, if all of their faces may take it.
// - Then teeth: a face whose edges border another direction on more than half of its shared edges
//   takes that direction, if it may; repeated (at most 16 rounds) until nothing changes.
// `direction`: per face, -1 for faces that keep their file's UVs (left alone); `normal`: per face,
// its own unit normal (0 for a face without area, which takes no other direction). `order`: the
// faces in the order both rules visit them, one that does not depend on the file's (each change
// shifts the counts the next face sees: the blob with its faces shuffled had other charts, 63
// pixels of a checker on it; found by an exploratory session, forty-seventh).
void tidy_box_charts(std::vector<int>& direction, const std::vector<dvec3>& normal, const FaceNeighbours& neighbours,
                     const std::vector<uint32_t>& order)
{
    const size_t faces = direction.size();
    const auto may_take = [&](size_t f, int d) { return glm::dot(normal[f], box_axis(d)) >= kMaxBoxTurn; };
    const auto most_common = [](const std::array<size_t, 6>& count) {
        return int(std::max_element(count.begin(), count.end()) - count.begin()); // ties: the lower
    };
    size_t generated = 0;
    for (int d : direction) generated += d >= 0;
    const size_t small = std::max<size_t>(16, generated / 64);

    // Small charts, each as one piece.
    std::vector<uint32_t> chart(faces, kNone), members;
    for (const uint32_t seed : order) {
        if (direction[seed] < 0 || chart[seed] != kNone) continue;
        members.assign(1, uint32_t(seed));
        chart[seed] = uint32_t(seed);
        for (size_t i = 0; i < members.size(); ++i)
            for (uint32_t g : neighbours.of(members[i]))
                if (chart[g] == kNone && direction[g] == direction[seed]) {
                    chart[g] = uint32_t(seed);
                    members.push_back(g);
                }
        if (members.size() >= small) continue;
        std::array<size_t, 6> border{};
        for (uint32_t f : members)
            for (uint32_t g : neighbours.of(f))
                if (direction[g] >= 0 && direction[g] != direction[seed]) ++border[size_t(direction[g])];
        if (*std::max_element(border.begin(), border.end()) == 0) continue;
        const int d = most_common(border);
        if (std::all_of(members.begin(), members.end(), [&](uint32_t f) { return may_take(f, d); }))
            for (uint32_t f : members) direction[f] = d;
    }

    // Teeth.
    for (int round = 0; round < 16; ++round) {
        bool changed = false;
        for (const uint32_t f : order) {
            if (direction[f] < 0) continue;
            std::array<size_t, 6> count{};
            size_t shared = 0;
            for (uint32_t g : neighbours.of(f))
                if (direction[g] >= 0) {
                    ++count[size_t(direction[g])];
                    ++shared;
                }
            const int d = most_common(count);
            if (d != direction[f] && 2 * count[size_t(d)] > shared && may_take(f, d)) {
                direction[f] = d;
                changed = true;
            }
        }
        if (!changed) break;
    }
}

} // namespace

PreparedMesh prepare_mesh(const RawMesh& raw, const MeshOptions& options, const std::string& name)
{
    if (!(options.uv_scale > 0.0f) || !std::isfinite(options.uv_scale))
        throw Error(name, "uv_scale for generated UVs must be a positive number");
    PreparedMesh out;
    out.had_normals = raw.had_normals;
    const size_t face_count = raw.face_count();

    // ---- triangle budget, before anything is allocated per triangle --------------------------
    unsigned long long triangle_estimate = 0;
    for (size_t f = 0; f < face_count; ++f) {
        const size_t n = raw.face_offsets[f + 1] - raw.face_offsets[f];
        if (n >= 3) triangle_estimate += n - 2;
    }
    if (triangle_estimate > options.max_triangles)
        throw Error(name, "has " + std::to_string(triangle_estimate) +
                              " triangles after triangulation; the limit is " +
                              std::to_string(options.max_triangles));

    // ---- weld referenced positions by exact equality ------------------------------------------
    std::vector<uint32_t> weld_of(raw.positions.size(), kNone);
    DenseIndex<PositionKey, PositionHash> welds(std::min(raw.positions.size(), raw.corners.size()));
    for (uint32_t v : raw.corners) {
        if (weld_of[v] != kNone) continue;
        const glm::vec3& p = raw.positions[v];
        weld_of[v] =
            welds.insert(PositionKey{{float_bits(p.x), float_bits(p.y), float_bits(p.z)}}).first;
    }
    auto weld_position = [&](uint32_t w) {
        const PositionKey& k = welds.keys()[w];
        return dvec3(std::bit_cast<float>(k.bits[0]), std::bit_cast<float>(k.bits[1]),
                     std::bit_cast<float>(k.bits[2]));
    };

    // ---- triangulate and drop zero-area triangles ----------------------------------------------
    std::vector<Triangle> tris;
    tris.reserve(size_t(triangle_estimate));
    size_t degenerate = raw.collapsed_faces;
    std::vector<dvec3> poly;
    std::vector<std::array<uint32_t, 3>> local;
    size_t clip_work_left = options.ear_clip_work;
    size_t fanned = 0;  // concave polygons past the ear clipping's limits
    size_t crossed = 0; // polygons whose outlines cross themselves
    std::vector<uint8_t> crossing(face_count, 0); // per face: its outline crosses itself
    size_t repeated_in_faces = 0, faces_repeating_triangles = 0;
    std::vector<std::pair<std::array<uint32_t, 3>, uint32_t>> in_face; // a polygon's triangles by their sorted welds
    std::vector<uint8_t> in_face_drop;
    for (size_t f = 0; f < face_count; ++f) {
        const uint32_t begin = raw.face_offsets[f];
        const size_t n = raw.face_offsets[f + 1] - begin;
        if (n < 3) {
            ++degenerate;
            continue;
        }
        poly.resize(n);
        for (size_t i = 0; i < n; ++i) poly[i] = weld_position(weld_of[raw.corners[begin + i]]);
        if (n == 3) {
            local.assign(1, {0, 1, 2}); // the common case, without the polygon machinery
        } else {
            const PolygonCut cut = triangulate_polygon(poly, local, clip_work_left);
            if (cut == PolygonCut::FannedPastLimits) ++fanned;
            if (cut == PolygonCut::CrossesItself) ++crossed, crossing[f] = 1;
        }
        const size_t first_triangle = tris.size();
        for (const auto& t : local) {
            const uint32_t w0 = weld_of[raw.corners[begin + t[0]]];
            const uint32_t w1 = weld_of[raw.corners[begin + t[1]]];
            const uint32_t w2 = weld_of[raw.corners[begin + t[2]]];
            const dvec3 c = glm::cross(poly[t[1]] - poly[t[0]], poly[t[2]] - poly[t[0]]);
            if (w0 == w1 || w1 == w2 || w0 == w2 || (c.x == 0.0 && c.y == 0.0 && c.z == 0.0)) {
                ++degenerate;
                continue;
            }
            tris.push_back({{begin + t[0], begin + t[1], begin + t[2]}, uint32_t(f)});
        }
        // A polygon whose outline runs over itself (a triangle listed 30,000 times in one face)
        // gives the same triangle again: the repeated-face pass below compares faces, not the
        // triangles of one, so the copies stayed, every edge shared by 30,000 of them, and the
        // prism's walk crossed them all. Dropped as a repeated face's are, in the same or the
        // opposite winding; the first is kept. (Only an outline through one point twice can
        // repeat a triangle.)
        if (n > 3 && tris.size() - first_triangle > 1) {
            in_face.clear();
            for (size_t i = first_triangle; i < tris.size(); ++i) {
                std::array<uint32_t, 3> w;
                for (int c = 0; c < 3; ++c) w[size_t(c)] = weld_of[raw.corners[tris[i].corner[c]]];
                std::sort(w.begin(), w.end());
                in_face.push_back({w, uint32_t(i)});
            }
            std::sort(in_face.begin(), in_face.end());
            size_t kept = first_triangle, dropped = 0;
            std::vector<uint8_t>& drop = in_face_drop;
            drop.assign(tris.size() - first_triangle, 0);
            for (size_t i = 1; i < in_face.size(); ++i)
                if (in_face[i].first == in_face[i - 1].first) {
                    drop[in_face[i].second - first_triangle] = 1; // the later in the triangulation
                    ++dropped;
                }
            if (dropped > 0) {
                for (size_t i = first_triangle; i < tris.size(); ++i)
                    if (!drop[i - first_triangle]) tris[kept++] = tris[i];
                tris.resize(kept);
                repeated_in_faces += dropped;
                ++faces_repeating_triangles;
            }
        }
    }
    if (repeated_in_faces > 0)
        warn(name + ": dropped " + std::to_string(repeated_in_faces) + " triangle" + (repeated_in_faces == 1 ? "" : "s") +
             " that repeat" + (repeated_in_faces == 1 ? "s" : "") + " another of the same face (" +
             std::to_string(faces_repeating_triangles) + " face" + (faces_repeating_triangles == 1 ? " whose outline runs" : "s whose outlines run") +
             " over itself; the first is kept)");
    if (fanned > 0)
        warn(name + ": " + std::to_string(fanned) + " concave polygon" + (fanned == 1 ? "" : "s") +
             " too large to clip (more than " + std::to_string(kEarClipCorners) +
             " corners, or past the time budget) triangulated as " + (fanned == 1 ? "a fan" : "fans") +
             ", which may cover area outside " + (fanned == 1 ? "its outline" : "their outlines"));
    // (No face number: the reader has dropped faces of fewer than three corners by then, so the
    // polygon's place in the file is not known here.)
    if (crossed > 0)
        warn(name + ": " + std::to_string(crossed) +
             (crossed == 1 ? " polygon's outline crosses itself" : " polygons' outlines cross themselves") +
             " (a bow tie?): triangulated as " + (crossed == 1 ? "it was" : "they were") +
             " given, which may cover area outside " + (crossed == 1 ? "its lobes" : "their lobes"));
    out.dropped_triangles = degenerate;
    if (tris.empty())
        throw Error(name,
                    "all " + std::to_string(degenerate) + " triangles are degenerate (zero area)");
    if (degenerate > 0) {
        // Far from the origin for its size, a mesh's float coordinates may be what flattened them
        // (a torus 5e6 out in a binary STL: floats 0.5 apart there, half its triangles lost): say so.
        glm::dvec3 lo(INFINITY), hi(-INFINITY);
        for (const glm::vec3& p : raw.positions) {
            lo = glm::min(lo, raw.origin + glm::dvec3(p));
            hi = glm::max(hi, raw.origin + glm::dvec3(p));
        }
        const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
        const double far = std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
        const bool coarse = raw.float_positions && extent > 0.0 && far * 1e-5 > extent;
        warn(name + ": dropped " + std::to_string(degenerate) + " degenerate (zero-area) triangle" +
             (degenerate == 1 ? "" : "s") +
             (coarse ? " (its coordinates are far from the origin for its size, beyond what its file's 32-bit floats "
                       "keep; ASCII OBJ, OFF and PLY and binary PLY of doubles are read in double)"
                     : ""));
    }

    // ---- faces that repeat another face --------------------------------------------------------
    // A face whose corners are the welded positions of an earlier face in the same cyclic order
    // (listed twice) or in the reverse order (the back of a two-sided sheet). The first listed
    // copy is kept and the repeats are dropped (docs/mesh-input.md, "Repeated faces"). A
    // same-winding repeat adds nothing to the picture but three faces on an edge, double weight
    // in the welded normals and edges "of opposite orientation", and it kept a closed mesh wound
    // inward from being reversed. An opposite-winding repeat cancelled the welded normals (a
    // fallback direction lay in the sheet, and the displacement slid sideways), and kept, with
    // the face's normal, it is a second copy of the same displaced surface, seen from the other
    // side: the two fought for the same pixels (dark speckles in every technique but the prism).
    // Every surface is drawn from both sides anyway, the back as the displaced surface's back.
    size_t same_repeats = 0, opposite_repeats = 0;
    {
        std::vector<uint8_t> has_triangle(face_count, 0);
        for (const Triangle& t : tris) has_triangle[t.face] = 1;
        auto face_welds = [&](size_t f, std::vector<uint32_t>& ids) {
            ids.clear();
            for (uint32_t c = raw.face_offsets[f]; c < raw.face_offsets[f + 1]; ++c)
                ids.push_back(weld_of[raw.corners[c]]);
        };
        // Faces grouped by their sorted welded positions (a hash, then the exact comparison).
        std::vector<std::pair<uint64_t, uint32_t>> order;
        order.reserve(face_count);
        std::vector<uint32_t> ids, other;
        for (size_t f = 0; f < face_count; ++f) {
            if (!has_triangle[f]) continue;
            face_welds(f, ids);
            std::sort(ids.begin(), ids.end());
            uint64_t h = mix64(ids.size());
            for (uint32_t id : ids) h = mix64(h ^ id);
            order.emplace_back(h, uint32_t(f));
        }
        std::sort(order.begin(), order.end());
        // 0: not a repeat of `a`; 1: the same cyclic order; 2: reversed.
        auto repeat_kind = [](const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
            const size_t n = a.size();
            if (b.size() != n) return 0;
            for (size_t r = 0; r < n; ++r) {
                if (b[r] != a[0]) continue;
                bool forward = true, backward = true;
                for (size_t i = 1; i < n && (forward || backward); ++i) {
                    forward = forward && b[(r + i) % n] == a[i];
                    backward = backward && b[(r + n - i) % n] == a[i];
                }
                if (forward) return 1;
                if (backward) return 2;
            }
            return 0;
        };
        std::vector<uint8_t> drop(face_count, 0);
        for (size_t i = 0; i < order.size();) {
            size_t j = i + 1;
            while (j < order.size() && order[j].first == order[i].first) ++j;
            // In file order within the group: each face is compared with the earlier ones that
            // are not repeats themselves.
            for (size_t b = i + 1; b < j; ++b) {
                face_welds(order[b].second, ids);
                for (size_t a = i; a < b; ++a) {
                    const uint32_t fa = order[a].second;
                    if (drop[fa]) continue;
                    face_welds(fa, other);
                    const int kind = repeat_kind(other, ids);
                    if (kind == 1) {
                        drop[order[b].second] = 1;
                        ++same_repeats;
                    } else if (kind == 2) {
                        drop[order[b].second] = 1;
                        ++opposite_repeats;
                    }
                    if (kind != 0) break;
                }
            }
            i = j;
        }
        if (same_repeats + opposite_repeats > 0)
            tris.erase(std::remove_if(tris.begin(), tris.end(), [&](const Triangle& t) { return drop[t.face] != 0; }),
                       tris.end());
    }
    if (same_repeats > 0)
        warn(name + ": dropped " + std::to_string(same_repeats) + " face" + (same_repeats == 1 ? "" : "s") +
             " that repeat" + (same_repeats == 1 ? "s" : "") +
             " another face (the same corners in the same order; the first is kept)");
    if (opposite_repeats > 0)
        warn(name + ": " + std::to_string(opposite_repeats) + " face" + (opposite_repeats == 1 ? "" : "s") +
             " repeat" + (opposite_repeats == 1 ? "s" : "") +
             " another face with the opposite winding (the back of a two-sided sheet): dropped, the first "
             "is kept and drawn from both sides");

    // ---- compact weld ids to the positions that survive ----------------------------------------
    std::vector<uint32_t> compact(welds.size(), kNone);
    std::vector<dvec3> wpos;
    const TriangleWelds tri_weld{compact, weld_of, raw.corners};
    for (const Triangle& t : tris) {
        for (int k = 0; k < 3; ++k) {
            uint32_t& c = compact[weld_of[raw.corners[t.corner[k]]]];
            if (c == kNone) {
                c = uint32_t(wpos.size());
                wpos.push_back(weld_position(weld_of[raw.corners[t.corner[k]]]));
            }
        }
    }
    const size_t weld_count = wpos.size();
    out.weld_count = uint32_t(weld_count);

    dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const dvec3& p : wpos) {
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
    }
    out.bbox_min = glm::vec3(lo);
    out.bbox_max = glm::vec3(hi);
    const dvec3 centre = 0.5 * (lo + hi);
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});

    // ---- faces wound against their neighbours, turned to agree ---------------------------------
    // An edge that two triangles run the same way joins faces of opposite orientation: their
    // welded normals cancel there and the shell folds (the walk lost whole triangles: two quads,
    // one reversed, IoU 0.63). Across the edges of exactly two triangles, each connected piece is
    // oriented one way: a closed one (no edge of one triangle) outward, or inward inside an odd
    // number of other closed pieces; an open one the way most of its area already winds; a piece
    // that cannot be (a Moebius strip) keeps its winding. Edges of three or more triangles are
    // not crossed, and do not open a piece (a fin on a closed body).
    // Edge keys pack two 31-bit weld ids and a direction bit into 64 bits (here and for the
    // topology remarks below).
    const auto edge_key = [&](const Triangle& t, int k) {
        const uint64_t a = tri_weld(t, k), b = tri_weld(t, (k + 1) % 3);
        return (std::min(a, b) << 32 | std::max(a, b)) << 1 | (a < b ? 0u : 1u);
    };
    size_t closed_pieces = 0; // closed, orientable pieces (the whole mesh's reversal below needs it)
    const auto normal = [&](const Triangle& v) {
        const dvec3 a = wpos[tri_weld(v, 0)];
        return glm::cross(wpos[tri_weld(v, 1)] - a, wpos[tri_weld(v, 2)] - a);
    };
    // Whether two triangles wind the same way round one plane (unit normals within 1e-6).
    const auto overlapping = [&](const Triangle& t, const Triangle& u) {
        const dvec3 n = normal(t), m = normal(u);
        const double lengths = glm::length(n) * glm::length(m);
        return lengths > 0.0 && glm::dot(n, m) > (1.0 - 1e-6) * lengths;
    };
    std::vector<uint64_t> overlaps; // edges (keys without direction) of two such triangles, ascending (as `sides`)
    // Whether two triangles on an edge lie back to back: folded flat onto each other across it
    // (unit normals opposite within 1e-6, the corners off the edge on the same side of it).
    const auto back_to_back = [&](const Triangle& t, const Triangle& u, uint64_t key) {
        const uint32_t ia = uint32_t(key >> 33), ib = uint32_t(key >> 1); // (edge_key's two weld ids)
        const dvec3 a = wpos[ia], b = wpos[ib];
        const auto off_edge = [&](const Triangle& v) {
            for (int k = 0; k < 3; ++k)
                if (tri_weld(v, k) != ia && tri_weld(v, k) != ib) return wpos[tri_weld(v, k)];
            return a;
        };
        const dvec3 n = normal(t), m = normal(u), p = off_edge(t), q = off_edge(u);
        const double lengths = glm::length(n) * glm::length(m);
        return lengths > 0.0 && glm::dot(n, m) < -(1.0 - 1e-6) * lengths &&
               glm::dot(glm::cross(b - a, p - a), n) * glm::dot(glm::cross(b - a, q - a), n) > 0.0;
    };
    // Faces with a triangle back to back on another: a two-sided sheet whose back does not repeat
    // its front's faces (those were dropped above), a flap folded flat. Both sides are drawn and
    // fight for the same pixels, their welded normals cancel, and the prism's walk loses its way
    // (an 8 x 8 plane with its reverse cut along the other diagonals: IoU 0.85 against the
    // reference, which is dark speckles itself; found by an exploratory session, forty-fourth):
    // said, not mended (which side was meant is not known, and a back may cover its front only
    // in part).
    std::vector<uint8_t> backed(face_count, 0);
    if (weld_count < (size_t(1) << 31) && !tris.empty()) {
        struct Side {
            uint64_t key; // lower weld id, upper weld id, direction bit
            uint32_t tri;
        };
        std::vector<Side> sides;
        sides.reserve(tris.size() * 3);
        for (size_t i = 0; i < tris.size(); ++i)
            for (int k = 0; k < 3; ++k)
                if (tri_weld(tris[i], k) != tri_weld(tris[i], (k + 1) % 3)) sides.push_back({edge_key(tris[i], k), uint32_t(i)});
        std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) { return x.key < y.key; });
        // Per triangle, up to three neighbours across edges of two triangles: (neighbour << 1) |
        // whether the two run that edge the same way (one of them must turn); and whether it has
        // an edge of its own (a boundary: its piece is open).
        std::vector<uint64_t> across(tris.size() * 3, ~uint64_t(0));
        std::vector<uint8_t> count(tris.size(), 0), boundary(tris.size(), 0);
        for (size_t i = 0; i < sides.size();) {
            size_t j = i;
            while (j < sides.size() && (sides[j].key >> 1) == (sides[i].key >> 1)) ++j;
            if (j - i == 1) boundary[sides[i].tri] = 1;
            for (size_t x = i; x < j && j - i <= 16; ++x) // (16: a fan of more on one edge is said anyway)
                for (size_t y = x + 1; y < j; ++y)
                    // (Not two triangles of one bow tie, folded by its own triangulation: said as
                    // crossing itself already, it read as a two-sided sheet too; an exploratory
                    // session, forty-ninth.)
                    if (!(tris[sides[x].tri].face == tris[sides[y].tri].face && crossing[tris[sides[x].tri].face]) &&
                        back_to_back(tris[sides[x].tri], tris[sides[y].tri], sides[i].key))
                        backed[tris[sides[x].tri].face] = backed[tris[sides[y].tri].face] = 1;
            if (j - i == 2 && sides[i].tri != sides[i + 1].tri) {
                const uint32_t x = sides[i].tri, y = sides[i + 1].tri;
                const uint64_t same = (sides[i].key & 1u) == (sides[i + 1].key & 1u);
                // Run the same way and wound the same way round one plane: the two lie over one
                // another on the same side of the edge (a quad drawn as both of its triangulations),
                // not a face turned over. Turning one put the pair back to back, their normals
                // cancelled and the prism lost 40 % of the surface (IoU 0.62; found by an
                // exploratory session). Not crossed; counted for the remark below.
                if (same && overlapping(tris[x], tris[y])) {
                    overlaps.push_back(sides[i].key >> 1);
                    i = j;
                    continue;
                }
                if (count[x] < 3) across[3 * x + count[x]++] = uint64_t(y) << 1 | same;
                if (count[y] < 3) across[3 * y + count[y]++] = uint64_t(x) << 1 | same;
            }
            i = j;
        }
        sides = {};
        // The pieces: triangles joined by edges of two triangles, each wound one way by `turn`
        // relative to its first triangle where it can be.
        struct Piece {
            size_t first, last; // in `order`
            bool orientable = true, disagrees = false, closed = true;
            size_t on_fins = 0; // triangles with an edge of three or more triangles
            double volume = 0.0; // six times the signed volume, as wound after `turn`
            dvec3 lo{std::numeric_limits<double>::max()}, hi{-std::numeric_limits<double>::max()};
        };
        std::vector<int8_t> turn(tris.size(), -1); // -1: not reached; 0 keep, 1 turn
        std::vector<uint32_t> order, stack;
        order.reserve(tris.size());
        std::vector<Piece> pieces;
        for (size_t seed = 0; seed < tris.size(); ++seed) {
            if (turn[seed] >= 0) continue;
            Piece piece;
            piece.first = order.size();
            turn[seed] = 0;
            stack.assign(1, uint32_t(seed));
            while (!stack.empty()) {
                const uint32_t t = stack.back();
                stack.pop_back();
                order.push_back(t);
                piece.closed = piece.closed && !boundary[t];
                piece.on_fins += count[t] < 3 && !boundary[t];
                for (int k = 0; k < count[t]; ++k) {
                    const uint32_t n = uint32_t(across[3 * t + k] >> 1);
                    const int8_t want = int8_t(turn[t] ^ int8_t(across[3 * t + k] & 1u));
                    piece.disagrees = piece.disagrees || (across[3 * t + k] & 1u) != 0;
                    if (turn[n] < 0) {
                        turn[n] = want;
                        stack.push_back(n);
                    } else if (turn[n] != want) {
                        piece.orientable = false;
                    }
                }
            }
            piece.last = order.size();
            // Closed: no edge of one triangle, and at most a few triangles (2 %) on edges of three
            // or more (a fin on a body). Pieces cut off by such edges (two cubes sharing a face: each
            // an open box, the face's triangles alone) have no inside to tell.
            const size_t size = piece.last - piece.first;
            piece.closed = piece.closed && size >= 4 && piece.on_fins * 50 <= size;
            const dvec3 origin = wpos[tri_weld(tris[seed], 0)];
            for (size_t i = piece.first; i < piece.last; ++i) {
                const Triangle& t = tris[order[i]];
                const dvec3 a = wpos[tri_weld(t, 0)], b = wpos[tri_weld(t, 1)], c = wpos[tri_weld(t, 2)];
                piece.volume += (turn[order[i]] ? -1.0 : 1.0) * glm::dot(a - origin, glm::cross(b - origin, c - origin));
                piece.lo = glm::min(piece.lo, glm::min(a, glm::min(b, c)));
                piece.hi = glm::max(piece.hi, glm::max(a, glm::max(b, c)));
            }
            pieces.push_back(piece);
        }
        // Whether `p` lies inside closed piece q (by the parity of three rays' crossings: a ray
        // through an edge may count one twice), for how deep a closed piece is nested.
        const auto inside = [&](const dvec3& p, const Piece& q) {
            if (glm::any(glm::lessThan(p, q.lo)) || glm::any(glm::greaterThan(p, q.hi))) return false;
            int votes = 0;
            for (const dvec3& d : vote_ray_directions()) {
                bool odd = false;
                for (size_t i = q.first; i < q.last; ++i) {
                    const Triangle& t = tris[order[i]];
                    odd = odd != (ray_crossing(p, d, wpos[tri_weld(t, 0)], wpos[tri_weld(t, 1)], wpos[tri_weld(t, 2)]) != 0);
                }
                votes += odd;
            }
            return votes >= 2;
        };
        for (const Piece& q : pieces) closed_pieces += q.closed && q.orientable;
        std::vector<uint8_t> turned_face(face_count, 0);
        size_t turned_faces = 0, pieces_left = 0, pieces_turned = 0;
        size_t nesting_work_left = size_t(1) << 28; // triangle tests for how deep pieces are nested
        bool nesting_unknown = false;
        for (const Piece& piece : pieces) {
            if (!piece.orientable) {
                pieces_left += piece.disagrees;
                for (size_t i = piece.first; i < piece.last; ++i) turn[order[i]] = 0;
                continue;
            }
            // A closed piece with faces against their neighbours winds outward (its signed volume
            // positive), or inward where it lies inside an odd number of other closed pieces (a
            // hollow solid's cavity). One wound one way throughout keeps the file's winding but
            // where it is wound inward and lies inside no other piece (a body the wrong way
            // round beside others, closed or open: a sheet beside it kept the whole mesh's
            // reversal below from seeing it closed; a mesh of that one piece alone is left to
            // that reversal); nested, either winding may be meant (a cavity, or a body inside a
            // transparent one). An open piece with faces against their neighbours winds as most
            // of its area does.
            int8_t flip = 0;
            if (piece.closed && (piece.disagrees || (pieces.size() > 1 && piece.volume < 0.0))) {
                // Nested in q: the piece's box strictly inside q's, and three of its triangles'
                // centres (the first, middle and last) inside q. (One centre alone lay on a face
                // q shares a plane with — a table's leg under its top — or inside a body it only
                // runs through.) Within a budget of box and triangle tests: a body of a million
                // triangles holding ten thousand small ones took 3·10^10; past it, a piece is
                // nested in none (wound outward), with a warning.
                const size_t size = piece.last - piece.first;
                const auto centre = [&](size_t i) {
                    const Triangle& t = tris[order[piece.first + i]];
                    return (wpos[tri_weld(t, 0)] + wpos[tri_weld(t, 1)] + wpos[tri_weld(t, 2)]) / 3.0;
                };
                const dvec3 probes[3] = {centre(0), centre(size / 2), centre(size - 1)};
                int depth = 0;
                bool told = true;
                if (closed_pieces > 1)
                    for (const Piece& q : pieces) {
                        if (nesting_work_left == 0) {
                            told = false;
                            break;
                        }
                        --nesting_work_left;
                        if (&q == &piece || !q.closed || !q.orientable) continue;
                        if (!glm::all(glm::greaterThan(piece.lo, q.lo)) || !glm::all(glm::lessThan(piece.hi, q.hi)))
                            continue;
                        const size_t cost = 9 * (q.last - q.first);
                        if (cost > nesting_work_left) {
                            told = false;
                            break;
                        }
                        nesting_work_left -= cost;
                        depth += inside(probes[0], q) && inside(probes[1], q) && inside(probes[2], q);
                    }
                if (!told) {
                    nesting_unknown = true;
                    depth = 0;
                }
                if (piece.disagrees)
                    flip = (piece.volume < 0.0) == (depth % 2 == 0) ? 1 : 0;
                else
                    flip = depth == 0 ? 1 : 0; // (wound inward, here)
                pieces_turned += piece.disagrees ? 0 : flip;
            } else if (piece.disagrees) {
                double kept = 0.0, turned = 0.0;
                for (size_t i = piece.first; i < piece.last; ++i) {
                    const Triangle& t = tris[order[i]];
                    const dvec3 a = wpos[tri_weld(t, 0)], b = wpos[tri_weld(t, 1)], c = wpos[tri_weld(t, 2)];
                    (turn[order[i]] ? turned : kept) += glm::length(glm::cross(b - a, c - a));
                }
                flip = turned > kept ? 1 : 0;
            }
            for (size_t i = piece.first; i < piece.last; ++i) {
                const uint32_t t = order[i];
                turn[t] = int8_t(turn[t] ^ flip);
                if (!turn[t]) continue;
                std::swap(tris[t].corner[1], tris[t].corner[2]);
                if (piece.disagrees && !turned_face[tris[t].face]) ++turned_faces;
                turned_face[tris[t].face] = 1;
            }
        }
        if (turned_faces > 0)
            warn(name + ": " + std::to_string(turned_faces) + " face" + (turned_faces == 1 ? "" : "s") +
                 " wound against " + (turned_faces == 1 ? "its" : "their") +
                 " neighbours (the welded normals cancel there) turned so that each piece winds one way "
                 "(a closed one outward, or inward as a cavity)");
        if (pieces_turned > 0)
            warn(name + ": " + std::to_string(pieces_turned) + " of its " + std::to_string(closed_pieces) +
                 " closed pieces wound inward, and inside no other piece, turned outward");
        if (pieces_left > 0)
            warn(name + ": " + std::to_string(pieces_left) + " piece" + (pieces_left == 1 ? "" : "s") +
                 " cannot be wound one way (a Moebius strip?): kept as in the file; where its faces meet "
                 "against each other the welded normals cancel and the prism's shell folds, which may "
                 "lose surface there");
        if (nesting_unknown)
            warn(name + ": too many closed pieces to tell every cavity among them in time; those not "
                        "told were wound outward");
    }

    // ---- angle-weighted welded normals ---------------------------------------------------------
    // Triangles so thin that float rounding of their corners decides their normal are left out
    // of the angle-weighted sum (their obtuse corner would weigh almost pi); the plain sum of
    // cross products is the fallback for a position that only touches such triangles.
    std::vector<dvec3> nsum(weld_count, dvec3(0.0)), csum(weld_count, dvec3(0.0));
    std::vector<double> angle_sum(weld_count, 0.0), cross_sum(weld_count, 0.0);
    // The unit normal of the first triangle (in file order) around each position: the direction
    // of a position whose faces cancel.
    std::vector<dvec3> first_normal(weld_count, dvec3(0.0));
    for (const Triangle& t : tris) {
        const uint32_t w[3] = {tri_weld(t, 0), tri_weld(t, 1), tri_weld(t, 2)};
        const dvec3 &a = wpos[w[0]], &b = wpos[w[1]], &c = wpos[w[2]];
        const dvec3 cr = glm::cross(b - a, c - a);
        const double len = glm::length(cr);
        for (uint32_t wi : w) {
            csum[wi] += cr;
            cross_sum[wi] += len;
            if (len > 0.0 && first_normal[wi] == dvec3(0.0)) first_normal[wi] = cr / len;
        }
        if (!normal_is_sound(a, b, c, len)) continue;
        const dvec3 fn = cr / len;
        const double angles[3] = {corner_angle(a, b, c), corner_angle(b, c, a),
                                  corner_angle(c, a, b)};
        for (int k = 0; k < 3; ++k) {
            nsum[w[k]] += angles[k] * fn;
            angle_sum[w[k]] += angles[k];
        }
    }
    std::vector<dvec3> wnormal(weld_count);
    size_t fallback_normals = 0;
    for (size_t i = 0; i < weld_count; ++i) {
        // Relative to the total weight: what is left after near-complete cancellation is noise.
        const double l = glm::length(nsum[i]);
        if (l > 1e-6 * angle_sum[i] && l > 0.0) {
            wnormal[i] = nsum[i] / l;
            continue;
        }
        const double lc = glm::length(csum[i]);
        if (angle_sum[i] == 0.0 && lc > 1e-6 * cross_sum[i] && lc > 0.0) {
            wnormal[i] = csum[i] / lc; // only slivers around it: their summed cross products
            continue;
        }
        // Cancelled (faces of opposite orientation at one position, e.g. a fin folded flat or
        // two sheets back to back): the first face's side. Sums of cross products cancel as well,
        // to rounding noise, and a direction radial from the box's centre lay in a flat sheet, so
        // the displacement slid sideways.
        ++fallback_normals;
        const dvec3 d = wpos[i] - centre;
        if (first_normal[i] != dvec3(0.0))
            wnormal[i] = first_normal[i];
        else if (glm::length(d) > 0.0)
            wnormal[i] = glm::normalize(d);
        else
            wnormal[i] = dvec3(0, 0, 1);
    }
    if (fallback_normals > 0)
        warn(name + ": " + std::to_string(fallback_normals) +
             (fallback_normals == 1 ? " position has no defined normal (its faces cancel out); used the normal of "
                                      "the first face around it"
                                    : " positions have no defined normal (their faces cancel out); used the "
                                      "normal of the first face around each"));

    // ---- topology remarks: non-manifold edges and inconsistent orientation ---------------------
    if (weld_count < (size_t(1) << 31)) {
        std::vector<uint64_t> edges;
        edges.reserve(tris.size() * 3);
        for (const Triangle& t : tris)
            for (int k = 0; k < 3; ++k) edges.push_back(edge_key(t, k));
        std::sort(edges.begin(), edges.end());
        // unbalanced: edges run more often one way than the other (every edge of a closed,
        // consistently oriented surface runs once each way per pair of faces on it).
        size_t non_manifold = 0, flipped = 0, boundary = 0, unbalanced = 0, overlapping_edges = 0;
        for (size_t i = 0; i < edges.size();) {
            size_t j = i, forward = 0;
            while (j < edges.size() && (edges[j] >> 1) == (edges[i] >> 1)) {
                forward += (edges[j] & 1u) == 0u;
                ++j;
            }
            const size_t count = j - i;
            if (count > 2)
                ++non_manifold;
            else if (count == 2 && forward != 1 && !std::binary_search(overlaps.begin(), overlaps.end(), edges[i] >> 1))
                ++flipped;
            else if (count == 2 && forward != 1)
                ++overlapping_edges;
            else if (count == 1)
                ++boundary;
            unbalanced += 2 * forward != count;
            i = j;
        }
        edges = {};
        // A closed, consistently oriented mesh wound the other way round (clockwise seen from
        // outside: its signed volume is negative) has every normal pointing in, so its shell and
        // bumps would go inward and the prism would show the body from inside. Such files are
        // common (a mirrored export, another convention) and meant outward: reversed, with a
        // warning. "Closed and consistent" is: every edge runs as often one way as the other,
        // which allows non-manifold edges where closed pieces touch (four faces on an edge, two
        // each way); the signed volume is then the enclosed volume wherever it is taken from. An
        // open or inconsistently oriented mesh has no inside to tell: it keeps its winding, with a
        // warning when it is nearly closed (the faces' area vectors sum to under a fifth of their
        // total area: a hole, a few flipped faces) and its signed volume about the box's centre
        // is clearly negative (more than three quarters of the faces' volume turned inward), e.g.
        // a sphere wound inward with a face missing or flipped. (A hemisphere's opening is half
        // its area: a bowl, either winding may be meant; a spherical cap passes the fifth beyond
        // about 127 degrees from its pole.)
        double volume = 0.0, magnitude = 0.0; // six times the signed (and unsigned) volume about the centre
        dvec3 area(0.0);                      // twice the summed area vectors
        double area_total = 0.0;
        std::vector<double> face_volume(face_count, 0.0);
        for (const Triangle& t : tris) {
            const dvec3 a = wpos[tri_weld(t, 0)] - centre, b = wpos[tri_weld(t, 1)] - centre,
                        c = wpos[tri_weld(t, 2)] - centre;
            const double v = glm::dot(a, glm::cross(b, c));
            volume += v;
            magnitude += std::fabs(v);
            face_volume[t.face] += v;
            const dvec3 cr = glm::cross(b - a, c - a);
            area += cr;
            area_total += glm::length(cr);
        }
        // (Several closed pieces were each wound above: the total volume must not undo that.)
        const bool closed = unbalanced == 0 && closed_pieces < 2;
        if (volume < 0.0 &&
            (closed ? -volume > 1e-9 * magnitude : -volume > 0.5 * magnitude && glm::length(area) < 0.2 * area_total)) {
            if (closed) {
                for (Triangle& t : tris) std::swap(t.corner[1], t.corner[2]);
                for (dvec3& n : wnormal) n = -n;
                warn(name + ": the faces wind clockwise seen from outside (the closed mesh's volume is "
                            "negative): reversed, so that its normals point out");
            } else {
                size_t inward = 0, faces = 0;
                std::vector<uint8_t> counted(face_count, 0);
                for (const Triangle& t : tris) {
                    if (counted[t.face]) continue;
                    counted[t.face] = 1;
                    ++faces;
                    inward += face_volume[t.face] < 0.0;
                }
                std::string why;
                auto add = [&](size_t n, const std::string& what) {
                    if (n == 0) return;
                    why += (why.empty() ? "" : ", ") + std::to_string(n) + " " + what;
                };
                add(boundary, "open edges");
                add(flipped, "edges joining faces of opposite orientation");
                if (boundary == 0 && flipped == 0) add(unbalanced, "non-manifold edges with more faces one way than the other");
                warn(name + ": the faces appear to wind clockwise seen from outside (the signed volume is "
                            "negative: " + std::to_string(inward) + " of " + std::to_string(faces) +
                     " faces turn towards the middle), but the mesh is not closed and consistently oriented (" +
                     why + "): not reversed, so its normals, shell and bumps may point inward; fix the file's winding");
            }
        }
        if (non_manifold > 0)
            warn(name + ": " + std::to_string(non_manifold) +
                 (non_manifold == 1 ? " edge is" : " edges are") +
                 " shared by more than two faces (non-manifold); rendered as they are");
        // Vertices where fans of faces that share no edge meet (two solids touching at a point):
        // the welded normal there averages the fans', and the prism's shell folds about it (two
        // cones touching at their apex lost a third of one cone near it, IoU 0.89, without a word;
        // found by an exploratory session, thirty-fourth; docs/prism.md "Known limits").
        {
            // Each weld's corners (corner c is triangle c / 3's), bucketed by weld (a sort of the
            // pairs took 11 % of a million-triangle mesh's load; found by a review).
            const Buckets around = bucket_by_key(weld_count, tris.size() * 3,
                                                 [&](size_t c) { return tri_weld(tris[c / 3], int(c % 3)); });
            const std::vector<uint32_t>& first = around.start;
            size_t pinched = 0;
            std::vector<uint32_t> parent;
            std::vector<std::pair<uint32_t, uint32_t>> neighbours; // (other weld, the fan's triangle)
            for (size_t v = 0; v < weld_count; ++v) {
                const size_t i = first[v], j = first[v + 1];
                if (j - i < 2) continue;
                parent.resize(j - i);
                for (size_t k = 0; k < parent.size(); ++k) parent[k] = uint32_t(k);
                const auto root = [&](uint32_t k) {
                    while (parent[k] != k) k = parent[k] = parent[parent[k]];
                    return k;
                };
                neighbours.clear();
                for (size_t k = i; k < j; ++k)
                    for (int c = 0; c < 3; ++c)
                        if (const uint32_t w = uint32_t(tri_weld(tris[around.items[k] / 3], c)); w != v)
                            neighbours.push_back({w, uint32_t(k - i)});
                std::sort(neighbours.begin(), neighbours.end());
                for (size_t k = 1; k < neighbours.size(); ++k)
                    if (neighbours[k].first == neighbours[k - 1].first)
                        parent[root(neighbours[k].second)] = root(neighbours[k - 1].second);
                size_t fans = 0;
                for (size_t k = 0; k < parent.size(); ++k) fans += root(uint32_t(k)) == k;
                pinched += fans > 1;
            }
            if (pinched > 0)
                warn(name + ": " + std::to_string(pinched) + (pinched == 1 ? " vertex joins" : " vertices join") +
                     " fans of faces that share no edge (non-manifold: pieces touching at a point, or joined by T-junctions); the welded "
                     "normal there averages them, and the prism's shell may fold about it");
        }
        if (flipped > 0)
            warn(name + ": " + std::to_string(flipped) + (flipped == 1 ? " edge joins" : " edges join") +
                 " faces of opposite orientation; welded normals may cancel there");
        if (overlapping_edges > 0)
            warn(name + ": " + std::to_string(overlapping_edges) +
                 (overlapping_edges == 1 ? " edge joins" : " edges join") + " faces that lie over one another (wound the same way round one plane); rendered as they are");
    }
    if (const size_t n = size_t(std::count(backed.begin(), backed.end(), uint8_t(1))); n > 0)
        warn(name + ": " + std::to_string(n) + (n == 1 ? " face lies" : " faces lie") +
             " back to back on others, folded flat across an edge (a two-sided sheet whose back is not a copy of its "
             "front's faces?): rendered as they are, the two sides fighting for the same pixels and the prism's shell "
             "folded; keep one side");

    // ---- UVs per triangle corner ----------------------------------------------------------------
    const bool file_uvs = !options.force_generated_uvs && !raw.face_has_uv.empty();
    auto face_uses_file_uv = [&](uint32_t f) { return file_uvs && raw.face_has_uv[f] != 0; };
    std::vector<int> face_direction(face_count, -1);
    size_t generated_faces = 0;
    const bool any_generated =
        !file_uvs || std::any_of(raw.face_has_uv.begin(), raw.face_has_uv.end(), [](uint8_t h) { return h == 0; });
    if (any_generated) {
        const FaceNeighbours neighbours =
            generated_face_neighbours(tris, tri_weld, weld_count, face_count,
                                      [&](uint32_t f) { return !face_uses_file_uv(f); });
        // Dominant axis of each face's averaged welded normal (face normal if that cancels).
        std::vector<dvec3> fsum(face_count, dvec3(0.0)), fcross(face_count, dvec3(0.0));
        for (const Triangle& t : tris) {
            if (face_uses_file_uv(t.face)) continue;
            for (int k = 0; k < 3; ++k) fsum[t.face] += wnormal[tri_weld(t, k)];
            const dvec3 &a = wpos[tri_weld(t, 0)], &b = wpos[tri_weld(t, 1)],
                        &c = wpos[tri_weld(t, 2)];
            fcross[t.face] += glm::cross(b - a, c - a);
        }
        // The axis is judged against the face's own normal (its plane is what the projection
        // stretches): at a sharp edge the corners' welded normals lean far from the face, and a
        // wedge's side took the axis in its own plane, its uvs on a line (the texture smeared to
        // stripes, an STL's above all, which has no uvs; found by an exploratory session,
        // thirty-sixth). Where the welded normals' axis lies more than 60 degrees from it, the
        // face takes its own normal's; tidy_box_charts keeps to the same bound.
        std::vector<dvec3>& face_normal = fcross; // (reused: the face's own unit normal)
        for (size_t f = 0; f < face_count; ++f) {
            if (face_uses_file_uv(uint32_t(f))) continue;
            const double own = glm::length(fcross[f]);
            face_normal[f] = own > 0.0 ? fcross[f] / own : dvec3(0.0);
            const dvec3 s = glm::length(fsum[f]) > 1e-9 ? fsum[f] : fcross[f];
            face_direction[f] = box_direction(s);
            if (own > 0.0 && glm::dot(face_normal[f], box_axis(face_direction[f])) < kMaxBoxTurn)
                face_direction[f] = box_direction(face_normal[f]);
        }
        fsum = {};
        // The faces by where they are: the mean of each one's distinct corners, then its normal
        // (then its number, for faces alike in both: none in a file of distinct faces). A face's
        // triangles lie together in `tris`, faces in order (made so above, and only ever removed).
        std::vector<dvec3> centre(face_count, dvec3(0.0));
        std::vector<uint32_t> corners; // the welds of one face's triangles
        for (size_t i = 0; i < tris.size();) {
            const uint32_t f = tris[i].face;
            corners.clear();
            for (; i < tris.size() && tris[i].face == f; ++i)
                for (int k = 0; k < 3; ++k) corners.push_back(tri_weld(tris[i], k));
            std::sort(corners.begin(), corners.end());
            const auto end = std::unique(corners.begin(), corners.end());
            for (auto it = corners.begin(); it != end; ++it) centre[f] += wpos[*it];
            centre[f] /= double(end - corners.begin());
        }
        std::vector<uint32_t> order(face_count);
        std::iota(order.begin(), order.end(), 0u);
        const auto key = [&](uint32_t f) {
            return std::tuple{centre[f].x, centre[f].y, centre[f].z, face_normal[f].x, face_normal[f].y, face_normal[f].z};
        };
        std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
            const auto ka = key(a), kb = key(b);
            return ka != kb ? ka < kb : a < b;
        });
        tidy_box_charts(face_direction, face_normal, neighbours, order);
    }
    const double uv_per_unit = extent > 0.0 ? double(options.uv_scale) / extent : 1.0;
    auto generated_uv = [&](uint32_t weld, int direction) {
        const BoxAxis& ax = kBoxAxes[direction];
        const dvec3& p = wpos[weld];
        // Offsets from the box corner keep generated UVs in [0, uv_scale]; the same formula for
        // every face of a direction keeps them continuous.
        const double u =
            ax.u_sign > 0 ? p[ax.u_axis] - lo[ax.u_axis] : hi[ax.u_axis] - p[ax.u_axis];
        const double v =
            ax.v_sign > 0 ? p[ax.v_axis] - lo[ax.v_axis] : hi[ax.v_axis] - p[ax.v_axis];
        return glm::vec2(float(u * uv_per_unit), float(v * uv_per_unit));
    };

    std::vector<glm::vec2> tri_uv(tris.size() * 3);
    std::vector<uint8_t> seen_face(face_count, 0);
    size_t faces = 0; // that made triangles
    for (size_t i = 0; i < tris.size(); ++i) {
        const Triangle& t = tris[i];
        const bool from_file = face_uses_file_uv(t.face);
        if (!seen_face[t.face]) {
            seen_face[t.face] = 1;
            ++faces;
            generated_faces += from_file ? 0 : 1;
        }
        for (int k = 0; k < 3; ++k) {
            tri_uv[i * 3 + size_t(k)] = from_file
                                            ? raw.corner_uvs[t.corner[k]]
                                            : generated_uv(tri_weld(t, k), face_direction[t.face]);
        }
    }
    out.had_uvs = generated_faces == 0;
    if (generated_faces > 0 && !options.force_generated_uvs) {
        const std::string repeats = " (" + format_number(options.uv_scale) + " repeats across the largest extent)";
        if (raw.face_has_uv.empty() && !raw.file_had_uvs)
            warn(name + ": no texture coordinates; generated box-projected UVs" + repeats);
        else if (generated_faces == faces)
            // Texture coordinates that no face could use (a corner without one; said "no texture
            // coordinates" until the forty-third session: found by an exploratory session).
            warn(name +
                 (faces == 1 ? std::string(": its face has no") : ": none of the " + std::to_string(faces) + " faces has") +
                 " usable texture coordinates (one at every corner); generated box-projected UVs" + repeats);
        else
            warn(name + ": " + std::to_string(generated_faces) + " of " + std::to_string(faces) +
                 " faces have no usable texture coordinates (one at every corner); generated box-projected "
                 "UVs for them, the others keep the file's");
    }

    // Texture coordinates too large for single precision: past 2^20 a float resolves no finer
    // than an eighth of a texture repeat, and the shaders work in floats (the prism drew nothing
    // at 1e38 with a warning to check the camera, a flat dark colour at 1e20, where the reference
    // showed the object; found by an exploratory session).
    constexpr float kLargestUv = 1048576.0f;
    float largest_uv = 0.0f;
    bool largest_generated = false;
    for (size_t i = 0; i < tri_uv.size(); ++i) {
        out.largest_uv_axes = glm::max(out.largest_uv_axes, glm::abs(glm::vec2(tri_uv[i])));
        const float m = std::max(std::fabs(tri_uv[i].x), std::fabs(tri_uv[i].y));
        if (m <= largest_uv) continue;
        largest_uv = m;
        largest_generated = !face_uses_file_uv(tris[i / 3].face);
    }
    out.largest_uv = largest_uv;
    out.largest_uv_generated = largest_generated;
    if (largest_uv > kLargestUv)
        throw Error(name, std::string(largest_generated ? "generated " : "") + "texture coordinates reach " +
                              format_number(largest_uv) +
                              ", past 1048576 (2^20), where single precision resolves no finer than an eighth of "
                              "a texture repeat: " +
                              (largest_generated ? "use a smaller --uv-scale" : "scale them down in the file"));

    // ---- per-triangle metric frames ---------------------------------------------------------
    // dP/du and dP/dv of each triangle: P is linear in UV over a triangle, so
    // e1 = T du1 + B dv1 and e2 = T du2 + B dv2. The frame of a triangle that is nearly flat in
    // UV grows without bound (dividing by its UV area), so such triangles weigh less when frames
    // are averaged: `tri_quality` is the UV area over the product of the UV extents (about 0.5 to
    // 1 for well-shaped triangles).
    //
    // Triangles without UV area have no such frame. Over a triangle whose UVs are all equal, u
    // and v do not change: the height is constant there, its slope zero, and a ray does not move
    // in UV. Over one whose UVs lie on a line, only the coordinate along the line changes. Their
    // frame is the limit of dP/du and dP/dv as the UV area shrinks to nothing: infinitely long
    // along the directions in which the UV does not change. A frame many times longer than the
    // face along those directions (a `limit frame`) says that to the shaders: the height's
    // slope along it vanishes from the normal (height_normal(): dS/du = T + N depth dh/du), and the
    // view ray, expressed in the frame, does not move in UV along it (docs/mesh-input.md).
    // - UVs on a line with direction e (unit, in UV) and w = UV . e: g' = dP/dw (the gradient of w
    //   over the face over its squared length) and m, the unit vector in the face perpendicular
    //   to it; T = e.x g' + e'.x L m and B = e.y g' + e'.y L m, with e' = e turned by 90 degrees
    //   and L = kLimitStretch |g'| (right-handed, and the same for e and -e).
    // - UVs at one point: T and B perpendicular, kPointStretch times the mean frame length. The
    //   shading normal is then the direction of T x B, so across the triangle it must follow the
    //   interpolated normal: T comes from one direction in the face's plane (any, as no slope
    //   crosses to the next face) made perpendicular to each corner's normal, and each such
    //   triangle has render vertices of its own (a direction per vertex, shared by neighbours,
    //   cannot be smooth on a closed surface and left a pattern of dark lines).
    // Such triangles get render vertices of their own (averaged with a real frame, a limit frame
    // would be neither), and they take no part in their neighbours' frames.
    // A line's 1e4 keeps what the slope across it contributes under 1e-4 of what the slope along
    // it does, and the finite part of its frame (1e-4 of its length at most) well above float
    // rounding (T and B are then nearly parallel: the shaders' inverse and cross products lose
    // about 1e4 x 6e-8). A point's frame is perpendicular and can be longer: 1e5 (a slope of 10
    // per UV unit times the depth tilts the normal by 1e-4 of a radian).
    constexpr double kLimitStretch = 1e4, kPointStretch = 1e5;
    enum : uint8_t { kRealFrame, kLineFrame, kPointFrame };
    std::vector<glm::vec3> tri_t(tris.size()), tri_b(tris.size());
    std::vector<double> tri_det(tris.size());
    std::vector<float> tri_quality(tris.size(), 0.0f);
    std::vector<uint8_t> tri_kind(tris.size(), kPointFrame);
    for (size_t i = 0; i < tris.size(); ++i) {
        const Triangle& t = tris[i];
        const dvec3 &p0 = wpos[tri_weld(t, 0)], &p1 = wpos[tri_weld(t, 1)],
                    &p2 = wpos[tri_weld(t, 2)];
        const dvec2 uv0(tri_uv[i * 3]), uv1(tri_uv[i * 3 + 1]), uv2(tri_uv[i * 3 + 2]);
        const dvec2 d1 = uv1 - uv0, d2 = uv2 - uv0;
        tri_det[i] = cross2(d1, d2);
        const dvec3 e1 = p1 - p0, e2 = p2 - p0;
        if (dvec3 T, B; real_metric_frame(e1, e2, d1, d2, T, B, tri_quality[i])) {
            tri_t[i] = glm::vec3(T);
            tri_b[i] = glm::vec3(B);
            tri_kind[i] = kRealFrame;
            continue;
        }
        // A limit frame: UVs on a line (its longest UV edge gives the direction) or at a point.
        dvec2 longest = d1;
        for (const dvec2& d : {d2, d2 - d1})
            if (glm::dot(d, d) > glm::dot(longest, longest)) longest = d;
        const double ell = glm::length(longest);
        const double uv_size = std::max({1.0, std::fabs(uv0.x), std::fabs(uv0.y), std::fabs(uv1.x),
                                         std::fabs(uv1.y), std::fabs(uv2.x), std::fabs(uv2.y)});
        const dvec3 fn = glm::cross(e1, e2);
        const double fn2 = glm::dot(fn, fn);
        if (!(ell > 1e-6 * uv_size) || !(fn2 > 0.0)) continue; // a point (to float precision)
        const dvec2 e = longest / ell, e_turned(-e.y, e.x);
        const dvec3 g = (glm::dot(d1, e) * glm::cross(e2, fn) + glm::dot(d2, e) * glm::cross(fn, e1)) / fn2;
        const double g2 = glm::dot(g, g);
        if (!(g2 > 0.0) || !std::isfinite(g2)) continue;
        const dvec3 along = g / g2; // dP/dw
        const dvec3 m = glm::normalize(glm::cross(fn, g));
        const double stretch = kLimitStretch * glm::length(along);
        const dvec3 T = e.x * along + e_turned.x * stretch * m;
        const dvec3 B = e.y * along + e_turned.y * stretch * m;
        if (!std::isfinite(glm::length(T) + glm::length(B))) continue;
        tri_t[i] = glm::vec3(T);
        tri_b[i] = glm::vec3(B);
        tri_kind[i] = kLineFrame;
    }

    // ---- render vertices
    // ------------------------------------------------------------------------- One per (welded
    // position, UV), split further when the triangles sharing it have tangent frames more than ~75
    // degrees apart: a cube with 0..1 UVs on every face shares UV (1, 1) between perpendicular
    // faces at a corner, and averaging their frames would suit neither. Mirrored UVs flip T or B,
    // so mirror seams split too. Greedy, in triangle order: each corner joins the first cluster of
    // its (position, UV) whose first frame is compatible. Corners of triangles whose UVs lie on a
    // line join clusters of their own, and those of triangles whose UVs are one point take
    // vertices of their own (limit frames, above).
    struct Cluster {
        glm::vec3 t_dir{0.0f}, b_dir{0.0f};
        bool has_frame = false;
        bool limit = false;
        uint32_t next = kNone;
        uint32_t vertex = kNone;
    };
    DenseIndex<UvKey, UvKeyHash> uv_vertices(weld_count + weld_count / 4);
    std::vector<uint32_t> first_cluster;
    std::vector<Cluster> clusters;
    std::vector<UvKey> vertex_keys;
    std::vector<uint8_t> vertex_mirrored, vertex_kind; // tri_kind of the triangles it belongs to
    first_cluster.reserve(weld_count + weld_count / 4);
    out.indices.resize(tris.size() * 3);
    constexpr float kCompatible = 0.25f; // cos 75 degrees
    for (size_t i = 0; i < tris.size(); ++i) {
        const bool has = tri_kind[i] == kRealFrame;
        if (tri_kind[i] == kPointFrame) {
            for (int k = 0; k < 3; ++k) {
                const glm::vec2 uv = tri_uv[i * 3 + size_t(k)];
                out.indices[i * 3 + size_t(k)] = uint32_t(vertex_keys.size());
                vertex_keys.push_back({tri_weld(tris[i], k), float_bits(uv.x), float_bits(uv.y)});
                vertex_mirrored.push_back(0);
                vertex_kind.push_back(kPointFrame);
            }
            continue;
        }
        const glm::vec3 td = has ? glm::normalize(tri_t[i]) : glm::vec3(0.0f);
        const glm::vec3 bd = has ? glm::normalize(tri_b[i]) : glm::vec3(0.0f);
        for (int k = 0; k < 3; ++k) {
            const glm::vec2 uv = tri_uv[i * 3 + size_t(k)];
            const UvKey key{tri_weld(tris[i], k), float_bits(uv.x), float_bits(uv.y)};
            const auto [id, inserted] = uv_vertices.insert(key);
            if (inserted) first_cluster.push_back(kNone);
            uint32_t chosen = kNone, last = kNone;
            for (uint32_t c = first_cluster[id]; c != kNone; c = clusters[c].next) {
                const Cluster& cl = clusters[c];
                if (cl.limit == !has &&
                    (!has || !cl.has_frame ||
                     (glm::dot(td, cl.t_dir) > kCompatible && glm::dot(bd, cl.b_dir) > kCompatible))) {
                    chosen = c;
                    break;
                }
                last = c;
            }
            if (chosen == kNone) {
                chosen = uint32_t(clusters.size());
                Cluster c;
                c.vertex = uint32_t(vertex_keys.size());
                c.limit = !has;
                clusters.push_back(c);
                if (last == kNone)
                    first_cluster[id] = chosen;
                else
                    clusters[last].next = chosen;
                vertex_keys.push_back(key);
                vertex_mirrored.push_back(0);
                vertex_kind.push_back(tri_kind[i]);
            }
            Cluster& c = clusters[chosen];
            if (has && !c.has_frame) {
                // the first triangle with a frame defines the cluster's directions
                c.t_dir = td;
                c.b_dir = bd;
                c.has_frame = true;
                vertex_mirrored[c.vertex] = tri_det[i] < 0.0;
            }
            out.indices[i * 3 + size_t(k)] = c.vertex;
        }
    }
    const size_t vertex_count = vertex_keys.size();

    // ---- metric tangent frames ------------------------------------------------------------------
    // Triangle frames averaged over the triangles around a render vertex with corner-angle
    // weights (scaled down for triangles nearly flat in UV); lengths are kept (object units per
    // UV unit). Limit frames of lines the same way (their vertices have no others); a vertex of
    // a point's triangle gets the direction in the face that its T starts from.
    std::vector<glm::vec3> tsum(vertex_count, glm::vec3(0.0f)), bsum(vertex_count, glm::vec3(0.0f));
    std::vector<float> wsum(vertex_count, 0.0f);
    for (size_t i = 0; i < tris.size(); ++i) {
        const Triangle& t = tris[i];
        const dvec3 &p0 = wpos[tri_weld(t, 0)], &p1 = wpos[tri_weld(t, 1)],
                    &p2 = wpos[tri_weld(t, 2)];
        if (tri_kind[i] == kPointFrame) {
            const dvec3 fn = glm::cross(p1 - p0, p2 - p0);
            const double len = glm::length(fn);
            const glm::vec3 dir = len > 0.0 ? glm::vec3(any_perpendicular(fn / len)) : glm::vec3(0.0f);
            for (int k = 0; k < 3; ++k) tsum[out.indices[i * 3 + size_t(k)]] = dir;
            continue;
        }
        const double angles[3] = {corner_angle(p0, p1, p2), corner_angle(p1, p2, p0),
                                  corner_angle(p2, p0, p1)};
        const float shape = tri_kind[i] == kLineFrame ? 1.0f : frame_shape(tri_quality[i]);
        for (int k = 0; k < 3; ++k) {
            const uint32_t v = out.indices[i * 3 + size_t(k)];
            const float w = float(angles[k]) * shape;
            tsum[v] += tri_t[i] * w;
            bsum[v] += tri_b[i] * w;
            wsum[v] += w;
        }
    }

    // Length for frames that cannot be derived from UVs: the mean of the derived ones, else
    // what generated UVs would give.
    double mean_len = 0.0;
    size_t mean_n = 0;
    for (size_t v = 0; v < vertex_count; ++v) {
        if (wsum[v] <= 0.0f || vertex_kind[v] != kRealFrame) continue;
        mean_len += 0.5 * (glm::length(tsum[v]) + glm::length(bsum[v])) / wsum[v];
        ++mean_n;
    }
    double fallback_len =
        mean_n > 0 ? mean_len / double(mean_n) : (extent > 0.0 ? 1.0 / uv_per_unit : 1.0);
    if (!(fallback_len > 0.0) || !std::isfinite(fallback_len)) fallback_len = 1.0;

    out.vertices.resize(vertex_count);
    for (size_t v = 0; v < vertex_count; ++v) {
        const UvKey& key = vertex_keys[v];
        MeshVertex& mv = out.vertices[v];
        const dvec3 n = wnormal[key.weld];
        mv.position = glm::vec3(wpos[key.weld]);
        mv.normal = glm::vec3(n);
        mv.uv = glm::vec2(std::bit_cast<float>(key.u), std::bit_cast<float>(key.v));
        mv.weld_id = key.weld;

        const double sign = vertex_mirrored[v] ? -1.0 : 1.0;
        dvec3 T(0.0), B(0.0);
        if (wsum[v] > 0.0f) {
            T = dvec3(tsum[v]) / double(wsum[v]);
            B = dvec3(bsum[v]) / double(wsum[v]);
            T -= n * glm::dot(n, T);
            B -= n * glm::dot(n, B);
        }
        const double lt = glm::length(T), lb = glm::length(B);
        if (vertex_kind[v] != kRealFrame) {
            // A line's limit frame if its average still is one (right-handed, not flat), else a
            // point's: perpendicular, both kPointStretch times the mean frame length, T from the
            // face's direction.
            const bool line = vertex_kind[v] == kLineFrame && std::isfinite(lt) && std::isfinite(lb) &&
                              lt > 0.0 && lb > 0.0 && glm::dot(glm::cross(T, B), n) > 0.1 / kLimitStretch * lt * lb;
            if (!line) {
                dvec3 t_dir = dvec3(tsum[v]) - n * glm::dot(n, dvec3(tsum[v]));
                const double l = glm::length(t_dir);
                t_dir = vertex_kind[v] == kPointFrame && l > 0.1 ? t_dir / l : any_perpendicular(n);
                T = kPointStretch * fallback_len * t_dir;
                B = kPointStretch * fallback_len * glm::cross(n, t_dir);
            }
        } else {
            const double eps = 1e-6 * fallback_len;
            const bool t_ok = lt > eps && std::isfinite(lt), b_ok = lb > eps && std::isfinite(lb);
            if (t_ok && b_ok && glm::length(glm::cross(T / lt, B / lb)) > 1e-3) {
                // a usable frame
            } else if (t_ok) {
                B = sign * (b_ok ? lb : lt) * glm::cross(n, T / lt);
            } else if (b_ok) {
                T = sign * lb * glm::cross(B / lb, n);
            } else {
                T = fallback_len * any_perpendicular(n);
                B = sign * fallback_len * glm::cross(n, T / fallback_len);
            }
        }
        const double handed = glm::dot(glm::cross(n, T), B) < 0.0 ? -1.0 : 1.0;
        mv.tangent = glm::vec4(glm::vec3(T), float(handed));
        mv.bitangent = glm::vec3(B);
    }
    return out;
}

void place_mesh_frames(PreparedMesh& mesh, const glm::dmat3& linear)
{
    const glm::dmat3 gram = glm::transpose(linear) * linear;
    const double scale = (gram[0][0] + gram[1][1] + gram[2][2]) / 3.0;
    double off = 0.0;
    for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) off = std::max(off, std::abs(gram[c][r] - (c == r ? scale : 0.0)));
    if (!(off > 1e-9 * scale)) return; // a similarity carries angles, normals and frames as they are
    std::vector<MeshVertex>& vertices = mesh.vertices;
    const uint32_t welds = welded_position_count(vertices);
    std::vector<dvec3> nsum(welds, dvec3(0.0)), tsum(vertices.size(), dvec3(0.0)), bsum(vertices.size(), dvec3(0.0));
    std::vector<double> nweight(welds, 0.0), fweight(vertices.size(), 0.0);
    std::vector<uint8_t> keep_frame(vertices.size(), 0);
    for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
        const uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
        const dvec3 a = linear * dvec3(vertices[i[0]].position), b = linear * dvec3(vertices[i[1]].position),
                    c = linear * dvec3(vertices[i[2]].position);
        const dvec3 cr = glm::cross(b - a, c - a);
        const double len = glm::length(cr);
        const double angles[3] = {corner_angle(a, b, c), corner_angle(b, c, a), corner_angle(c, a, b)};
        if (normal_is_sound(a, b, c, len))
            for (int k = 0; k < 3; ++k) {
                nsum[vertices[i[k]].weld_id] += angles[k] * (cr / len);
                nweight[vertices[i[k]].weld_id] += angles[k];
            }
        dvec3 T, B;
        float quality = 0.0f;
        if (!real_metric_frame(b - a, c - a, dvec2(vertices[i[1]].uv - vertices[i[0]].uv),
                               dvec2(vertices[i[2]].uv - vertices[i[0]].uv), T, B, quality)) {
            for (const uint32_t v : i) keep_frame[v] = 1;
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            const double w = angles[k] * frame_shape(quality);
            tsum[i[k]] += w * T;
            bsum[i[k]] += w * B;
            fweight[i[k]] += w;
        }
    }
    const glm::dmat3 to_object_normal = glm::transpose(linear); // normal_matrix() of it gives the world's back
    const glm::dmat3 to_object = glm::inverse(linear);
    const glm::dmat3 to_world_normal = glm::transpose(to_object);
    for (size_t k = 0; k < vertices.size(); ++k) {
        MeshVertex& v = vertices[k];
        const dvec3 sum = nsum[v.weld_id];
        const double l = glm::length(sum);
        // Of unit length in world space, not in the object's: interpolated in object space (the
        // reference's tessellation), they then interpolate as the world's unit normals do.
        const dvec3 world = to_world_normal * dvec3(v.normal);
        const dvec3 n = l > 1e-6 * nweight[v.weld_id] ? sum / l : world / glm::length(world);
        v.normal = glm::vec3(to_object_normal * n);
        if (keep_frame[k] || !(fweight[k] > 0.0)) continue;
        dvec3 T = tsum[k] / fweight[k], B = bsum[k] / fweight[k];
        T -= n * glm::dot(n, T);
        B -= n * glm::dot(n, B);
        const double lt = glm::length(T), lb = glm::length(B);
        if (!(lt > 0.0 && lb > 0.0 && std::isfinite(lt + lb) && glm::length(glm::cross(T / lt, B / lb)) > 1e-3)) continue;
        v.tangent = glm::vec4(glm::vec3(to_object * T), v.tangent.w);
        v.bitangent = glm::vec3(to_object * B);
    }
}

} // namespace pr
