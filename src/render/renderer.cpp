#include "render/renderer.hpp"

#include "core/error.hpp"
#include "core/fnv.hpp"
#include "core/memory.hpp"
#include "core/transform.hpp"
#include "maps/conemap.hpp"
#include "mesh/adjacency.hpp"
#include "mesh/flat_merge.hpp"
#include "render/conemap_gpu.hpp"
#include "render/reference_geometry.hpp"
#include "render/shell_bounds.hpp"
#include "render/shader_program.hpp"

#include "common/shared.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <utility>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

namespace pr {

namespace {

// GL_OUT_OF_MEMORY while uploading (make_vertex_array): a caller that knows what set the size
// names it (prepare_reference).
struct GpuOutOfMemory : Error {
    using Error::Error;
};

// Bins of the histogram of height samples per fragment (bench's p95): sample_bin() in
// shaders/common/counters.glsl, sample_bin_low() here. (256 before the thirteenth session: every
// p95 above 255 read 255; 8192 before the thirty-fifth, the last "that many or more".)
constexpr int kHistogramBins = kExactSampleBins + (31 - PR_EXACT_SAMPLE_BITS) * kSampleBinsPerOctave; // up to 2^31
constexpr int kCounterWords = 7; // before the histogram, two words a bin (shaders/common/counters.glsl)
// The largest shell (radius of the sphere around it) the prism draws: its exit tests multiply three
// world lengths in floats, which overflow (3.4e38): the torus drew right at a radius of 2.2e13, nothing at 6.5e13.
constexpr float kPrismMaxShellRadius = 1e13f;
// And the smallest: the same products underflow (the torus drew right at a radius of 1.4e-9, lost
// part of its outline at 4e-10 and nothing at 1.4e-10).
constexpr float kPrismMinShellRadius = 1e-9f;

int mip_levels(int w, int h)
{
    int levels = 1;
    while ((w | h) >> levels) ++levels;
    return levels;
}

// A mip-mapped texture with repeat wrap: bilinear within a level, trilinear between levels.
gl::Texture make_texture(GLenum internal_format, int w, int h, GLenum format, GLenum type, const void* data)
{
    gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), mip_levels(w, h), internal_format, w, h);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.id(), 0, 0, 0, w, h, format, type, data);
    glGenerateTextureMipmap(t.id());
    gl::sample_repeating(t, GL_LINEAR_MIPMAP_LINEAR, GL_LINEAR);
    return t;
}

gl::Texture make_height_texture(const HeightField& hf)
{
    // Full precision on the GPU (contract): R16 for 16-bit input, R8 otherwise.
    return make_texture(hf.bits > 8 ? GL_R16 : GL_R8, hf.width, hf.height, GL_RED, GL_FLOAT, hf.texels.data());
}

gl::Texture make_color_texture(const RgbaImage& img)
{
    return make_texture(GL_RGBA8, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, img.pixels.data());
}

// A cone map's texels: R = height, G = sqrt(cone ratio), the ratios narrowed for bilinear
// filtering (ratios_for_bilinear: each the smallest of its 3x3 neighbourhood).
std::vector<float> cone_texels(const ConeMap& map)
{
    const std::size_t n = map.heights.size();
    const std::vector<float> ratios = ratios_for_bilinear(map.ratios, map.width, map.height);
    std::vector<float> texels(n * 2);
    for (std::size_t i = 0; i < n; ++i) {
        texels[2 * i] = map.heights[i];
        texels[2 * i + 1] = ratios[i];
    }
    return texels;
}

// Cone map: cone_texels, level 0 only (cone ratios of a coarser level would mean nothing),
// bilinear, repeat. RG16 keeps the 16-bit heights and the rounded-down ratios exact.
gl::Texture make_cone_texture(const ConeMap& map)
{
    return gl::map_texture(GL_RG16, map.width, map.height, GL_RG, cone_texels(map).data(), GL_LINEAR);
}

// A relaxed map's texture: the relaxed map (layer 0) and the cone map (layer 1), for rising rays
// (shaders/march/cone.glsl, cone_at), as the layers of one RG16 array, so that the ray's direction
// picks the layer, a texture coordinate, in one fetch, and the heights and slopes read from the
// texture the march reads. (The conservative ratios as a third channel (RGB16) made every fetch
// dearer on llvmpipe; the cone map as a texture of its own, fetched in a branch, cost the prism's
// relaxed march on the blob 7 % of its frame; docs/benchmarks.md, forty-second session.)
gl::Texture make_cone_pair_texture(const ConeMap& relaxed, const ConeMap& cone)
{
    if (relaxed.width != cone.width || relaxed.height != cone.height)
        throw Error("cone map", "a relaxed map and its cone map differ in size");
    gl::Texture t = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
    glTextureStorage3D(t.id(), 1, GL_RG16, relaxed.width, relaxed.height, 2);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage3D(t.id(), 0, 0, 0, 0, relaxed.width, relaxed.height, 1, GL_RG, GL_FLOAT, cone_texels(relaxed).data());
    glTextureSubImage3D(t.id(), 0, 0, 0, 1, cone.width, cone.height, 1, GL_RG, GL_FLOAT, cone_texels(cone).data());
    gl::sample_repeating(t, GL_LINEAR, GL_LINEAR);
    return t;
}

// The base-surface cone marchers' heights and ratios in one R32F texel each, read four at a time
// with textureGather (shaders/march/cone.glsl, patch_at): the four corners of a bilinear patch,
// its heights and its ratio (the narrowest of the four) in one fetch. Each texel is an integer
// below 2^24 over 2^24, exact in a float: its top 16 bits the height (an 8-bit map's exactly, as
// k * 257), its low 8 bits the map's sqrt(c) rounded down to 8 bits. (Four heights and 16-bit
// ratios in an RGBA32F texel per patch, read with texelFetch, one fetch as well: the torus's
// frame 25.8 ms on llvmpipe against 21.4 with this texture.)
gl::Texture make_patch_texture(const ConeMap& map)
{
    std::vector<float> texels(map.heights.size());
    for (std::size_t i = 0; i < texels.size(); ++i) {
        const auto height = std::uint32_t(std::lround(double(std::clamp(map.heights[i], 0.0f, 1.0f)) * 65535.0));
        const auto ratio = std::uint32_t(std::clamp(std::floor(double(map.ratios[i]) * 255.0 + 1e-6), 0.0, 255.0));
        texels[i] = float(height << 8 | ratio) / 16777216.0f;
    }
    return gl::map_texture(GL_R32F, map.width, map.height, GL_RED, texels.data(), GL_NEAREST);
}

// Max pyramid for the max-mip marcher (R32F, texelFetch only). Level 0 cell (i, j) is the
// bilinear patch between texel centres (i, j) and (i + 1, j + 1), wrapping, and holds the max of
// its 4 corner texels, which bounds the patch. Level k has GL's floor(size / 2^k) cells per side;
// cell c covers level-0 cells [c 2^k, (c + 1) 2^k), the last one also the remainder up to the
// size (shaders/march/maxmip.glsl computes the same spans).
gl::Texture make_max_pyramid_texture(const HeightField& hf)
{
    const int w = hf.width, h = hf.height, levels = mip_levels(w, h);
    std::vector<float> prev(std::size_t(w) * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            prev[std::size_t(y) * w + x] = std::max(std::max(hf.at(x, y), hf.at(x + 1, y)),
                                                    std::max(hf.at(x, y + 1), hf.at(x + 1, y + 1)));
    gl::Texture t = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), levels, GL_R32F, w, h);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.id(), 0, 0, 0, w, h, GL_RED, GL_FLOAT, prev.data());
    int pw = w, ph = h;
    for (int level = 1; level < levels; ++level) {
        const int lw = std::max(1, w >> level), lh = std::max(1, h >> level);
        std::vector<float> cur(std::size_t(lw) * lh, 0.0f);
        // Each cell of the previous level goes to its parent; the last parent takes the rest.
        for (int y = 0; y < ph; ++y)
            for (int x = 0; x < pw; ++x) {
                float& m = cur[std::size_t(std::min(y / 2, lh - 1)) * lw + std::min(x / 2, lw - 1)];
                m = std::max(m, prev[std::size_t(y) * pw + x]);
            }
        glTextureSubImage2D(t.id(), level, 0, 0, lw, lh, GL_RED, GL_FLOAT, cur.data());
        prev = std::move(cur);
        pw = lw;
        ph = lh;
    }
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    return t;
}

// The prism walk's shell (PR_TEX_CORNERS), per render vertex, world space, the formula of
// shaders/prism/shell.glsl: vec4(bottom corner, u), vec4(unit normal N, v), vec4(tight top
// height, welded id as float bits, 0, 0). The corner at height h is bottom + h * (depth * N); the
// walk reads three vec4 per corner instead of a vertex and two matrix products.
std::vector<glm::vec4> make_shell_corners(const std::vector<MeshVertex>& vertices,
                                          const std::vector<std::uint32_t>& indices, const HeightField& height,
                                          float height_max, const glm::mat4& transform, float depth, float midlevel)
{
    const glm::mat3 normals = normal_matrix(transform);
    const std::vector<float> top = shell_top_heights(vertices, indices, height, height_max, TopSlope{transform, depth});
    std::vector<glm::vec4> corners;
    corners.reserve(vertices.size() * 3);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        const MeshVertex& v = vertices[i];
        const glm::vec3 world = glm::vec3(transform * glm::vec4(v.position, 1.0f));
        const glm::vec3 n = glm::normalize(normals * v.normal);
        const glm::vec3 dn = depth * n;
        corners.emplace_back(world - midlevel * dn, v.uv.x);
        corners.emplace_back(n, v.uv.y);
        corners.emplace_back(top[i], std::bit_cast<float>(v.weld_id), 0.0f, 0.0f);
    }
    return corners;
}

// The most prisms one walk may cross (ObjectBlock::u_walk): 256, and twice the most triangles
// around one welded position (a fan of slivers around a point), and twice the prisms a straight
// path through the shell can cross across its narrow triangles: the object's bounding diameter
// (a grazing ray runs inside the shell along a surface as flat as the object allows) over the
// triangles' 5th-percentile altitude (an open cylinder of 2000 sides in one row of slivers 1.5
// long and 0.0016 wide: rays near its outline cross about 300 prisms, and past 256 they were
// dropped, IoU 0.964; found by an exploratory session; a chord of a shell curved as the
// bounding sphere, as first taken, is the shortest such path, not the longest: a gently curved
// sheet of 2000 strips seen 3 degrees up kept holes, found by a review). At most 256 + 8192: a
// vertex of a million triangles, or slivers of no width, must not let every ray that misses walk
// a million prisms.
// Also what bounded it, for the warnings where it is cut short (ensure_walk_data).
struct WalkLimit {
    int prisms = 256;
    std::uint32_t most_around = 0; // triangles around one welded position, at most
    double crossed = 0.0;          // prisms a straight path through the shell may cross (no more than its piece has)
};
constexpr std::uint32_t kWalkMostAround = 4096;
constexpr double kWalkCap = 256.0 + 8192.0;

WalkLimit walk_prism_limit(const std::vector<MeshVertex>& vertices, const std::vector<std::uint32_t>& indices,
                           const glm::mat4& transform, float depth)
{
    WalkLimit w;
    std::vector<std::uint32_t> around(welded_position_count(vertices), 0);
    for (const std::uint32_t i : indices) ++around[vertices[i].weld_id];
    const std::uint32_t most = around.empty() ? 0 : *std::max_element(around.begin(), around.end());
    w.most_around = most;
    double limit = 256.0 + 2.0 * double(std::min<std::uint32_t>(most, kWalkMostAround));
    // A walk goes from prism to neighbouring prism, so it stays within one piece of the mesh (its
    // triangles joined by shared positions): its path is bounded by the largest piece's size, not
    // the whole mesh's (two cubes 2 units wide, 2e5 apart in one file, read "may cross up to about
    // 141423 prisms"; found by an exploratory session, forty-seventh).
    std::vector<std::uint32_t> piece(around.size());
    std::iota(piece.begin(), piece.end(), 0u);
    const auto root = [&](std::uint32_t a) {
        while (piece[a] != a) a = piece[a] = piece[piece[a]];
        return a;
    };
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
        for (int k = 1; k < 3; ++k) {
            const std::uint32_t a = root(vertices[indices[t]].weld_id), b = root(vertices[indices[t + std::size_t(k)]].weld_id);
            if (a != b) piece[std::max(a, b)] = std::min(a, b);
        }
    std::vector<glm::dvec3> lo(around.size(), glm::dvec3(std::numeric_limits<double>::max()));
    std::vector<glm::dvec3> hi(around.size(), glm::dvec3(-std::numeric_limits<double>::max()));
    std::vector<double> altitudes;
    altitudes.reserve(indices.size() / 3);
    std::vector<std::uint32_t> piece_triangles(around.size(), 0);
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        glm::dvec3 p[3];
        const std::uint32_t r = root(vertices[indices[t]].weld_id);
        ++piece_triangles[r];
        for (int k = 0; k < 3; ++k) {
            p[k] = glm::dvec3(transform * glm::vec4(vertices[indices[t + std::size_t(k)]].position, 1.0f));
            lo[r] = glm::min(lo[r], p[k]);
            hi[r] = glm::max(hi[r], p[k]);
        }
        const double longest = std::max({glm::length(p[1] - p[0]), glm::length(p[2] - p[1]), glm::length(p[0] - p[2])});
        const double twice_area = glm::length(glm::cross(p[1] - p[0], p[2] - p[0]));
        if (longest > 0.0 && twice_area > 0.0) altitudes.push_back(twice_area / longest);
    }
    double across = 0.0; // the largest piece's diagonal
    for (std::size_t r = 0; r < around.size(); ++r)
        if (piece[r] == r && lo[r].x <= hi[r].x) across = std::max(across, glm::length(hi[r] - lo[r]));
    if (altitudes.empty() || !(depth > 0.0f)) {
        w.prisms = int(limit);
        return w;
    }
    const std::size_t at = altitudes.size() / 20;
    std::nth_element(altitudes.begin(), altitudes.begin() + std::ptrdiff_t(at), altitudes.end());
    const double narrow = altitudes[at];
    const double crossed = (across + 2.0 * double(depth)) / narrow;
    if (std::isfinite(crossed)) {
        // (A straight path crosses a prism once: no more than its piece's triangles. The estimate
        // alone warned of "about 15273506 prisms" for a square of four triangles, one a sliver;
        // found by an exploratory session, fiftieth. The limit keeps its margin.)
        const std::uint32_t largest_piece = *std::max_element(piece_triangles.begin(), piece_triangles.end());
        w.crossed = std::min(crossed, double(largest_piece));
        limit = std::max(limit, std::min(2.0 * crossed, kWalkCap));
    }
    w.prisms = int(std::min(limit, kWalkCap));
    return w;
}

