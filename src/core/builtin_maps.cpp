// Built-in procedural height and colour maps. Each is a function of (u, v) in [0,1)² built from
// an integer number of cells or noise periods per UV unit and evaluated at texel centres
// ((i+0.5)/w, (j+0.5)/h), so every map tiles seamlessly at any size. Randomness comes from a
// fixed integer hash, so the maps are the same on every run.
#include "core/builtin_maps.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <system_error>
#include <thread>
#include <vector>

#include <fmt/format.h>

namespace pr {
namespace builtin {
namespace {

// ---- deterministic randomness ----

std::uint32_t hash(std::uint32_t x)
{
    // "lowbias32" (Chris Wellons): a cheap integer hash with good avalanche.
    x ^= x >> 16;
    x *= 0x7feb352dU;
    x ^= x >> 15;
    x *= 0x846ca68bU;
    x ^= x >> 16;
    return x;
}

// Uniform in [0,1) for a cell (i, j) of one pattern; `salt` separates patterns and uses.
double rand01(int i, int j, std::uint32_t salt)
{
    const std::uint32_t h = hash(hash(hash(salt) ^ std::uint32_t(i)) ^ std::uint32_t(j));
    return double(h >> 8) / double(1U << 24);
}

int mod(int i, int n) { return ((i % n) + n) % n; }

// Periodic 2D gradient (Perlin) noise with `period` lattice cells per UV unit; about [-0.7,0.7].
double perlin(double u, double v, int period, std::uint32_t salt)
{
    const double x = u * period, y = v * period;
    const double fx = std::floor(x), fy = std::floor(y);
    const int ix = int(fx), iy = int(fy);
    const double tx = x - fx, ty = y - fy;
    const auto grad = [&](int ci, int cj, double dx, double dy) {
        // Gradients hashed on the wrapped lattice index: that is what makes the noise periodic.
        const double turn = rand01(mod(ci, period), mod(cj, period), salt);
        const double angle = 2.0 * std::numbers::pi * turn;
        return std::cos(angle) * dx + std::sin(angle) * dy;
    };
    const auto fade = [](double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); };
    const double n00 = grad(ix, iy, tx, ty), n10 = grad(ix + 1, iy, tx - 1, ty);
    const double n01 = grad(ix, iy + 1, tx, ty - 1), n11 = grad(ix + 1, iy + 1, tx - 1, ty - 1);
    const double a = fade(tx), b = fade(ty);
    return (1 - b) * ((1 - a) * n00 + a * n10) + b * ((1 - a) * n01 + a * n11);
}

// Sum of octaves, periods base, 2·base, ...; amplitudes halve.
double fbm(double u, double v, int base_period, int octaves, std::uint32_t salt)
{
    double sum = 0.0, amplitude = 1.0;
    for (int o = 0; o < octaves; ++o) {
        sum += amplitude * perlin(u, v, base_period << o, salt + std::uint32_t(o));
        amplitude *= 0.5;
    }
    return sum;
}

// ---- patterns, as functions of (u, v) ----

constexpr std::uint32_t kSaltBoxes = 0xB0C5E5, kSaltBricks = 0xB41C45, kSaltNoise = 0x4015E;

// A cell grid: index and position inside the cell, centred ([-0.5, 0.5)).
struct Cell {
    int i, j;
    double x, y;
};

Cell cell(double u, double v, int n)
{
    const double x = u * n, y = v * n;
    const double fx = std::floor(x), fy = std::floor(y);
    return {mod(int(fx), n), mod(int(fy), n), x - fx - 0.5, y - fy - 0.5};
}

// The patterns below laid out on a grid of cells take the number of cells per UV unit as `cells`:
// kCells, or fewer on maps too small to show them with kCells (height_values).
constexpr int kCells = 8;

// 8×8 round bumps: a raised-cosine dome of radius 0.42 cells on flat ground (smooth, C¹).
double bumps(double u, double v, int cells)
{
    const Cell c = cell(u, v, cells);
    const double r = std::hypot(c.x, c.y) / 0.42;
    return r < 1.0 ? 0.5 * (1.0 + std::cos(std::numbers::pi * r)) : 0.0;
}

// 8×8 square pyramids, apex 1 at the cell centre, 0 along the cell borders.
double pyramids(double u, double v, int cells)
{
    const Cell c = cell(u, v, cells);
    return 1.0 - 2.0 * std::max(std::abs(c.x), std::abs(c.y));
}

// 8×8 cells, each with a flat-topped box of its own size, place and height on ground 0, some
// with a taller box stacked on top: hard vertical steps, as in cone-map test images. Boxes stay
// inside their cell, so the borders (and the map's edges) are ground.
double boxes(double u, double v, int cells)
{
    const Cell c = cell(u, v, cells);
    const auto r = [&](std::uint32_t k) { return rand01(c.i, c.j, kSaltBoxes + k); };
    if (r(0) < 0.1) return 0.0; // an empty cell now and then
    const double hx = 0.18 + 0.24 * r(1), hy = 0.18 + 0.24 * r(2); // half sizes, ≤ 0.42
    const double cx = (0.46 - hx) * (2.0 * r(3) - 1.0), cy = (0.46 - hy) * (2.0 * r(4) - 1.0);
    const double dx = std::abs(c.x - cx), dy = std::abs(c.y - cy);
    if (dx > hx || dy > hy) return 0.0;
    const double height = 0.2 + 0.05 * std::floor(r(5) * 13.0); // 0.2 … 0.8 in steps of 0.05
    if (r(6) < 0.35 && dx < 0.45 * hx && dy < 0.45 * hy)
        return std::min(1.0, height + 0.2 + 0.2 * r(7));
    return height;
}

double noise(double u, double v, int /*cells: none*/) { return fbm(u, v, 4, 5, kSaltNoise); }

// Running-bond bricks: 8 courses per UV unit, 4 bricks per course (2:1 on a square map), every
// other course shifted by half a brick. Shared by the height and colour maps so they line up.
struct BrickSample {
    int id;       // brick number, the same for every texel of one (wrapped) brick
    double edge;  // distance to the brick's outline, in course heights (0 at the outline)
};
constexpr int kCourses = 8, kBricksPerCourse = 4;
constexpr double kMortar = 0.07; // half the mortar joint, in course heights
constexpr double kBevel = 0.14;  // width of the bevel, in course heights

BrickSample brick(double u, double v)
{
    const double y = v * kCourses;
    const int course = mod(int(std::floor(y)), kCourses);
    const double fy = y - std::floor(y);
    const double x = u * kBricksPerCourse + (course % 2 ? 0.5 : 0.0);
    const int column = mod(int(std::floor(x)), kBricksPerCourse);
    const double fx = x - std::floor(x);
    const double aspect = double(kCourses) / kBricksPerCourse; // brick length / course height
    const double edge = std::min(std::min(fx, 1.0 - fx) * aspect, std::min(fy, 1.0 - fy));
    return {course * kBricksPerCourse + column, edge};
}

constexpr double kMortarHeight = 0.08;

bool in_mortar(const BrickSample& b) { return b.edge < kMortar; }

double bricks(double u, double v, int /*cells: courses and bricks of their own*/)
{
    const BrickSample b = brick(u, v);
    if (in_mortar(b)) return kMortarHeight + 0.03 * fbm(u, v, 64, 2, kSaltBricks + 1);
    // Each brick sits a little proud or sunk; the bevel eases from the joint up to the face.
    const double top =
        0.86 + 0.1 * rand01(b.id, 0, kSaltBricks) + 0.03 * fbm(u, v, 32, 2, kSaltBricks + 2);
    const double t = std::min(1.0, (b.edge - kMortar) / kBevel);
    return kMortarHeight + (top - kMortarHeight) * t * (2.0 - t);
}

// ---- colours ----

struct Rgb {
    double r, g, b;
};

Rgb lerp(const Rgb& a, const Rgb& b, double t)
{
    return {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
}

Rgb checker_color(double u, double v)
{
    const Cell c = cell(u, v, 8);
    return (c.i + c.j) % 2 ? Rgb{226, 222, 210} : Rgb{62, 74, 92};
}

Rgb uv_color(double u, double v) { return {255.0 * u, 255.0 * v, 0.0}; }

Rgb bricks_color(double u, double v)
{
    const BrickSample b = brick(u, v);
    const double grain = fbm(u, v, 64, 2, kSaltBricks + 3);
    if (in_mortar(b)) {
        const double g = 168.0 + 40.0 * grain;
        return {g, g - 2.0, g - 8.0};
    }
    // Reddish, varying per brick in hue and brightness, with a little grain inside each.
    const double hue = rand01(b.id, 1, kSaltBricks), value = rand01(b.id, 2, kSaltBricks);
    const Rgb base = lerp(Rgb{150, 58, 40}, Rgb{172, 92, 58}, hue);
    const double k = (0.78 + 0.3 * value) * (1.0 + 0.25 * grain);
    return {base.r * k, base.g * k, base.b * k};
}

// A height shown as colour: dark umber at 0, sand at 0.5, near-white at 1.
Rgb tint(double h)
{
    const Rgb low{74, 56, 44}, mid{198, 168, 122}, high{250, 247, 238};
    return h < 0.5 ? lerp(low, mid, h * 2.0) : lerp(mid, high, h * 2.0 - 1.0);
}

// ---- the catalogue ----

using HeightFn = double (*)(double u, double v, int cells);
struct HeightEntry {
    const char* name;
    HeightFn fn;
    bool normalize; // rescale the sampled map to exactly [0,1] (noise has no fixed range)
    bool cells;     // laid out on a grid of kCells cells per UV unit, or fewer (height_values)
};
constexpr HeightEntry kHeights[] = {
    {"bumps", bumps, false, true},       {"bricks", bricks, false, false}, {"noise", noise, true, false},
    {"pyramids", pyramids, false, true}, {"boxes", boxes, false, true},
};
constexpr const char* kConstName = "const:V";

using ColorFn = Rgb (*)(double, double);
struct ColorEntry {
    const char* name;
    ColorFn fn;
};
constexpr ColorEntry kColors[] = {
    {"checker", checker_color}, {"bricks", bricks_color}, {"uv", uv_color}};

std::string join(const std::vector<std::string>& names)
{
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + n;
    return s;
}

// "NAME[@N|@WxH]" after the prefix.
struct Parsed {
    std::string name;
    int width = kDefaultSize, height = kDefaultSize;
};

std::optional<int> parse_int(std::string_view s)
{
    int value = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (ec != std::errc() || end != s.data() + s.size() || s.empty()) return std::nullopt;
    return value;
}

Parsed parse(const std::string& spec, const ImageLimits& limits)
{
    const std::string body = spec.substr(kPrefix.size());
    Parsed p;
    const auto at = body.rfind('@');
    p.name = body.substr(0, at);
    // Without '@' the default size, which obeys the limits (--max-image-size) as an @N does.
    const std::string_view size =
        at == std::string::npos ? std::string_view() : std::string_view(body).substr(at + 1);
    const auto x = size.find('x');
    const auto w = at == std::string::npos ? std::optional<int>(kDefaultSize) : parse_int(size.substr(0, x));
    const auto h = x == std::string_view::npos ? w : parse_int(size.substr(x + 1));
    const int max = limits.max_dimension;
    if (at == std::string::npos && kDefaultSize > max) {
        // (A pattern shows in no fewer than 3 texels a side: below that an @N would be refused
        // too, and the suggestion of one was.)
        const bool pattern_too_small = max < 3 && !p.name.starts_with("const:");
        throw Error(spec, fmt::format("its default size, {0}x{0}, is over the limit of {1} per side "
                                      "(--max-image-size){2}",
                                      kDefaultSize, max,
                                      pattern_too_small ? ", and its pattern needs at least 3 texels per side: raise the limit"
                                                        : fmt::format(": give a size, e.g. {}@{}", spec, max)));
    }
    if (!w || !h || *w < 1 || *h < 1 || *w > max || *h > max)
        throw Error(spec, fmt::format("size after '@' must be N or WxH with each side between 1 "
                                      "and {}, got '{}'",
                                      max, size));
    if (std::int64_t(*w) * *h > limits.max_pixels)
        throw Error(spec, fmt::format("{}x{} is more than the limit of {} pixels", *w, *h,
                                      limits.max_pixels));
    p.width = *w;
    p.height = *h;
    return p;
}

// "const:V" → V, or nullopt when the name is not a const map at all.
std::optional<double> parse_const(const std::string& spec, const std::string& name)
{
    constexpr std::string_view prefix = "const:";
    if (name.rfind(prefix, 0) != 0) return std::nullopt;
    const std::string text = name.substr(prefix.size());
    double value = 0.0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size() ||
        !(value >= 0.0 && value <= 1.0))
        throw Error(spec, "const:V needs a number V in [0,1], got '" + text + "'");
    return value;
}

[[noreturn]] void unknown(const std::string& spec, const std::string& name,
                          const std::vector<std::string>& known)
{
    throw Error(spec, "unknown built-in map '" + name + "'; known: " + join(known));
}

float quantize16(double x)
{
    return float(std::round(std::clamp(x, 0.0, 1.0) * 65535.0) / 65535.0);
}
std::uint8_t to_byte(double x) { return std::uint8_t(std::lround(std::clamp(x, 0.0, 255.0))); }

// Samples f at texel centres, bottom row first; doubles so normalization sees full precision.
// Rows are handed out to the cores (the patterns are pure functions: the same values whatever
// the order): builtin:noise@8192, five octaves of gradient noise, took 27 s on one thread
// without a word (found by an exploratory session, thirty-eighth).
std::vector<double> sample_grid(int w, int h, const std::function<double(double, double)>& f)
{
    std::vector<double> out(std::size_t(w) * h);
    std::atomic<int> next_row{0};
    const auto work = [&] {
        for (int j = next_row++; j < h; j = next_row++)
            for (int i = 0; i < w; ++i) out[std::size_t(j) * w + i] = f((i + 0.5) / w, (j + 0.5) / h);
    };
    const std::size_t texels = std::size_t(w) * std::size_t(h);
    const unsigned cores = std::max(1u, std::min(std::thread::hardware_concurrency(), 16u));
    const unsigned helpers = texels < (std::size_t(1) << 16) ? 0u : std::min<unsigned>(cores - 1, unsigned(h) - 1);
    std::vector<std::thread> threads;
    threads.reserve(helpers);
    try {
        for (unsigned t = 0; t < helpers; ++t) threads.emplace_back(work);
    } catch (const std::system_error&) {
        // (No thread to be had: the ones started and this one do the rows.)
    }
    work();
    for (std::thread& t : threads) t.join();
    return out;
}

// The height map `name` as doubles in [0,1], or nullopt when there is no such height map.
std::optional<std::vector<double>> height_values(const std::string& spec, const Parsed& p)
{
    if (const auto c = parse_const(spec, p.name))
        return std::vector<double>(std::size_t(p.width) * p.height, *c);
    for (const HeightEntry& e : kHeights) {
        if (p.name != e.name) continue;
        int cells = kCells;
        const auto sample = [&] {
            return sample_grid(p.width, p.height, [&](double u, double v) { return e.fn(u, v, cells); });
        };
        const auto flat = [](const std::vector<double>& v) {
            return std::all_of(v.begin(), v.end(), [&](double x) { return x == v[0]; });
        };
        std::vector<double> v = sample();
        if (e.cells) {
            // Where every texel centre sits at the same place in its cell (one or two texels per
            // cell: bumps@8, bumps@16), a cell pattern comes out flat. Such maps take fewer, larger
            // cells, halving until the pattern shows; every map that shows it with kCells keeps
            // that layout, bit for bit. With one cell a side of 3 texels shows any of them. Also
            // until a cell has 3 texels along the map's longer side: boxes give each cell its own
            // height, so one texel a cell was never flat and boxes@8 came out as 64 random heights,
            // no box (found by a review, thirty-third). Maps of 24 texels and more keep kCells.
            while ((flat(v) || std::max(p.width, p.height) < 3 * cells) && cells > 1) {
                cells /= 2;
                v = sample();
            }
        }
        // Bricks and noise have no cells to enlarge: at 2 texels a side every texel centre of
        // bricks lies in the mortar, and noise normalizes to a constant (they were accepted as
        // constant maps before the sixteenth session). A cell pattern under 3 texels both ways
        // has a texel a cell at most: boxes@2 came out as four random heights, no box (found by
        // an exploratory session, thirty-third); long thin maps (@64x1) sample it and are kept.
        if (flat(v) || (e.cells && std::max(p.width, p.height) < 3))
            throw Error(spec, e.cells ? "too small for its pattern; at least 3 texels along its longer side"
                                      : "too small for its pattern: every texel centre takes the same height");
        if (e.normalize) {
            const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
            const double a = *lo, range = *hi - *lo;
            for (double& x : v) x = range > 0.0 ? (x - a) / range : 0.5;
        }
        return v;
    }
    return std::nullopt;
}

} // namespace

HeightField make_height(const std::string& spec, const ImageLimits& limits)
{
    const Parsed p = parse(spec, limits);
    const auto values = height_values(spec, p);
    if (!values) unknown(spec, p.name, builtin_height_names());
    HeightField hf;
    hf.width = p.width;
    hf.height = p.height;
    hf.bits = 16;
    hf.name = spec;
    hf.texels.resize(values->size());
    std::transform(values->begin(), values->end(), hf.texels.begin(), quantize16);
    return hf;
}

RgbaImage make_color(const std::string& spec, const ImageLimits& limits)
{
    const Parsed p = parse(spec, limits);
    RgbaImage img;
    img.width = p.width;
    img.height = p.height;
    img.pixels.resize(std::size_t(p.width) * p.height * 4);
    const auto put = [&](std::size_t k, const Rgb& c) {
        img.pixels[4 * k + 0] = to_byte(c.r);
        img.pixels[4 * k + 1] = to_byte(c.g);
        img.pixels[4 * k + 2] = to_byte(c.b);
        img.pixels[4 * k + 3] = 255;
    };
    for (const ColorEntry& e : kColors) {
        if (p.name != e.name) continue;
        for (int j = 0; j < p.height; ++j)
            for (int i = 0; i < p.width; ++i)
                put(std::size_t(j) * p.width + i,
                    e.fn((i + 0.5) / p.width, (j + 0.5) / p.height));
        // As a height map's (height_values): checker@4 and bricks@4 came out one colour, the
        // checker's one square and the mortar, without a word (found by an exploratory session,
        // fifty-third).
        bool one_colour = true;
        for (std::size_t k = 4; k < img.pixels.size() && one_colour; ++k) one_colour = img.pixels[k] == img.pixels[k % 4];
        if (one_colour) throw Error(spec, "too small for its pattern: every texel centre takes the same colour");
        return img;
    }
    // Any height map without a colour of its own: its height, tinted.
    const auto values = height_values(spec, p);
    if (!values) unknown(spec, p.name, builtin_color_names());
    for (std::size_t k = 0; k < values->size(); ++k) put(k, tint((*values)[k]));
    return img;
}

} // namespace builtin

void check_builtin_name(const std::string& spec, bool color, const ImageLimits& limits)
{
    if (!builtin::is_builtin(spec)) return;
    const builtin::Parsed p = builtin::parse(spec, limits);
    if (builtin::parse_const(spec, p.name)) return;
    const auto named = [&](const auto& entries) {
        return std::any_of(std::begin(entries), std::end(entries), [&](const auto& e) { return p.name == e.name; });
    };
    if (named(builtin::kHeights) || (color && named(builtin::kColors))) return;
    builtin::unknown(spec, p.name, color ? builtin_color_names() : builtin_height_names());
}

std::vector<std::string> builtin_height_names()
{
    std::vector<std::string> names;
    for (const auto& e : builtin::kHeights) names.emplace_back(e.name);
    names.emplace_back(builtin::kConstName);
    return names;
}

std::vector<std::string> builtin_color_names()
{
    std::vector<std::string> names;
    for (const auto& e : builtin::kColors) names.emplace_back(e.name);
    for (const std::string& h : builtin_height_names())
        if (std::find(names.begin(), names.end(), h) == names.end()) names.push_back(h);
    return names;
}

} // namespace pr