// What the walk needs per triangle, from one pass over the triangles:
// - `prisms` (PR_TEX_PRISMS; shell.glsl, load_walk_prism), eight texels per triangle, so that the
//   walk finds a prism from its number alone: its corners' two texels of `corners` each (bottom
//   corner and u; unit normal and v), then their tight tops, then edge_adjacency()'s three
//   neighbours and the flags: bit 0 the prism's winding, as shell.glsl's walk_orientation reads
//   it (set where the base triangle, world space, winds clockwise about the sum of its vertices'
//   normals), bits 1..3 the diagonals of its sides (diagonal_from_a of edge e's welded ids),
//   PR_PRISM_FRAME_DIFFERS where a neighbour's texture frame differs from its own;
// - `listed` (PR_TEX_PRISM_LIST, prism.geom's PR_PRISM_LISTED), with the tight tops in `corners`
//   and with full ones: the prisms whose faces other than the caps the walk draws, in ascending
//   order — those whose shell folds (a cap turned more than 60 degrees from its base triangle),
//   with bit 31 set, and those with an edge without a neighbour, whose wall there is part of the
//   shell's outside.
struct WalkTriangles {
    std::vector<std::uint32_t> prisms;
    std::vector<std::uint32_t> listed[2]; // tight tops, full ones
};

// How much a neighbour's texture frame (dP/du, dP/dv) may differ from a triangle's, as a fraction
// of the frame's size, before the light's march in the triangle's texture plane gives way to the
// walk (prism.frag): a fifth is a turn of about 11 degrees of both axes. Flagged, with the
// triangles around the ends of such edges: none of the torus's and the plane's prisms, 26 % of
// the rock's, 39 % of the blob's, 60 % of the UV sphere's (its rows nearest the poles) and every
// one of the cube's.
constexpr float kFrameChange = 0.2f;

WalkTriangles walk_triangles(const std::vector<MeshVertex>& vertices, const std::vector<std::uint32_t>& indices,
                             const std::vector<glm::vec4>& corners, const EdgeAdjacency& adjacency,
                             const glm::mat4& transform, float depth)
{
    const std::vector<std::uint32_t>& neighbours = adjacency.neighbours;
    WalkTriangles w;
    w.prisms.reserve(indices.size() / 3 * 32);
    const auto normal = [](glm::vec3 a, glm::vec3 b, glm::vec3 c) { return glm::cross(b - a, c - a); };
    const auto turned = [](glm::vec3 n, glm::vec3 n_base) {
        return glm::dot(n, n_base) < 0.5f * glm::length(n) * glm::length(n_base);
    };
    const auto bits = [](const glm::vec4& v) {
        return std::array<std::uint32_t, 4>{std::bit_cast<std::uint32_t>(v.x), std::bit_cast<std::uint32_t>(v.y),
                                            std::bit_cast<std::uint32_t>(v.z), std::bit_cast<std::uint32_t>(v.w)};
    };
    // Each triangle's texture frame, dP/du and dP/dv (world): where a neighbour's differs (a crease,
    // a change of the UV scale, a UV seam), the texture plane around the triangle is not the
    // mesh's, and the light's march in it may pass bumps the mesh shows (flag bit 4).
    const std::size_t count = indices.size() / 3;
    std::vector<std::array<glm::vec3, 2>> frames(count);
    std::vector<char> no_frame(count, 0);
    for (std::size_t t = 0; t < count; ++t) {
        glm::vec3 p[3];
        glm::vec2 uv[3];
        for (int i = 0; i < 3; ++i) {
            const MeshVertex& v = vertices[indices[3 * t + std::size_t(i)]];
            p[i] = glm::vec3(transform * glm::vec4(v.position, 1.0f));
            uv[i] = v.uv;
        }
        const glm::vec3 e1 = p[1] - p[0], e2 = p[2] - p[0];
        const glm::vec2 d1 = uv[1] - uv[0], d2 = uv[2] - uv[0];
        const float det = d1.x * d2.y - d2.x * d1.y;
        no_frame[t] = !(std::abs(det) > 0.0f);
        if (!no_frame[t]) frames[t] = {(e1 * d2.y - e2 * d1.y) / det, (e2 * d1.x - e1 * d2.x) / det};
    }
    // Edge e of triangle t: whether the frames differ across it.
    const auto edge_differs = [&](std::size_t t, int e) {
        const std::uint32_t across = neighbours[3 * t + std::size_t(e)];
        if (across == kNoNeighbour) return false;
        const std::size_t n = across >> 2;
        if (no_frame[t] || no_frame[n] || adjacency.seam[3 * t + std::size_t(e)] != 0) return true; // (a UV seam)
        const float size = glm::length(frames[t][0]) + glm::length(frames[t][1]);
        const float change = glm::length(frames[n][0] - frames[t][0]) + glm::length(frames[n][1] - frames[t][1]);
        return !(change <= kFrameChange * size);
    };
    // The welded positions at the ends of such edges: the triangles around them are flagged too,
    // whose shell bends with the welded normal there though their own edges' frames agree (a sheet
    // folded along a hinge cut its shadows along the diagonals of the triangles that touch the
    // hinge at a corner; found by an exploratory session).
    std::vector<char> bent(vertices.size() ? welded_position_count(vertices) : 0, 0);
    for (std::size_t t = 0; t < count; ++t)
        for (int e = 0; e < 3; ++e)
            if (no_frame[t] || edge_differs(t, e)) {
                bent[vertices[indices[3 * t + std::size_t(e)]].weld_id] = 1;
                bent[vertices[indices[3 * t + std::size_t(e + 1) % 3]].weld_id] = 1;
            }
    const auto frame_differs = [&](std::size_t t) {
        if (no_frame[t]) return true;
        for (int i = 0; i < 3; ++i)
            if (bent[vertices[indices[3 * t + std::size_t(i)]].weld_id]) return true;
        return false;
    };
    for (std::size_t t = 0; t + 2 < indices.size(); t += 3) {
        glm::vec3 base[3], bottom[3], top[2][3], up(0.0f);
        glm::vec4 tops(0.0f);
        std::uint32_t weld[3];
        for (int i = 0; i < 3; ++i) {
            const std::uint32_t v = indices[t + std::size_t(i)];
            const ShellCorner c = shell_corner(corners, v);
            base[i] = glm::vec3(transform * glm::vec4(vertices[v].position, 1.0f));
            bottom[i] = c.bottom;
            top[0][i] = c.at(c.top, depth);
            top[1][i] = c.at(1.0f, depth);
            up += c.normal;
            tops[i] = c.top;
            weld[i] = c.weld;
        }
        for (int k = 0; k < 2; ++k)
            for (int i = 0; i < 3; ++i) {
                const auto texel = bits(corners[3 * std::size_t(indices[t + std::size_t(i)]) + std::size_t(k)]);
                w.prisms.insert(w.prisms.end(), texel.begin(), texel.end());
            }
        const auto top_bits = bits(tops);
        w.prisms.insert(w.prisms.end(), top_bits.begin(), top_bits.end());
        const glm::vec3 n_base = normal(base[0], base[1], base[2]);
        std::uint32_t flags = glm::dot(n_base, up) < 0.0f ? 1u : 0u;
        for (int e = 0; e < 3; ++e)
            if (weld[e] < weld[(e + 1) % 3]) flags |= 2u << e; // shell.glsl, diagonal_from_a
        if (frame_differs(t / 3)) flags |= PR_PRISM_FRAME_DIFFERS;
        w.prisms.insert(w.prisms.end(), {neighbours[t], neighbours[t + 1], neighbours[t + 2], flags});
        const bool open = std::any_of(neighbours.begin() + std::ptrdiff_t(t), neighbours.begin() + std::ptrdiff_t(t + 3),
                                      [](std::uint32_t n) { return n == kNoNeighbour; });
        const bool bottom_turned = turned(normal(bottom[0], bottom[1], bottom[2]), n_base);
        const auto prism = std::uint32_t(t / 3);
        for (int full = 0; full < 2; ++full) {
            if (bottom_turned || turned(normal(top[full][0], top[full][1], top[full][2]), n_base))
                w.listed[full].push_back(prism | 0x80000000u);
            else if (open)
                w.listed[full].push_back(prism);
        }
    }
    return w;
}

// The scissor as the caller left it: `clip` bounds a box by it (unchanged where the test is
// off), `restore` sets it back.
struct ScissorState {
    bool enabled = false;
    std::array<GLint, 4> box{};
    static ScissorState current()
    {
        ScissorState s;
        s.enabled = glIsEnabled(GL_SCISSOR_TEST) == GL_TRUE;
        glGetIntegerv(GL_SCISSOR_BOX, s.box.data());
        return s;
    }
    std::array<GLint, 4> clip(std::array<GLint, 4> r) const
    {
        if (!enabled) return r;
        const GLint x0 = std::max(r[0], box[0]), y0 = std::max(r[1], box[1]);
        const GLint x1 = std::min(r[0] + r[2], box[0] + box[2]), y1 = std::min(r[1] + r[3], box[1] + box[3]);
        return {x0, y0, x1 - x0, y1 - y0};
    }
    void restore() const
    {
        glScissor(box[0], box[1], box[2], box[3]);
        if (enabled) glEnable(GL_SCISSOR_TEST);
        else glDisable(GL_SCISSOR_TEST);
    }
};

// The second pass's work, tile by tile: for each tile the first pass marked in `tiles` (tw x th),
// the prisms whose bottom cap's screen box covers it, and those it is unsure of (a corner behind
// the eye, a box of more than 64 tiles) in every marked tile; each tile's list is drawn with the
// tile as scissor. The lists one after the other in `prisms`, tile t's from offsets[t] to
// offsets[t + 1]; `marked` the tiles (y * tw + x) in that order.
struct TileLists {
    std::vector<std::uint32_t> prisms, offsets, marked;
};

TileLists prisms_over_marked_tiles(const std::vector<glm::vec4>& corners, const std::vector<std::uint32_t>& triangles,
                                   const glm::mat4& view_proj, glm::vec2 viewport, const std::vector<GLuint>& tiles,
                                   int tw, int th)
{
    TileLists out;
    std::vector<int> slot(tiles.size(), -1);
    for (std::size_t i = 0; i < tiles.size(); ++i) {
        if (tiles[i] == 0) continue;
        slot[i] = int(out.marked.size());
        out.marked.push_back(std::uint32_t(i));
    }
    std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs; // (slot, prism)
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
        const auto prism = std::uint32_t(t / 3);
        glm::vec2 lo(1e30f), hi(-1e30f);
        bool unsure = false;
        for (int i = 0; i < 3; ++i) {
            const glm::vec4 clip = view_proj * glm::vec4(shell_corner(corners, triangles[t + std::size_t(i)]).bottom, 1.0f);
            if (clip.w <= 0.0f) {
                unsure = true;
                break;
            }
            const glm::vec2 px = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * viewport;
            lo = glm::min(lo, px);
            hi = glm::max(hi, px);
        }
        if (!unsure && !(lo.x < viewport.x && lo.y < viewport.y && hi.x >= 0.0f && hi.y >= 0.0f)) continue;
        const glm::ivec2 a = unsure ? glm::ivec2(0)
                                    : glm::clamp(glm::ivec2(glm::floor(lo / float(PR_TEAR_TILE))), glm::ivec2(0),
                                                 glm::ivec2(tw - 1, th - 1));
        const glm::ivec2 b = unsure ? glm::ivec2(-1)
                                    : glm::clamp(glm::ivec2(glm::floor(hi / float(PR_TEAR_TILE))), glm::ivec2(0),
                                                 glm::ivec2(tw - 1, th - 1));
        if (unsure || (b.x - a.x + 1) * (b.y - a.y + 1) > 64) {
            for (std::size_t m = 0; m < out.marked.size(); ++m) pairs.emplace_back(std::uint32_t(m), prism);
            continue;
        }
        for (int y = a.y; y <= b.y; ++y)
            for (int x = a.x; x <= b.x; ++x)
                if (const int s = slot[std::size_t(y) * std::size_t(tw) + std::size_t(x)]; s >= 0)
                    pairs.emplace_back(std::uint32_t(s), prism);
    }
    std::sort(pairs.begin(), pairs.end());
    out.offsets.assign(out.marked.size() + 1, 0);
    for (const auto& [s, p] : pairs) {
        ++out.offsets[s + 1];
        out.prisms.push_back(p);
    }
    for (std::size_t m = 0; m < out.marked.size(); ++m) out.offsets[m + 1] += out.offsets[m];
    return out;
}

std::string variant_key(const ShaderDefines& defines)
{
    std::string key;
    for (const auto& [k, v] : defines) key += k + "=" + v + ";";
    return key;
}

ShaderDefines defines_for(const DrawSettings& s)
{
    static const char* tech[] = {"PR_TECH_FLAT", "PR_TECH_NORMAL",    "PR_TECH_OFFSET",
                                 "PR_TECH_STEEP", "PR_TECH_POM",      "PR_TECH_RELIEF",
                                 "PR_TECH_REFERENCE", "PR_TECH_PRISM", "PR_TECH_CONE",
                                 "PR_TECH_RELAXED_CONE"};
    static const char* marcher[] = {"PR_MARCH_LINEAR", "PR_MARCH_RELIEF", "PR_MARCH_CONE",
                                    "PR_MARCH_RELAXED_CONE", "PR_MARCH_MAX_MIP"};
    static const char* shadows[] = {"PR_SHADOWS_NONE", "PR_SHADOWS_HARD", "PR_SHADOWS_SOFT"};
    static const char* quality[] = {"PR_NORMAL_GATHER", "PR_NORMAL_CENTRAL", "PR_NORMAL_SOBEL"};
    ShaderDefines d = {{"PR_TECHNIQUE", tech[static_cast<int>(s.technique)]},
                       {"PR_NORMAL_QUALITY", quality[static_cast<int>(s.normal_quality)]}};
    if (s.technique == Technique::Prism) {
        d.emplace_back("PR_MARCHER", marcher[static_cast<int>(s.marcher)]);
        if (s.prism_exit == PrismExit::Vertex) d.emplace_back("PR_PRISM_EXIT_VERTEX", "1");
        if (s.prism_walk()) d.emplace_back("PR_PRISM_WALK", "1");
        if (s.prism_walk() && s.full_shell) d.emplace_back("PR_PRISM_FULL_SHELL", "1");
    }
    // Only where the point shown lies below the polygon (reads_depth_write): flat, normal and
    // offset show the polygon's own depth, which the rasterizer's is.
    if (s.depth_write && reads_depth_write(s)) d.emplace_back("PR_DEPTH_WRITE", "1");
    if (drawn_shadows(s) != Shadows::None) d.emplace_back("PR_SHADOWS", shadows[static_cast<int>(s.shadows)]);
    if (s.aux_map() == AuxMap::Cone || s.aux_map() == AuxMap::Relaxed) d.emplace_back("PR_HEIGHT_FROM_CONE", "1");
    if (marches_patches(s)) d.emplace_back("PR_CONE_PATCHES", "1");
    if (s.count_samples) d.emplace_back("PR_COUNT_SAMPLES", "1");
    return d;
}

} // namespace

Renderer::Renderer(int width, int height) : width_(width), height_(height)
{
    create_target();
    frame_ubo_ = gl::Buffer::create();
    glNamedBufferStorage(frame_ubo_.id(), sizeof(shader::FrameBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
    object_ubo_ = gl::Buffer::create();
    glNamedBufferStorage(object_ubo_.id(), sizeof(shader::ObjectBlock), nullptr, GL_DYNAMIC_STORAGE_BIT);
    counters_ = gl::Buffer::create();
    const std::size_t counter_bytes = (kCounterWords + 2 * kHistogramBins) * sizeof(std::uint32_t);
    glNamedBufferStorage(counters_.id(), counter_bytes, nullptr,
                         GL_DYNAMIC_STORAGE_BIT | GL_MAP_READ_BIT);
    const auto* name = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    const std::string renderer = name ? name : "";
    software_ = renderer.find("llvmpipe") != std::string::npos || renderer.find("softpipe") != std::string::npos;
    tear_pass_ = software_ ? TearPass::Tiles : TearPass::Whole;
}

Renderer::~Renderer() = default;

void Renderer::create_target()
{
    GLint max_size = 0;
    glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
    if (width_ < 1 || height_ < 1 || width_ > max_size || height_ > max_size)
        throw Error("--size", std::to_string(width_) + "x" + std::to_string(height_) +
                                  " is outside 1.." + std::to_string(max_size) + " per side");
    color_target_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(color_target_.id(), 1, GL_RGBA8, width_, height_);
    depth_target_ = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(depth_target_.id(), 1, GL_DEPTH_COMPONENT32F, width_, height_);
    tear_mask_ = {};
    tear_tiles_ = {};
    fbo_ = gl::Framebuffer::create();
    glNamedFramebufferTexture(fbo_.id(), GL_COLOR_ATTACHMENT0, color_target_.id(), 0);
    glNamedFramebufferTexture(fbo_.id(), GL_DEPTH_ATTACHMENT, depth_target_.id(), 0);
    if (glCheckNamedFramebufferStatus(fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("--size", "could not create a " + std::to_string(width_) + "x" +
                                  std::to_string(height_) + " render target (out of memory?)");
}

void Renderer::resize(int width, int height)
{
    if (width == width_ && height == height_) return;
    width_ = width;
    height_ = height;
    create_target();
}

void Renderer::upload(const Scene& scene)
{
    shadow_light_.reset();
    objects_.clear();
    texture_cache_.clear();
    aux_cache_.clear();
    cone_entries_.clear();
    // Cone maps stay for the height fields the new scene still draws with.
    for (auto it = cone_maps_.begin(); it != cone_maps_.end();) {
        const bool kept = std::any_of(scene.objects.begin(), scene.objects.end(),
                                      [&](const SceneObject& so) { return so.height == it->second.field; });
        it = kept ? std::next(it) : cone_maps_.erase(it);
    }
    // Each height field's range, found once for the objects that share it (each object scanned
    // every texel: 200 cubes under builtin:bumps@4096 took 10-16 s to upload; found by an
    // exploratory session, thirty-eighth).
    std::map<const HeightField*, std::pair<float, float>> ranges;
    for (std::size_t k = 0; k < scene.objects.size(); ++k) {
        const SceneObject& so = scene.objects[k];
        GpuObject o;
        o.depth = so.depth;
        o.midlevel = so.midlevel;
        // (A Scene put together by hand, as tests do, has no bounds.)
        const Sphere shell = k < scene.object_bounds.size() ? scene.object_bounds[k] : sphere_around(shell_box(so));
        o.shell_radius = float(shell.radius);
        o.shell_center = shell.center;
        o.name = !so.place.empty() ? so.place : so.mesh_name.empty() ? "object " + std::to_string(k) : so.mesh_name;
        o.origin = glm::dvec3(so.transform[3]);
        o.local = linear_part(so.transform);
        o.base_color = so.base_color;
        o.base = make_geometry(so.mesh.vertices, so.mesh.indices);

        // Textures shared between objects are uploaded once; the cache owns them and each
        // object refers to the cached name (gl::Texture is move-only, so objects hold none).
        auto& h = texture_cache_[so.height.get()];
        if (!h) h = make_height_texture(*so.height);
        o.height_texture = h.id();
        o.height_size = {so.height->width, so.height->height};
        o.height_field = so.height;
        const auto [range, fresh] = ranges.try_emplace(so.height.get());
        if (fresh) range->second = {so.height->min_value(), so.height->max_value()};
        o.height_low = range->second.first;
        o.height_high = range->second.second;
        if (so.color) {
            auto& c = texture_cache_[so.color.get()];
            if (!c) c = make_color_texture(*so.color);
            o.color_texture = c.id();
        }
        objects_.push_back(std::move(o));
    }
    if (glGetError() == GL_OUT_OF_MEMORY) throw Error("scene", "out of GPU memory while uploading");
}

Renderer::Geometry Renderer::make_geometry(const std::vector<MeshVertex>& verts,
                                           const std::vector<std::uint32_t>& idx)
{
    Geometry g;
    g.vertices = gl::immutable_buffer(verts);
    g.indices = gl::immutable_buffer(idx);
    g.index_count = static_cast<GLsizei>(idx.size());
    g.vao = make_vertex_array(g.vertices.id(), g.indices.id());
    return g;
}

gl::VertexArray Renderer::make_vertex_array(GLuint vertices, GLuint indices)
{
    gl::VertexArray array = gl::VertexArray::create();
    const GLuint vao = array.id();
    glVertexArrayVertexBuffer(vao, 0, vertices, 0, sizeof(MeshVertex));
    glVertexArrayElementBuffer(vao, indices);
    const auto attrib = [vao](GLuint loc, GLint n, std::size_t offset) {
        glEnableVertexArrayAttrib(vao, loc);
        glVertexArrayAttribFormat(vao, loc, n, GL_FLOAT, GL_FALSE, static_cast<GLuint>(offset));
        glVertexArrayAttribBinding(vao, loc, 0);
    };
    attrib(PR_ATTR_POSITION, 3, offsetof(MeshVertex, position));
    attrib(PR_ATTR_NORMAL, 3, offsetof(MeshVertex, normal));
    attrib(PR_ATTR_UV, 2, offsetof(MeshVertex, uv));
    attrib(PR_ATTR_TANGENT, 4, offsetof(MeshVertex, tangent));
    attrib(PR_ATTR_BITANGENT, 3, offsetof(MeshVertex, bitangent));
    glEnableVertexArrayAttrib(vao, PR_ATTR_WELD_ID);
    glVertexArrayAttribIFormat(vao, PR_ATTR_WELD_ID, 1, GL_UNSIGNED_INT, offsetof(MeshVertex, weld_id));
    glVertexArrayAttribBinding(vao, PR_ATTR_WELD_ID, 0);
    if (glGetError() == GL_OUT_OF_MEMORY) throw GpuOutOfMemory("scene", "out of GPU memory while uploading geometry");
    return array;
}

namespace {

// The option that sets the number of the reference's triangles.
std::string reference_size_option(const ReferenceOptions& options)
{
    return options.level > 0 ? "--reference-level" : "--reference-max-triangles";
}

// Memory (the CPU's or the GPU's) ran out for the reference's triangles (the scene's, all
// objects'): named by the option that sets their number.
Error reference_out_of_memory(const ReferenceOptions& options, std::size_t triangles, int level)
{
    const std::string option = reference_size_option(options);
    return Error(option, "out of memory for the reference's " + std::to_string(triangles) + " triangles (level " +
                             std::to_string(level) + "): give a lower " + option);
}

// The reference needs `bytes`, more than the `available` memory (renderer on the CPU).
Error reference_too_large(const ReferenceOptions& options, std::size_t triangles, int level, std::uint64_t bytes,
                          std::uint64_t available)
{
    const auto gb = [](std::uint64_t b) {
        char text[32];
        std::snprintf(text, sizeof text, "%.1f GB", double(b) / 1e9);
        return std::string(text);
    };
    const std::string option = reference_size_option(options);
    return Error(option, "the reference's " + std::to_string(triangles) + " triangles (level " + std::to_string(level) +
                             ") need " + gb(bytes) + ", more than the " + gb(available) +
                             " of memory available: give a lower " + option);
}

} // namespace

Renderer::ReferenceStats Renderer::prepare_reference(const Scene& scene, const Camera& camera,
                                                     const ReferenceOptions& options)
{
    if (scene.objects.size() != objects_.size())
        throw Error("reference", "the scene was not uploaded to this renderer");
    const auto start = std::chrono::steady_clock::now();
    shadow_light_.reset();
    ReferenceStats stats;
    constexpr std::size_t kChunkTriangles = 1u << 20; // output triangles per upload
    std::vector<MeshVertex> vertices;
    std::vector<std::uint32_t> indices;
    std::size_t scene_triangles = 0;
    for (const SceneObject& so : scene.objects) scene_triangles += so.mesh.triangle_count();
    const int floor_level = cheap_reference_level(scene_triangles);
    // Each object's level, then the cap on all of them together: applied to each object alone,
    // it let N objects build N times its triangles (2,000 cubes, 131 M triangles for a 64 x 64
    // compare, out of memory naming one object's 65,712; found by an exploratory session,
    // thirty-eighth). A map that objects share is scanned once (each object scanned it: 200
    // cubes under builtin:bumps@4096 took a minute).
    // An object out of view takes no more than the scene's cheap level (what its shadows, with
    // --shadows, may need): with the cap on the scene, objects behind the eye lowered the levels
    // of those in view, which the cap named (a torus at level 30 alone, 15 beside four rocks
    // behind the eye; found by an exploratory session, thirty-eighth).
    // An object in view is floored at least at its share of the cheap budget, the budget over the
    // objects in view: with the scene's floor alone a small object beside large ones fell to its
    // pixel criterion (a 12-triangle cube at level 31 beside a sphere and a torus, 147 alone, and
    // the scene's PSNR 24.8 dB where its objects alone gave 27.8-41.5; found by an exploratory
    // session, forty-fourth). The whole then holds at most twice the cheap budget.
    std::vector<ReferenceLevel> levels(objects_.size());
    std::vector<std::size_t> base_triangles(objects_.size());
    std::vector<char> hidden(objects_.size(), 0);
    std::size_t in_view = 0;
    for (std::size_t k = 0; k < objects_.size(); ++k) {
        base_triangles[k] = scene.objects[k].mesh.triangle_count();
        hidden[k] = k < scene.object_bounds.size() &&
                    !sphere_in_view(camera, double(width_) / double(std::max(height_, 1)), scene.object_bounds[k]);
        in_view += hidden[k] == 0;
    }
    std::map<const HeightField*, TexelSteps> steps;
    for (std::size_t k = 0; k < objects_.size(); ++k) {
        const SceneObject& so = scene.objects[k];
        if (options.level > 0) {
            levels[k].level = options.level;
            continue;
        }
        const auto [at, fresh] = steps.try_emplace(so.height.get());
        if (fresh) at->second = texel_steps(*so.height);
        const int floor_k = hidden[k] ? floor_level
                                      : std::max(floor_level, cheap_reference_level(base_triangles[k] * std::max<std::size_t>(in_view, 1)));
        levels[k] = choose_reference_level(so.mesh, so.transform, *so.height, at->second, so.depth, so.midlevel, camera,
                                           width_, height_, std::numeric_limits<std::size_t>::max(), floor_k);
        if (hidden[k]) levels[k].level = std::min(levels[k].level, floor_level);
    }
    // (An explicit level is not capped: the sum is the scene's triangles.)
    const std::size_t scene_total = cap_reference_levels(
        levels, base_triangles, options.level > 0 ? std::numeric_limits<std::size_t>::max() : options.max_triangles);
    for (std::size_t k = 0; k < levels.size(); ++k)
        if (hidden[k]) levels[k].capped = false; // (lowered for being out of view, not by the cap)
    // A bound under the meshes' own triangles cannot be kept: level 1 is the meshes themselves
    // (said; the report's `capped` alone read as if it had been kept: 2304 triangles under a bound
    // of 1; found by an exploratory session, fifty-second).
    if (options.level == 0 && scene_total > options.max_triangles)
        warn("--reference-max-triangles: " + std::to_string(options.max_triangles) + " is under the " +
             std::to_string(scene_total) + " triangles of the meshes themselves (level 1): the reference has those");
    int finest = 1;
    for (const ReferenceLevel& lv : levels) finest = std::max(finest, lv.level);
    // The reference held now is given back first: rebuilt, it is replaced (and on llvmpipe a
    // rebuild that fits once it is gone, the viewer's, was refused while it was counted below;
    // found by a review).
    for (GpuObject& o : objects_) o.reference.clear();
    // A software renderer's buffers are this process's memory: a reference larger than what the
    // system has available is refused before it is built. (An explicit --reference-level 256 on
    // the rock asks for 27 GB, more than the 23 GB machine has: it was built chunk by chunk until
    // memory ran out, and where the system overcommits memory the kernel kills such a process,
    // with no message, rather than failing an allocation.)
    if (software_) {
        std::uint64_t bytes = 0;
        for (std::size_t k = 0; k < levels.size(); ++k)
            bytes += std::uint64_t(base_triangles[k]) * reference_bytes_per_triangle(levels[k].level);
        const std::optional<std::uint64_t> available = available_memory_bytes();
        if (available && bytes > *available) throw reference_too_large(options, scene_total, finest, bytes, *available);
    }
    for (std::size_t k = 0; k < objects_.size(); ++k) {
        const SceneObject& so = scene.objects[k];
        GpuObject& o = objects_[k];
        const ReferenceLevel& lv = levels[k];
        stats.level = std::max(stats.level, lv.level);
        stats.levels.push_back(lv.level);
        stats.capped = stats.capped || lv.capped;
        stats.capped_objects.push_back(lv.capped ? 1 : 0);
        const std::size_t per_base = std::size_t(lv.level) * std::size_t(lv.level);
        const std::size_t batch = std::max<std::size_t>(1, kChunkTriangles / per_base);
        const std::size_t count = so.mesh.triangle_count();
        // Out of memory, the CPU's or the GPU's: named by what sets its size (the one line was
        // "scene: out of GPU memory…", or "out of memory" alone, found by an exploratory session).
        // No object keeps a reference: the memory is given back, and a draw asks for
        // prepare_reference() again.
        const auto out_of_memory = [&] {
            for (GpuObject& each : objects_) each.reference.clear();
            return reference_out_of_memory(options, scene_total, finest);
        };
        try {
            for (std::size_t first = 0; first < count; first += batch) {
                vertices.clear();
                indices.clear();
                tessellate_reference(so.mesh, linear_part(so.transform), *so.height, so.depth, so.midlevel, lv.level,
                                     first, std::min(count, first + batch), vertices, indices);
                stats.triangles += indices.size() / 3;
                stats.bytes += vertices.size() * sizeof(MeshVertex) + indices.size() * sizeof(std::uint32_t);
                o.reference.push_back(make_geometry(vertices, indices)); // (GpuOutOfMemory)
            }
        } catch (const std::bad_alloc&) {
            throw out_of_memory();
        } catch (const GpuOutOfMemory&) {
            throw out_of_memory();
        }
    }
    stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

GLuint Renderer::program_for(const DrawSettings& settings, WalkVariant variant, ShellDraw shell, bool color_texture)
{
    ShaderDefines defines = defines_for(settings);
    if (color_texture) defines.emplace_back("PR_COLOR_TEXTURE", "1");
    if (variant == WalkVariant::Seamless) defines.emplace_back("PR_PRISM_SEAMLESS", "1");
    if (variant == WalkVariant::Through || variant == WalkVariant::Inside || variant == WalkVariant::UnderSurface ||
        variant == WalkVariant::OpenEntry)
        defines.emplace_back("PR_PRISM_TEARS", "1");
    if (variant == WalkVariant::OpenEntry) defines.emplace_back("PR_PRISM_OPEN_ENTRY", "1");
    if (variant == WalkVariant::Inside) defines.emplace_back("PR_PRISM_INSIDE", "1");
    if (variant == WalkVariant::UnderSurface) defines.emplace_back("PR_PRISM_EYE_UNDER", "1");
    if (shell == ShellDraw::Tops) defines.emplace_back("PR_PRISM_TOPS", "1"); // no shader reads it: it keys the program, whose stages differ
    if (shell == ShellDraw::Bottoms) defines.emplace_back("PR_PRISM_BOTTOMS", "1");
    if (shell == ShellDraw::Listed) defines.emplace_back("PR_PRISM_LISTED", "1");
    if (shell == ShellDraw::FromEye) defines.emplace_back("PR_PRISM_FROM_EYE", "1");
    const std::string key = variant_key(defines);
    auto it = programs_.find(key);
    if (it == programs_.end()) {
        gl::Program p = settings.technique != Technique::Prism
                            ? build_program({{GL_VERTEX_SHADER, "surface.vert"},
                                             {GL_FRAGMENT_SHADER, "surface.frag"}},
                                            defines)
                        : shell == ShellDraw::Tops || shell == ShellDraw::Bottoms || shell == ShellDraw::FromEye
                            ? build_program({{GL_VERTEX_SHADER, shell == ShellDraw::FromEye ? "prism_eye.vert" : "prism_caps.vert"},
                                             {GL_FRAGMENT_SHADER, "prism.frag"}},
                                            defines)
                            : build_program({{GL_VERTEX_SHADER, shell == ShellDraw::Listed ? "prism_caps.vert" : "prism.vert"},
                                             {GL_GEOMETRY_SHADER, "prism.geom"},
                                             {GL_FRAGMENT_SHADER, "prism.frag"}},
                                            defines);
        it = programs_.emplace(key, std::move(p)).first;
    }
    return it->second.id();
}

const std::filesystem::path& Renderer::cache_dir()
{
    static const std::filesystem::path none;
    if (no_cache_) return none;
    if (cache_dir_.empty()) cache_dir_ = default_cache_dir();
    return cache_dir_;
}

namespace {

std::vector<ConeKind> cone_kinds_for(AuxMap map)
{
    if (map == AuxMap::Cone) return {ConeKind::Cone};
    if (map == AuxMap::Relaxed) return {ConeKind::Cone, ConeKind::Relaxed};
    return {};
}

} // namespace

std::vector<Renderer::ConeMapNeed> Renderer::missing_cone_maps(AuxMap map)
{
    std::vector<ConeMapNeed> needs;
    const int k = static_cast<int>(map) - 1;
    for (const GpuObject& o : objects_) {
        if (o.aux_texture[k] || aux_cache_.count({o.height_field.get(), k})) continue;
        for (ConeKind kind : cone_kinds_for(map)) {
            const bool listed = std::any_of(needs.begin(), needs.end(), [&](const ConeMapNeed& n) {
                return n.field == o.height_field && n.kind == kind;
            });
            if (listed || cone_maps_.count({o.height_field.get(), kind})) continue;
            // The entry's name hashes every texel: once per height field and kind, not every frame
            // that asks (the viewer asks while another map is built).
            auto entry = cone_entries_.find({o.height_field.get(), kind});
            if (entry == cone_entries_.end())
                entry = cone_entries_
                            .emplace(std::pair{o.height_field.get(), kind},
                                     cone_cache_entry(*o.height_field, kind, ConeBuildOptions{}, cache_dir()))
                            .first;
            std::error_code ec;
            needs.push_back({o.height_field, kind, std::filesystem::is_regular_file(entry->second, ec)});
        }
    }
    return needs;
}

void Renderer::provide_cone_map(const std::shared_ptr<const HeightField>& field, ConeMap map)
{
    const bool drawn = std::any_of(objects_.begin(), objects_.end(),
                                   [&](const GpuObject& o) { return o.height_field == field; });
    if (!drawn || !field || map.width != field->width || map.height != field->height) return;
    const ConeKind kind = map.kind;
    cone_maps_[{field.get(), kind}] = HeldConeMap{field, std::move(map)};
}

const ConeMap& Renderer::cone_map(const std::shared_ptr<const HeightField>& field, ConeKind kind)
{
    auto it = cone_maps_.find({field.get(), kind});
    if (it != cone_maps_.end()) return it->second.map;
    ConeBuildOptions options;
    if (cone_progress_) {
        options.progress = [this, what = cone_map_label(kind, *field)](double f) { cone_progress_(what, f); };
    }
    ConeBuilder build = build_cone_map_cpu;
    if (cone_gpu_)
        build = [](const HeightField& f, ConeKind k, const ConeBuildOptions& o) { return build_cone_map_gpu(f, k, o); };
    ConeMap map = cached_cone_map(*field, kind, cache_dir(), options, build).map;
    return cone_maps_.insert_or_assign({field.get(), kind}, HeldConeMap{field, std::move(map)}).first->second.map;
}

void Renderer::ensure_aux_textures(AuxMap map, bool patches)
{
    if (map == AuxMap::None) return;
    const int k = static_cast<int>(map) - 1;
    for (GpuObject& o : objects_) {
        if (!o.aux_texture[k]) {
            auto& t = aux_cache_[{o.height_field.get(), k}];
            if (!t) {
                if (map == AuxMap::MaxMip) {
                    t = make_max_pyramid_texture(*o.height_field);
                } else {
                    const ConeMap& cone = cone_map(o.height_field, ConeKind::Cone);
                    t = map == AuxMap::Cone ? make_cone_texture(cone)
                                            : make_cone_pair_texture(cone_map(o.height_field, ConeKind::Relaxed), cone);
                }
            }
            o.aux_texture[k] = t.id();
        }
        // The base-surface techniques' patches (make_patch_texture), built for them only.
        if (!patches || map == AuxMap::MaxMip || o.patch_texture[k]) continue;
        auto& t = aux_cache_[{o.height_field.get(), k + kPatchTextureKey}];
        if (!t) t = make_patch_texture(cone_map(o.height_field, map == AuxMap::Cone ? ConeKind::Cone : ConeKind::Relaxed));
        o.patch_texture[k] = t.id();
    }
    if (glGetError() == GL_OUT_OF_MEMORY) throw Error("scene", "out of GPU memory while uploading derived maps");
}

namespace {

// A buffer texture over `buffer`, read by the prism's shaders with texelFetch (shared.h); throws
// when the buffer holds more texels than this OpenGL's buffer textures can address.
gl::Texture buffer_texture(const gl::Buffer& buffer, GLenum format, GLint64 texel_bytes, GLint64 limit)
{
    GLint64 bytes = 0, max_texels = 0;
    glGetNamedBufferParameteri64v(buffer.id(), GL_BUFFER_SIZE, &bytes);
    glGetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &max_texels);
    if (limit > 0) max_texels = std::min(max_texels, limit);
    if (bytes / texel_bytes > max_texels) {
        throw Error("scene", "the mesh is too large for the prism technique: " + std::to_string(bytes / texel_bytes) +
                                 " texels in one buffer texture, this OpenGL allows " + std::to_string(max_texels));
    }
    gl::Texture t = gl::Texture::create(GL_TEXTURE_BUFFER);
    glTextureBuffer(t.id(), format, buffer.id());
    return t;
}

} // namespace

void Renderer::ensure_prism_data(bool walk)
{
    if (walk) ensure_walk_data();
    for (GpuObject& o : objects_) {
        // (Each set is kept only when all of it was made: a mesh too large leaves nothing half done.)
        if (!o.vertex_texels) {
            static_assert(sizeof(MeshVertex) == 16 * sizeof(float), "four rgba32ui texels per vertex");
            gl::Texture vertices = buffer_texture(o.base.vertices, GL_RGBA32UI, 16, texture_buffer_limit_);
            o.index_texels = buffer_texture(o.base.indices, GL_RGB32UI, 12, texture_buffer_limit_);
            o.vertex_texels = std::move(vertices);
        }
        if (walk && !o.corner_texels) {
            if (o.walk.vao) o.walk_index_texels = buffer_texture(o.walk.indices, GL_RGB32UI, 12, texture_buffer_limit_);
            o.prism_texels = buffer_texture(o.prisms, GL_RGBA32UI, 16, texture_buffer_limit_);
            for (int full = 0; full < 2; ++full)
                o.listed_texels[full] = buffer_texture(o.listed[full], GL_R32UI, 4, texture_buffer_limit_);
            o.corner_texels = buffer_texture(o.corners, GL_RGBA32UI, 16, texture_buffer_limit_);
        }
    }
}

void Renderer::bind_prism_data(const GpuObject& o, bool walk)
{
    glBindTextureUnit(PR_TEX_VERTICES, o.vertex_texels.id());
    glBindTextureUnit(PR_TEX_INDICES, walk && o.walk_index_texels ? o.walk_index_texels.id() : o.index_texels.id());
    glBindTextureUnit(PR_TEX_PRISMS, o.prism_texels.id());
    glBindTextureUnit(PR_TEX_CORNERS, o.corner_texels.id());
}

void Renderer::ensure_walk_data()
{
    // Built on the first walk draw, not at upload: other techniques need none of it (on a
    // 5-million-triangle mesh it takes about 2 s). The mesh comes back from its own buffers.
    for (GpuObject& o : objects_) {
        if (o.corners) continue;
        std::vector<MeshVertex> vertices;
        std::vector<std::uint32_t> base_indices;
        read_back_mesh(o, vertices, base_indices);
        // The walk's own triangles: flat, evenly mapped stretches merged (fewer prisms to cross).
        std::vector<std::uint32_t> indices = walk_triangles_of(vertices, base_indices);
        if (indices.size() != base_indices.size()) {
            o.walk.indices = gl::immutable_buffer(indices);
            o.walk.index_count = static_cast<GLsizei>(indices.size());
            o.walk.vao = make_vertex_array(o.base.vertices.id(), o.walk.indices.id());
        }
        base_indices = {};
        const EdgeAdjacency adjacency = edge_adjacency(vertices, indices);
        o.open_shell = adjacency.open_edges > 0;
        o.closed = !o.open_shell;
        o.tears = !o.open_shell && adjacency.seam_edges > 0;
        o.seamless = adjacency.seam_edges == 0;
        std::vector<glm::vec4> corners =
            make_shell_corners(vertices, indices, *o.height_field, o.height_high, o.local, o.depth, o.midlevel); // the object's frame
        o.corners = gl::immutable_buffer(corners);
        const WalkTriangles triangles = walk_triangles(vertices, indices, corners, adjacency, o.local, o.depth);
        o.prisms = gl::immutable_buffer(triangles.prisms);
        for (int full = 0; full < 2; ++full) {
            o.listed[full] = gl::immutable_buffer(triangles.listed[full]);
            o.listed_count[full] = GLsizei(triangles.listed[full].size());
        }
        const WalkLimit limit = walk_prism_limit(vertices, indices, o.local, o.depth);
        o.walk_max_prisms = limit.prisms;
        // Where the walk is cut short, said: the rays past it are dropped, holes in the picture,
        // and every ray that walks that far costs its crossings (a fan of 100,000 triangles drew
        // a ragged hole round its centre, IoU 0.927; an open cylinder of a million slivers took
        // over 150 s at 64 x 64; both without a word; found by an exploratory session,
        // forty-fourth). (docs/prism.md, "Known limits".)
        if (limit.most_around > kWalkMostAround)
            warn(o.name + ": a position has " + std::to_string(limit.most_around) +
                 " triangles around it, more than the prism's walk follows (" + std::to_string(kWalkMostAround) +
                 "): rays that pass near it may be dropped (holes in the prism's picture)");
        // (Past the walk's own limit, as the message says: twice the estimate, the limit's margin,
        // warned of "about 7074 prisms, more than the prism's walk follows (8448)"; found by an
        // exploratory session, fiftieth.)
        if (limit.crossed > kWalkCap)
            warn(o.name + ": its triangles are narrow for its size and shell: a ray through the shell may cross up to about " +
                 std::to_string(std::llround(std::min(limit.crossed, 1e12))) + " prisms, more than the prism's walk follows (" +
                 std::to_string(int(kWalkCap)) + "): rays that do are dropped (holes in the prism's picture), and long "
                 "walks make slow frames; a mesh of wider triangles or a smaller --depth helps");
        o.eye_blocks = prism_blocks(corners, indices, o.depth);
        o.triangles = std::move(indices);
        o.shell_corners = std::move(corners);
    }
    if (glGetError() == GL_OUT_OF_MEMORY) throw Error("scene", "out of GPU memory while building the prism walk's buffers");
}

void Renderer::read_back_mesh(const GpuObject& o, std::vector<MeshVertex>& vertices, std::vector<std::uint32_t>& indices)
{
    GLint64 vertex_bytes = 0;
    glGetNamedBufferParameteri64v(o.base.vertices.id(), GL_BUFFER_SIZE, &vertex_bytes);
    vertices.resize(static_cast<std::size_t>(vertex_bytes) / sizeof(MeshVertex));
    indices.resize(static_cast<std::size_t>(o.base.index_count));
    glGetNamedBufferSubData(o.base.vertices.id(), 0, static_cast<GLsizeiptr>(vertices.size() * sizeof(MeshVertex)),
                            vertices.data());
    glGetNamedBufferSubData(o.base.indices.id(), 0, static_cast<GLsizeiptr>(indices.size() * sizeof(std::uint32_t)),
                            indices.data());
}

bool Renderer::closed_shell(GpuObject& o)
{
    if (!o.closed) {
        // Only the edges' pairing: not the walk's buffers, shell corners and merged stretches,
        // which a base technique has no use for (0.5 s more on a 408k-triangle mesh).
        std::vector<MeshVertex> vertices;
        std::vector<std::uint32_t> indices;
        read_back_mesh(o, vertices, indices);
        o.closed = edge_adjacency(vertices, indices).open_edges == 0;
    }
    return *o.closed;
}

std::vector<std::uint32_t> Renderer::walk_triangles_of(const std::vector<MeshVertex>& vertices,
                                                       const std::vector<std::uint32_t>& indices)
{
    if (!has_flat_stretch(vertices, indices)) return indices; // cheaper than the key
    Fnv key;
    key.add(vertices.data(), vertices.size() * sizeof(MeshVertex));
    key.add(indices.data(), indices.size() * sizeof(std::uint32_t));
    const auto hit = std::find_if(merged_.begin(), merged_.end(), [&](const MergedTriangles& m) {
        return m.key == key.h && m.vertex_count == vertices.size() && m.index_count == indices.size();
    });
    if (hit != merged_.end()) {
        std::rotate(merged_.begin(), hit, hit + 1); // most recent first
        return merged_.front().indices;
    }
    std::vector<std::uint32_t> merged = merge_flat_regions(vertices, indices);
    if (merged.size() != indices.size()) {
        merged_.insert(merged_.begin(), MergedTriangles{key.h, vertices.size(), indices.size(), merged});
        if (merged_.size() > kMergedKept) merged_.pop_back();
    }
    return merged;
}

void Renderer::upload_object(const GpuObject& o, const DrawSettings& settings, float midlevel,
                             const EyeInShell* eye)
{
    upload_frame_block(o.origin);
    shader::ObjectBlock ob{};
    ob.u_model = o.local;
    ob.u_normal_matrix = glm::mat4(normal_matrix(o.local));
    ob.u_displace = glm::vec4(o.depth, midlevel, o.height_size.x, o.height_size.y);
    ob.u_march = glm::ivec4(settings.steps, settings.refine, eye ? int(eye->prism) : -1,
                            o.closed && !*o.closed ? PR_FLAG_OPEN_SHELL : 0); // (the walk's data sets it too)
    ob.u_eye_tex = eye ? glm::vec4(eye->tex, 0.0f) : glm::vec4(0.0f);
    ob.u_walk = glm::ivec4(o.walk_max_prisms, 0, 0, 0);
    ob.u_material = glm::vec4(0.12f, 0.88f, 0.18f, 48.0f);
    ob.u_base_color = glm::vec4(o.base_color, 1.0f);
    for (std::size_t k = 0; k < shadow_layers_.size(); ++k)
        ob.u_shadow[k] = glm::mat4(glm::dmat4(shadow_layers_[k].view_proj) *
                                   glm::translate(glm::dmat4(1.0), o.origin - shadow_layers_[k].origin));
    ob.u_shadow_bias = glm::vec4(shadow_bias_, float(shadow_layers_.size()), float(shadow_layer_drawn_));
    glNamedBufferSubData(object_ubo_.id(), 0, sizeof(ob), &ob);
}

namespace {

// Two axes across a unit direction: x and z turned as the shortest rotation from +y to it turns
// +y, so that they turn smoothly with it, but for directions within 0.26 degrees of straight
// below (-y), which take x and z themselves (the rotation there is about to turn round).
std::pair<glm::dvec3, glm::dvec3> across_light(const glm::dvec3& d)
{
    if (d.y > -0.99999) {
        const double a = 1.0 / (1.0 + d.y);
        return {glm::dvec3(1.0 - d.x * d.x * a, -d.x, -d.x * d.z * a), glm::dvec3(-d.x * d.z * a, -d.z, 1.0 - d.z * d.z * a)};
    }
    const glm::dvec3 side = glm::normalize(glm::dvec3(1.0, 0.0, 0.0) - d.x * d);
    return {side, glm::cross(side, d)};
}

} // namespace

void Renderer::ensure_shadow_map(glm::vec3 light_dir, bool soft, float light_tan)
{
    // Drawn for a light and a camera: each map covers the points the image shows (whatever casts
    // a shadow on one lies towards the light from it, which in the map's orthographic view is the
    // same texel), so its texels are as fine as that part of the scene needs. (Over the sphere
    // around every object's shell, a second torus 300 units away made them 70 times coarser,
    // and the first torus's bumps lost their shadows: found by a review.)
    const float aspect = float(width_) / float(height_);
    const Camera& c = frame_camera_;
    const Camera& k = shadow_camera_;
    const bool same_view = c.eye == k.eye && c.target == k.target && c.up == k.up && c.fovy_deg == k.fovy_deg &&
                           c.near_plane == k.near_plane && c.far_plane == k.far_plane && aspect == shadow_aspect_;
    if (!soft) light_tan = 0.0f;
    if (shadow_light_ && *shadow_light_ == light_dir && shadow_light_tan_ == light_tan &&
        int(shadow_layers_.size()) == (soft ? PR_SHADOW_LAYERS : 1) && same_view)
        return;
    if (!shadow_program_ || !shadow_eye_program_) { // (both, or again: a build that threw left one)
        shadow_program_ = build_program({{GL_VERTEX_SHADER, "shadow_map.vert"}}, {});
        shadow_eye_program_ = build_program({{GL_VERTEX_SHADER, "shadow_map.vert"}}, {{"PR_SHADOW_FROM_EYE", "1"}});
    }
    // The caller's scissor (the viewer's split view) would keep the map's clear and draws to its
    // own columns: off here, set back at the end.
    const ScissorState scissor = ScissorState::current();
    glDisable(GL_SCISSOR_TEST);
    // Hard shadows: one map of 4096 texels a side, read at the nearest texel. Soft: one of 2048 a
    // side from each direction over the disc (16 of 4096 would take a gigabyte), each read
    // filtered over its 2 x 2 texels, which smooths the steps between the directions' edges.
    const int size = soft ? kSoftShadowMapSize : kShadowMapSize;
    const int layers = soft ? PR_SHADOW_LAYERS : 1;
    if (!shadow_map_ || shadow_map_size_ != size || shadow_map_layers_ != layers) {
        shadow_depth_ = {};
        shadow_map_ = {};
        shadow_fbo_ = {};
        shadow_light_.reset();
        while (glGetError() != GL_NO_ERROR) {} // (an earlier error is not this one)
        shadow_map_ = gl::Texture::create(GL_TEXTURE_2D_ARRAY);
        glTextureStorage3D(shadow_map_.id(), 1, GL_DEPTH_COMPONENT32F, size, size, layers);
        const GLint filter = soft ? GL_LINEAR : GL_NEAREST;
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_MIN_FILTER, filter);
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_MAG_FILTER, filter);
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
        glTextureParameteri(shadow_map_.id(), GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
        // The soft shadows' blocker search reads the depths: a view of the same storage with its
        // own parameters (a view's name must be new, not yet a texture: glGenTextures).
        GLuint view = 0;
        glGenTextures(1, &view);
        glTextureView(view, GL_TEXTURE_2D_ARRAY, shadow_map_.id(), GL_DEPTH_COMPONENT32F, 0, 1, 0, GLuint(layers));
        shadow_depth_ = gl::Texture(view);
        glTextureParameteri(view, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(view, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTextureParameteri(view, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTextureParameteri(view, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        glTextureParameteri(view, GL_TEXTURE_COMPARE_MODE, GL_NONE);
        shadow_fbo_ = gl::Framebuffer::create();
        glNamedFramebufferTextureLayer(shadow_fbo_.id(), GL_DEPTH_ATTACHMENT, shadow_map_.id(), 0, 0);
        glNamedFramebufferDrawBuffer(shadow_fbo_.id(), GL_NONE);
        if (glGetError() == GL_OUT_OF_MEMORY ||
            glCheckNamedFramebufferStatus(shadow_fbo_.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
            shadow_depth_ = {};
            shadow_map_ = {};
            shadow_fbo_ = {};
            shadow_map_size_ = shadow_map_layers_ = 0;
            scissor.restore();
            throw Error("--shadows", "could not create the reference's shadow map" + std::string(soft ? "s (" : " (") +
                                         (soft ? std::to_string(layers) + " of " : std::string()) +
                                         std::to_string(size) + "x" + std::to_string(size) + ", out of GPU memory?)");
        }
        shadow_map_size_ = size;
        shadow_map_layers_ = layers;
    }
    const auto draw_references = [&](GLuint program) {
        glUseProgram(program);
        for (const GpuObject& o : objects_) {
            upload_object(o, DrawSettings{}, o.midlevel);
            for (const Geometry& g : o.reference) {
                glBindVertexArray(g.vao.id());
                glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
            }
        }
    };

    // The maps' frames are about the centre of the objects' shells, every one within `radius` of it.
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const GpuObject& o : objects_) {
        lo = glm::min(lo, o.shell_center - double(o.shell_radius));
        hi = glm::max(hi, o.shell_center + double(o.shell_radius));
    }
    const glm::dvec3 centre = objects_.empty() ? glm::dvec3(0.0) : 0.5 * (lo + hi);
    double radius = 0.0;
    for (const GpuObject& o : objects_)
        radius = std::max(radius, glm::distance(centre, o.shell_center) + double(o.shell_radius));
    radius = std::max(radius * 1.01, 1e-20);

    // The points the image shows: the references' depth from the camera (a pass into the frame's
    // own depth target, which the frame clears after), read back and taken to the world about
    // the centre (in double: a float view far from the origin is coarse).
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width_, height_);
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glDisable(GL_CULL_FACE); // (both sides cast and are seen)
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
    glDepthMask(GL_TRUE);
    const GLfloat far_eye = 0.0f;
    glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &far_eye);
    GLboolean color_mask[4];
    glGetBooleanv(GL_COLOR_WRITEMASK, color_mask);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE); // (the program has no fragment stage)
    shadow_layers_.clear(); // (none while the camera's pass uploads the objects)
    draw_references(shadow_eye_program_.id());
    glColorMask(color_mask[0], color_mask[1], color_mask[2], color_mask[3]);
    const std::vector<float> depth = read_depth();
    const Camera& cam = frame_camera_;
    const glm::dmat4 to_world = glm::inverse(glm::dmat4(cam.projection(aspect)) *
                                             glm::lookAt(cam.eye - centre, cam.target - centre, glm::dvec3(cam.up)));
    std::vector<glm::dvec3> shown;
    for (int y = 0; y < height_; ++y)
        for (int x = 0; x < width_; ++x) {
            const float d = depth[std::size_t(y) * std::size_t(width_) + std::size_t(x)];
            if (!(d > 0.0f)) continue; // nothing there
            const glm::dvec4 w = to_world * glm::dvec4((x + 0.5) / width_ * 2.0 - 1.0, (y + 0.5) / height_ * 2.0 - 1.0,
                                                       double(d), 1.0);
            shown.push_back(glm::dvec3(w) / w.w);
        }

    // The directions: along the light, or spread evenly over its disc (a sunflower spiral: the
    // k-th at the radius sqrt((k + 1/2) / n) of the disc's, turned by the golden angle from the
    // one before), on axes that turn smoothly with the light (across_light: axes from a cross
    // product with y, or with x near y, switched 8 degrees from overhead, and the pattern's turn
    // changed the image: 41 dB between two lights 0.07 degrees apart; found by a review).
    const glm::dvec3 toward = glm::normalize(glm::dvec3(light_dir));
    const auto [side_axis, up_axis] = across_light(toward);
    std::vector<ShadowLayer> fitted(static_cast<std::size_t>(layers));
    double texel = 0.0, depth_bias = 0.0;
    for (int layer = 0; layer < layers; ++layer) {
        glm::dvec3 dir = toward;
        if (soft) {
            const double r = double(light_tan) * std::sqrt((layer + 0.5) / layers);
            const double a = layer * 2.39996322972865332; // the golden angle
            dir = glm::normalize(toward + r * (std::cos(a) * side_axis + std::sin(a) * up_axis));
        }
        // The light's frame: x, y across the light, z along it towards the light (a rotation).
        // (The map's texels on the same smooth axes: an up vector that switched from y to x turned
        // the texel grid, and the hard shadows' image changed: 57.7 dB between two lights 0.01
        // degrees apart, 71-76 for the steps around; found by a review.)
        const glm::dmat4 light_axes = glm::lookAt(glm::dvec3(0.0), -dir, across_light(dir).second); // view z = dot(p, dir)
        const glm::dmat3 rotate(light_axes);
        glm::dvec3 box_lo(std::numeric_limits<double>::max()), box_hi(-std::numeric_limits<double>::max());
        for (const glm::dvec3& p : shown) {
            const glm::dvec3 l = rotate * p;
            box_lo = glm::min(box_lo, l);
            box_hi = glm::max(box_hi, l);
        }
        if (box_lo.x > box_hi.x) { // nothing shown: any map will do
            box_lo = glm::dvec3(-radius);
            box_hi = glm::dvec3(radius);
        }
        // A margin for the pixels' spread (a pixel's footprint, and --msaa's shifted passes) and
        // the look-up's offset towards the light: 2 % of the box and 8 texels of it.
        const double extent = std::max({box_hi.x - box_lo.x, box_hi.y - box_lo.y, 1e-9 * radius});
        const double margin = 0.02 * extent + 8.0 * extent / size;
        box_lo -= margin;
        box_hi += margin;
        // Its depth, likewise: from the farthest point shown up to the nearest point towards the
        // light of any shell over the box (only those can shadow a point in it). Over the whole
        // scene's sphere, and about its centre, a torus a million units off made the depth's steps
        // and bias coarser than the bumps, and a third of the shadows went (found by a review).
        for (const GpuObject& o : objects_) {
            const glm::dvec3 oc = rotate * (o.shell_center - centre);
            const double rr = double(o.shell_radius);
            if (oc.x + rr < box_lo.x || oc.x - rr > box_hi.x || oc.y + rr < box_lo.y || oc.y - rr > box_hi.y) continue;
            box_hi.z = std::max(box_hi.z, oc.z + rr);
        }
        box_lo.z -= 0.02 * (box_hi.z - box_lo.z);
        box_hi.z += 0.02 * (box_hi.z - box_lo.z);
        // The map's own origin: the box's middle (in the world, double), so that the matrices the
        // shaders get hold small numbers for the objects shown.
        const glm::dvec3 middle = 0.5 * (box_lo + box_hi);
        fitted[std::size_t(layer)].origin = centre + glm::transpose(rotate) * middle;
        const glm::dvec3 half = 0.5 * (box_hi - box_lo);
        const double extent_half = std::max(half.x, half.y); // square texels
        // (Looking along -z: the near plane at distance -half.z, towards the light, the far at +half.z.)
        fitted[std::size_t(layer)].view_proj = glm::mat4(
            glm::orthoRH_ZO(-extent_half, extent_half, -extent_half, extent_half, -half.z, half.z) * light_axes);
        // A texel and a half off the triangle and nearer the light (depth 0..1 spans the map's
        // depth range), and at least 8 steps of the depth's floats near 1 (a view closing in on
        // part of a large scene makes the texels far finer than the depth); the largest of the maps'.
        const double layer_texel = 2.0 * extent_half / size;
        texel = std::max(texel, layer_texel);
        depth_bias = std::max(depth_bias, 1.5 * layer_texel / std::max(2.0 * half.z, 1e-30));
    }
    shadow_layers_ = std::move(fitted);
    shadow_bias_ = glm::vec2(float(1.5 * texel), std::max(float(depth_bias), 1e-6f));
    // The texels against the pixels they shade (a pixel's width at its point's view depth): the
    // map spans what the image shows, and a torus 1000 units off in view made a near one's
    // texels 30 of its pixels wide, and its bumps' shadows went (found by an exploratory session,
    // thirty-fourth; compare counted that as the techniques' error). Said, not mended: one map per
    // range of depth (cascades) would multiply the soft light's 16.
    {
        const glm::dvec3 eye = cam.eye - centre;
        const glm::dvec3 forward = glm::normalize(cam.target - cam.eye);
        const double per_depth = 2.0 * std::tan(glm::radians(double(cam.fovy_deg)) / 2.0) / double(height_);
        std::size_t coarse = 0;
        double widest = 0.0;
        for (const glm::dvec3& p : shown) {
            const double texels = texel / std::max(glm::dot(p - eye, forward) * per_depth, 1e-300);
            if (texels > 2.0) ++coarse, widest = std::max(widest, texels);
        }
        shadow_fit_ = {shown.empty() ? 0.0 : double(coarse) / double(shown.size()), widest};
    }

    glBindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_.id());
    glViewport(0, 0, size, size);
    glDepthFunc(GL_LESS);
    // The depth's slope on top of the look-up's bias: steep triangles seen edge-on from the light.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1.5f, 0.0f);
    for (int layer = 0; layer < layers; ++layer) {
        glNamedFramebufferTextureLayer(shadow_fbo_.id(), GL_DEPTH_ATTACHMENT, shadow_map_.id(), 0, layer);
        const GLfloat far_depth = 1.0f;
        glClearNamedFramebufferfv(shadow_fbo_.id(), GL_DEPTH, 0, &far_depth);
        shadow_layer_drawn_ = layer;
        draw_references(shadow_program_.id());
    }
    shadow_layer_drawn_ = 0;
    glDisable(GL_POLYGON_OFFSET_FILL);
    scissor.restore();
    shadow_light_ = light_dir;
    shadow_light_tan_ = light_tan;
    shadow_camera_ = frame_camera_;
    shadow_aspect_ = aspect;
}

void Renderer::use_reversed_depth()
{
    glClipControl(GL_LOWER_LEFT, GL_ZERO_TO_ONE);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_GREATER);
}

void Renderer::upload_frame(const Camera& camera, glm::vec3 light_dir, glm::vec2 pixel_offset, float light_size)
{
    frame_camera_ = camera;
    frame_light_ = light_dir;
    frame_light_tan_ = static_cast<float>(std::tan(glm::radians(0.5 * double(light_size))));
    frame_offset_ = pixel_offset;
    upload_frame_block(glm::dvec3(0.0));
    glBindBufferBase(GL_UNIFORM_BUFFER, PR_UBO_FRAME, frame_ubo_.id());
    glBindBufferBase(GL_UNIFORM_BUFFER, PR_UBO_OBJECT, object_ubo_.id());
}

void Renderer::upload_frame_block(const glm::dvec3& origin)
{
    const Camera& camera = frame_camera_;
    const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
    shader::FrameBlock frame{};
    frame.u_view = camera.view_from(origin);
    // Each pixel samples the scene at pixel_offset from its centre: the image shifted by the
    // opposite, in clip space 2 / size per pixel, after the projection (every shader reaches the
    // screen, and back, through u_view_proj). (Shifted by the offset itself, until the
    // thirty-ninth session, every pass sampled the standard position turned by 180 degrees: the
    // same for 2 and 4 samples, whose patterns are symmetric, not for 8 and 16: a pixel 97 %
    // covered by an edge read alpha 15/16; found by an exploratory session.)
    const glm::vec2 shift = -2.0f * frame_offset_ / glm::vec2(width_, height_);
    frame.u_proj = glm::translate(glm::mat4(1.0f), glm::vec3(shift, 0.0f)) * camera.projection(aspect);
    frame.u_view_proj = frame.u_proj * frame.u_view;
    frame.u_eye = glm::vec4(glm::vec3(glm::dvec3(camera.eye) - origin), 1.0f);
    frame.u_light_dir = glm::vec4(frame_light_, frame_light_tan_);
    frame.u_viewport = glm::vec4(width_, height_, 1.0f / width_, 1.0f / height_);
    glNamedBufferSubData(frame_ubo_.id(), 0, sizeof(frame), &frame);
}

void Renderer::check_drawable(const DrawSettings& settings, const std::string& option) const
{
    if (settings.technique != Technique::Prism) return;
    // The prism's exits multiply three world-space lengths of a prism (signed volumes, in
    // single precision): a shell about 10^14 units across overflows them, one about 10^-10
    // across underflows them, and either drew nothing at all (the torus at --depth 10^14, or
    // scaled by 3·10^13 or 10^-10). Refused, not drawn empty.
    // With several objects, which one (and its own scale: "scale the scene up" was wrong for one
    // tiny object beside others; found by an exploratory session, thirty-fifth).
    for (std::size_t k = 0; k < objects_.size(); ++k) {
        const GpuObject& o = objects_[k];
        const bool large = !(o.shell_radius <= kPrismMaxShellRadius);
        if (!large && o.shell_radius >= kPrismMinShellRadius) continue;
        const bool one = objects_.size() == 1;
        const std::string which = one ? "an object's" : "object " + std::to_string(k) + "'s";
        const std::string what = one ? "the scene" : "that object";
        char across[32];
        std::snprintf(across, sizeof across, "%.3g", 2.0 * double(o.shell_radius));
        throw Error(option, "prism: " + which + " displacement shell is " + across +
                                (large ? " scene units across, more than the prism's single-precision geometry "
                                         "takes (2e13): scale " + what + " down or use a smaller depth"
                                       : " scene units across, less than the prism's single-precision geometry "
                                         "takes (2e-9): scale " + what + " up"));
    }
}

namespace {

// How far a prism object's displaced surface reaches from its base mesh: the height range's
// furthest texel from the midlevel, times the depth (Renderer::draw's thin shells).
template <class Object>
double shell_reach(const Object& o)
{
    const double m = double(o.midlevel);
    const double surface = std::max(std::abs(double(o.height_low) - m), std::abs(double(o.height_high) - m));
    return std::min(double(displacement_reach(o.depth, o.midlevel)), double(o.depth) * surface);
}

// A shell the prism draws as its base mesh: its reach under a millionth of the object's size, too
// thin for single precision (or none at all).
template <class Object>
bool shell_under_precision(const Object& o)
{
    return shell_reach(o) <= 1e-6 * double(o.shell_radius);
}

} // namespace

bool Renderer::prism_shell_too_thin(std::size_t object) const
{
    if (object >= objects_.size()) return false;
    const GpuObject& o = objects_[object];
    return shell_reach(o) > 0.0 && shell_under_precision(o);
}

double Renderer::draw(const Camera& camera, glm::vec3 light_dir, const DrawSettings& settings)
{
    const bool walk = settings.prism_walk();
    const AuxMap aux_map = settings.aux_map();
    ensure_aux_textures(aux_map, marches_patches(settings));
    check_drawable(settings);
    if (settings.technique == Technique::Prism) ensure_prism_data(walk);
    // The exact and vertex exits shade an open sheet's bottoms as its back (prism.frag): whether
    // each mesh is open, learnt without the walk's data (the flag was set by a walk's draw only).
    if (settings.technique == Technique::Prism && !walk)
        for (GpuObject& o : objects_) closed_shell(o);
    // A base-surface technique writing its depth draws a closed mesh's front faces only where the
    // eye is outside its body and shell: the depth a grazing front fragment writes may lie behind
    // the object's own far faces, which then showed through (a cube at --depth 0.15: 478 of 3,521
    // pixels). The back faces stay for an eye inside (the mesh seen from within) and on open or
    // inconsistently wound meshes (no inside to tell): closed_shell(), learnt once per object,
    // before the frame's clock starts. (Outside the sphere around the shell, not by the parity of
    // crossings: an eye inside two nested parts of one mesh counted as outside, and everything
    // was culled.)
    // (Only the techniques whose depth the flag changes, reads_depth_write: it culled flat's,
    // normal's and offset's back faces too, which changed their fragment counts and a pixel or
    // two of z-fighting, while the command line called the flag of no effect there; found by a
    // review.)
    const bool depth_writing_base = settings.depth_write && reads_depth_write(settings);
    std::vector<char> cull_back(objects_.size(), 0);
    if (depth_writing_base)
        for (std::size_t k = 0; k < objects_.size(); ++k)
            cull_back[k] = glm::distance(camera.eye, objects_[k].shell_center) > double(objects_[k].shell_radius) &&
                           closed_shell(objects_[k]);
    upload_frame(camera, glm::normalize(light_dir), settings.pixel_offset, settings.light_size);
    // The reference's shadows: its shadow maps, drawn before the frame's clock (as the
    // reference's geometry is built before it).
    if (settings.technique == Technique::Reference && drawn_shadows(settings) != Shadows::None) {
        ensure_shadow_map(glm::normalize(light_dir), drawn_shadows(settings) == Shadows::Soft, frame_light_tan_);
        glBindTextureUnit(PR_TEX_SHADOW_MAP, shadow_map_.id());
        glBindTextureUnit(PR_TEX_SHADOW_DEPTH, shadow_depth_.id());
    }
    if (settings.count_samples) {
        const GLuint zero = 0;
        glClearNamedBufferData(counters_.id(), GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        if (counts_below_carry_ != 0) { // (tests of the carry)
            const std::uint32_t start = 0u - counts_below_carry_;
            glNamedBufferSubData(counters_.id(), 0, sizeof start, &start);
            for (int i = 0; i < kHistogramBins; ++i)
                glNamedBufferSubData(counters_.id(), GLintptr((kCounterWords + 2 * i) * sizeof start), sizeof start, &start);
        }
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PR_SSBO_COUNTERS, counters_.id());
    }
    // The base-surface programs the objects need (with a colour texture and without), built
    // before the frame's clock starts, as they were when one program served every object.
    if (!walk)
        for (const GpuObject& o : objects_) object_program(settings, o);

    glFinish();
    const auto start = std::chrono::steady_clock::now();
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width_, height_);
    use_reversed_depth();
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE); // open meshes are seen from both sides
    glDisable(GL_BLEND);
    const GLfloat clear_color[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    const GLfloat clear_depth = 0.0f; // the far plane's (Camera::projection)
    glClearNamedFramebufferfv(fbo_.id(), GL_COLOR, 0, clear_color);
    glClearNamedFramebufferfv(fbo_.id(), GL_DEPTH, 0, &clear_depth);
    const bool prism = settings.technique == Technique::Prism;
    // A shell of (nearly) no thickness (--depth 0): the displaced surface is the base mesh, which
    // the reference's program draws as the reference shades it (smooth welded normals; no bump,
    // no shadow at depth 0; the flat program's face normals were 21 dB away on the cube). Walked,
    // its prisms' faces all meet at one place and some rays were lost (the rock at depth 0: 13
    // pinholes at 256x192); the exact exit drew black (prism.frag: `thin`).
    // The same where the displaced surface itself lies on the base mesh, whatever the shell: a
    // height map that is midlevel everywhere (builtin:const:0 at midlevel 0), whose tight shell has
    // no thickness at any depth (the rock at depth 1e-3: 10 pinholes at 256x192, IoU 0.9987, and
    // at the default depth too; found by an exploratory session). The reach is the height range's
    // furthest texel from the midlevel.
    const auto flat_shell = [&](const GpuObject& o) { return prism && shell_under_precision(o); };
    // Said, once an upload, where a displacement was asked for and is lost so: one file of pieces
    // far apart has one frame, whose size sets the bound (two cubes 2 units wide, 2e5 apart, at
    // --depth 0.09: their bumps were drawn flat without a word; found by an exploratory session,
    // forty-seventh). docs/prism.md, "Known limits".
    for (GpuObject& o : objects_)
        if (flat_shell(o) && shell_reach(o) > 0.0 && !o.thin_shell_said) {
            o.thin_shell_said = true;
            char reach[32], radius[32];
            std::snprintf(reach, sizeof reach, "%.3g", shell_reach(o));
            std::snprintf(radius, sizeof radius, "%.3g", double(o.shell_radius));
            warn(o.name + ": its displacement reaches " + reach + ", under a millionth of its size (radius " + radius +
                 "): too thin a shell for the prism's single precision, so it draws the base mesh (a larger depth "
                 "helps, or, where a file's pieces lie far apart, an object of its own for each in a scene file)");
        }
    DrawSettings flat_settings = settings;
    flat_settings.technique = Technique::Reference;
    flat_settings.shadows = Shadows::None;
    flat_settings.depth_write = false;
    const auto set_object = [&](const GpuObject& o, const EyeInShell* eye = nullptr) {
        upload_object(o, settings, o.midlevel, eye);
        glBindTextureUnit(PR_TEX_HEIGHT, o.height_texture);
        // Without a colour texture the unit still needs a valid texture; it is not sampled.
        glBindTextureUnit(PR_TEX_COLOR, o.color_texture ? o.color_texture : o.height_texture);
        // Likewise the derived-map unit: the map this draw needs, else any texture.
        const GLuint aux = aux_map == AuxMap::None ? 0 : o.aux_texture[static_cast<int>(aux_map) - 1];
        glBindTextureUnit(PR_TEX_CONE, aux ? aux : o.height_texture);
        // The base-surface cone marchers' patches (make_patch_texture), unsampled by the other draws.
        if (marches_patches(settings)) glBindTextureUnit(PR_TEX_PATCH, o.patch_texture[static_cast<int>(aux_map) - 1]);
    };
    // Torn meshes (GpuObject::tears): the walk marks the pixels whose rays went into the object
    // through a tear; a second pass from the far side's bottoms shades those (prism.frag).
    // The eye inside an object's shell (find_eye_prism, item 12): looked for once per object.
    // Else, inside a closed object's body (eye_inside_body).
    std::vector<std::optional<EyeInShell>> eye_in(objects_.size());
    std::vector<char> in_body(objects_.size(), 0);
    if (walk)
        for (std::size_t k = 0; k < objects_.size(); ++k) {
            const GpuObject& o = objects_[k];
            if (flat_shell(o)) continue;
            const glm::vec3 eye = glm::vec3(glm::dvec3(camera.eye) - o.origin); // in the object's frame, as its corners
            eye_in[k] = find_eye_prism(o.shell_corners, o.triangles, o.eye_blocks, o.depth, settings.full_shell, eye,
                                       [&](glm::vec2 uv) { return o.height_field ? o.height_field->sample(uv) : 0.0f; });
            in_body[k] = !eye_in[k] && !o.open_shell && eye_inside_body(o.shell_corners, o.triangles, o.eye_blocks, eye);
        }
    // Objects whose walks may go into the object under the surface and need the second pass:
    // torn meshes, and a closed mesh with the eye under its surface (inside a bump), whose rays
    // into the body come out on its far side.
    const auto goes_inside = [&](std::size_t k) {
        return !flat_shell(objects_[k]) &&
               (objects_[k].tears || (eye_in[k] && eye_in[k]->under && !objects_[k].open_shell));
    };
    // (The images are set up for any walk from under the surface, which marks pixels: on an open
    // mesh there is no second pass for them, but the images are bound.)
    bool tears = false;
    for (std::size_t k = 0; walk && k < objects_.size(); ++k)
        tears = tears || (!flat_shell(objects_[k]) &&
                          (objects_[k].tears || (eye_in[k] && eye_in[k]->under))); // goes_inside(k), open meshes too
    if (tears) {
        if (!tear_mask_) {
            tear_mask_ = gl::Texture::create(GL_TEXTURE_2D);
            glTextureStorage2D(tear_mask_.id(), 1, GL_R32UI, width_, height_);
            tear_tiles_ = gl::Texture::create(GL_TEXTURE_2D);
            glTextureStorage2D(tear_tiles_.id(), 1, GL_R32UI, (width_ + PR_TEAR_TILE - 1) / PR_TEAR_TILE,
                               (height_ + PR_TEAR_TILE - 1) / PR_TEAR_TILE);
        }
        const GLuint zero = 0;
        glClearTexImage(tear_mask_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glClearTexImage(tear_tiles_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, &zero);
        glBindImageTexture(PR_IMAGE_TEARS, tear_mask_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
        glBindImageTexture(PR_IMAGE_TEAR_TILES, tear_tiles_.id(), 0, GL_FALSE, 0, GL_READ_WRITE, GL_R32UI);
    }
    // The base mesh of `o` with the bound program; the prism rebuilds its prisms from the mesh
    // buffers (prism.frag).
    const auto draw_base = [&](const GpuObject& o) {
        set_object(o);
        if (prism) bind_prism_data(o, false);
        glBindVertexArray(o.base.vao.id());
        glDrawElements(GL_TRIANGLES, o.base.index_count, GL_UNSIGNED_INT, nullptr);
    };
    // Caps of the walk's shell by the vertex shader, culled by the rasterizer (base triangles wind
    // counter-clockwise seen along +N): the tops facing the eye, or the bottoms seen from below
    // (the same triangles' back faces). The object and its prism data are bound.
    const auto draw_caps = [&](const GpuObject& o, WalkVariant variant, ShellDraw caps) {
        const Geometry& shell = walk_geometry(o);
        glBindVertexArray(shell.vao.id());
        glEnable(GL_CULL_FACE);
        glFrontFace(GL_CCW);
        glCullFace(caps == ShellDraw::Tops ? GL_BACK : GL_FRONT);
        glUseProgram(object_program(settings, o, variant, caps));
        glDrawElements(GL_TRIANGLES, shell.index_count, GL_UNSIGNED_INT, nullptr);
        glDisable(GL_CULL_FACE);
    };
    // The walk: the top caps, on open meshes the bottom caps too (the sheet seen from below: the
    // walk starts under the surface and meets its back), then the other front faces of the
    // listed prisms (ShellDraw) — not with the eye inside the body: those of prisms folded where
    // the bottom caps fold (an inward shell at sharp edges) face it from inside and would start
    // walks as from outside (lit shards along the rock's seams at midlevel 1, PSNR 23 dB).
    const auto draw_walk_shell = [&](const GpuObject& o, WalkVariant variant, bool eye_in_body) {
        set_object(o);
        bind_prism_data(o, true);
        draw_caps(o, variant, ShellDraw::Tops);
        if (o.open_shell) draw_caps(o, WalkVariant::UnderSurface, ShellDraw::Bottoms);
        const int full = settings.full_shell ? 1 : 0;
        if (o.listed_count[full] > 0 && !eye_in_body) {
            // (On an open mesh a ray may come in through a wall under the surface: OpenEntry.)
            glUseProgram(object_program(settings, o, o.open_shell ? WalkVariant::OpenEntry : variant, ShellDraw::Listed));
            glBindTextureUnit(PR_TEX_PRISM_LIST, o.listed_texels[full].id());
            glDrawArrays(GL_POINTS, 0, o.listed_count[full]);
        }
    };
    // The eye inside a closed object's body, under its shell: every cap faces away. The bottom
    // caps seen from inside start each ray's walk under the surface, which it meets from below,
    // as the second pass through tears does (docs/prism.md, item 12).
    const auto draw_from_body = [&](const GpuObject& o) {
        set_object(o);
        bind_prism_data(o, true);
        draw_caps(o, WalkVariant::UnderSurface, ShellDraw::Bottoms);
    };
    // The eye inside an object's shell (a close-up): the caps around it face away, so no cap
    // starts the walk of the rays that begin there. A screen-filling triangle at the near plane
    // starts them at the eye, in the prism that holds it (docs/prism.md, item 12); an eye in no
    // prism but inside the body walks from the bottoms.
    const auto draw_from_eye = [&](const GpuObject& o, const std::optional<EyeInShell>& in, bool eye_in_body,
                                   WalkVariant variant) {
        if (!in) {
            if (eye_in_body) draw_from_body(o);
            return;
        }
        set_object(o, &*in);
        bind_prism_data(o, true);
        // Under the surface (inside a bump) the walk starts under it, as through a tear.
        glUseProgram(object_program(settings, o, in->under ? WalkVariant::UnderSurface : variant, ShellDraw::FromEye));
        glBindVertexArray(o.base.vao.id()); // (no attributes read)
        glDrawArrays(GL_TRIANGLES, 0, 3);
    };
    for (std::size_t k = 0; k < objects_.size(); ++k) {
        const GpuObject& o = objects_[k];
        if (flat_shell(o)) {
            glUseProgram(object_program(flat_settings, o));
            set_object(o);
            glBindVertexArray(o.base.vao.id());
            glDrawElements(GL_TRIANGLES, o.base.index_count, GL_UNSIGNED_INT, nullptr);
            continue;
        }
        if (walk) {
            const WalkVariant variant =
                o.tears ? WalkVariant::Through : (o.seamless ? WalkVariant::Seamless : WalkVariant::Plain);
            draw_walk_shell(o, variant, in_body[k]);
            draw_from_eye(o, eye_in[k], in_body[k], variant);
            continue;
        }
        glUseProgram(object_program(settings, o));
        if (settings.technique != Technique::Reference) {
            if (cull_back[k]) {
                glEnable(GL_CULL_FACE);
                glFrontFace(GL_CCW);
                glCullFace(GL_BACK);
            }
            draw_base(o);
            glDisable(GL_CULL_FACE);
            continue;
        }
        if (o.reference.empty()) throw Error("reference", "prepare_reference() was not called");
        set_object(o);
        for (const Geometry& g : o.reference) {
            glBindVertexArray(g.vao.id());
            glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
        }
    }
    // The second pass (TearPass): on a GPU over every prism's bottom; on llvmpipe only where the
    // first marked a tile (below). Both draw `o`'s prisms listed in `list` (PR_TEX_PRISM_LIST),
    // one point each, after this.
    const auto begin_second_pass = [&](const GpuObject& o, const gl::Texture& list) {
        set_object(o);
        bind_prism_data(o, true);
        glUseProgram(object_program(settings, o, WalkVariant::Inside, ShellDraw::Listed));
        glBindTextureUnit(PR_TEX_PRISM_LIST, list.id());
        glBindVertexArray(o.base.vao.id());
    };
    if (tears && tear_pass_ == TearPass::Whole) {
        // Every prism's bottom, each fragment discarding at once where the first pass marked
        // nothing (TearPass): nothing is read back, so the GPU never waits for the CPU.
        glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        for (std::size_t k = 0; k < objects_.size(); ++k) {
            GpuObject& o = objects_[k];
            if (!goes_inside(k)) continue;
            const GLsizei prisms = GLsizei(o.triangles.size() / 3);
            if (!o.every_prism_texels) {
                std::vector<std::uint32_t> every(std::size_t(prisms), 0);
                std::iota(every.begin(), every.end(), 0u);
                o.every_prism = gl::immutable_buffer(every);
                o.every_prism_texels = buffer_texture(o.every_prism, GL_R32UI, 4, texture_buffer_limit_);
            }
            begin_second_pass(o, o.every_prism_texels);
            glDrawArrays(GL_POINTS, 0, prisms);
        }
    } else if (tears) {
        // The marked tiles come back (a small read-back), and the CPU lists the prisms whose
        // bottoms may cover one (none when nothing is marked); a geometry-shader pass over every
        // triangle cost llvmpipe more.
        glMemoryBarrier(GL_TEXTURE_UPDATE_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
        const int tw = (width_ + PR_TEAR_TILE - 1) / PR_TEAR_TILE, th = (height_ + PR_TEAR_TILE - 1) / PR_TEAR_TILE;
        std::vector<GLuint> tiles(std::size_t(tw) * std::size_t(th));
        glGetTextureImage(tear_tiles_.id(), 0, GL_RED_INTEGER, GL_UNSIGNED_INT, GLsizei(tiles.size() * sizeof(GLuint)),
                          tiles.data());
        if (std::any_of(tiles.begin(), tiles.end(), [](GLuint t) { return t != 0; })) {
            // A caller's scissor (the viewer's split view draws each half in its own columns)
            // bounds the tiles below and is set back after each object's.
            const ScissorState outer = ScissorState::current();
            for (std::size_t k = 0; k < objects_.size(); ++k) {
                const GpuObject& o = objects_[k];
                if (!goes_inside(k)) continue;
                // (The corners are in the object's frame.)
                const glm::mat4 view_proj = camera.projection(float(width_) / float(height_)) * camera.view_from(o.origin);
                const TileLists lists = prisms_over_marked_tiles(o.shell_corners, o.triangles, view_proj,
                                                                 glm::vec2(width_, height_), tiles, tw, th);
                if (lists.prisms.empty()) continue;
                if (!pass_list_) {
                    pass_list_ = gl::Buffer::create();
                    pass_list_texels_ = gl::Texture::create(GL_TEXTURE_BUFFER);
                }
                glNamedBufferData(pass_list_.id(), GLsizeiptr(lists.prisms.size() * sizeof(std::uint32_t)),
                                  lists.prisms.data(), GL_STREAM_DRAW);
                glTextureBuffer(pass_list_texels_.id(), GL_R32UI, pass_list_.id());
                begin_second_pass(o, pass_list_texels_);
                // Each marked tile's prisms with the tile as scissor: only its pixels are shaded
                // (llvmpipe runs the whole shader even for fragments that discard at once).
                glEnable(GL_SCISSOR_TEST);
                for (std::size_t m = 0; m < lists.marked.size(); ++m) {
                    const GLsizei count = GLsizei(lists.offsets[m + 1] - lists.offsets[m]);
                    if (count == 0) continue;
                    const int x = int(lists.marked[m] % std::uint32_t(tw)), y = int(lists.marked[m] / std::uint32_t(tw));
                    const std::array<GLint, 4> tile =
                        outer.clip({x * PR_TEAR_TILE, y * PR_TEAR_TILE, PR_TEAR_TILE, PR_TEAR_TILE});
                    if (tile[2] <= 0 || tile[3] <= 0) continue;
                    glScissor(tile[0], tile[1], tile[2], tile[3]);
                    glDrawArrays(GL_POINTS, GLint(lists.offsets[m]), count);
                }
                outer.restore();
            }
        }
    }
    glFinish();
    const auto end = std::chrono::steady_clock::now();
    glBindVertexArray(0);
    glUseProgram(0);
    if (const GLenum err = glGetError(); err != GL_NO_ERROR) {
        throw Error("render", err == GL_OUT_OF_MEMORY ? "out of GPU memory"
                                                      : "OpenGL error " + std::to_string(err));
    }
    return std::chrono::duration<double, std::milli>(end - start).count();
}

RgbaImage read_texture_rgba8(GLuint texture, int width, int height)
{
    RgbaImage img;
    img.width = width;
    img.height = height;
    img.pixels.resize(std::size_t(width) * std::size_t(height) * 4);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glGetTextureImage(texture, 0, GL_RGBA, GL_UNSIGNED_BYTE, static_cast<GLsizei>(img.pixels.size()),
                      img.pixels.data());
    return img;
}

RgbaImage Renderer::read_color() const
{
    return read_texture_rgba8(color_target_.id(), width_, height_);
}

std::vector<float> Renderer::read_depth() const
{
    std::vector<float> depth(std::size_t(width_) * height_);
    glGetTextureImage(depth_target_.id(), 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                      static_cast<GLsizei>(depth.size() * sizeof(float)), depth.data());
    return depth;
}

SampleCounters Renderer::read_counters() const
{
    // (counters.glsl: fragments' low word, the low word of the samples past the exact bins, the
    // walk's prisms in two words, the most of one fragment, that sum's high word, fragments' high
    // word, the histogram in two words a bin.)
    std::vector<std::uint32_t> raw(kCounterWords + 2 * kHistogramBins);
    glGetNamedBufferSubData(counters_.id(), 0, static_cast<GLsizeiptr>(raw.size() * sizeof(std::uint32_t)),
                            raw.data());
    SampleCounters c;
    const auto words = [](std::uint32_t low, std::uint32_t high) { return std::uint64_t(low) | std::uint64_t(high) << 32; };
    c.fragments = words(raw[0], raw[6]);
    c.prisms = words(raw[2], raw[3]);
    c.prisms_most = raw[4];
    c.histogram.resize(kHistogramBins);
    for (int i = 0; i < kHistogramBins; ++i)
        c.histogram[std::size_t(i)] = words(raw[std::size_t(kCounterWords + 2 * i)], raw[std::size_t(kCounterWords + 2 * i + 1)]);
    // The total in 64 bits from the exact bins; the fragments past them were summed apart (in two
    // words: one wrapped past 4.3 G samples, about 524,000 fragments of 8,191 samples or more;
    // found by an exploratory session, thirty-second).
    c.samples = words(raw[1], raw[5]);
    for (std::size_t i = 0; i < std::size_t(kExactSampleBins); ++i) c.samples += std::uint64_t(i) * c.histogram[i];
    return c;
}

} // namespace pr
