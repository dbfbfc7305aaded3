#pragma once
// Cone maps (contract "Cone maps"): for every texel p of a height field, the widest cone with its
// apex at p's height, opening upward, that holds no higher texel (kind cone: conservative at texel
// centres), or the relaxed cone of Policarpo & Oliveira (kind relaxed: not conservative; marchers
// finish with a binary search). The ratio stored is sqrt(c), c = horizontal distance in UV units
// over height rise, capped at 1, distances wrapping (maps tile).
#include "core/image.hpp"

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pr {

enum class ConeKind { Cone, Relaxed };
enum class ConeFormat { Rg8, Rg16 };

ConeKind parse_cone_kind(const std::string& name, const std::string& option = "--kind");
std::string cone_kind_name(ConeKind kind);       // "cone" | "relaxed"
ConeFormat parse_cone_format(const std::string& name, const std::string& option = "--format");
std::string cone_format_name(ConeFormat format); // "rg8" | "rg16"
// What a progress line calls the map of `kind` for `field`: "relaxed cone map of builtin:noise@1024".
std::string cone_map_label(ConeKind kind, const HeightField& field);
// Where a cone map is built: "cpu" (threads) -> false, "gpu" (compute shader) -> true.
bool parse_cone_backend_gpu(const std::string& name, const std::string& option);

// Full-precision cone map, bottom row first like every image in prismrelief.
struct ConeMap {
    int width = 0;
    int height = 0;
    ConeKind kind = ConeKind::Cone;
    std::vector<float> heights; // the heights it was built from and stores (cone_source_field)
    std::vector<float> ratios;  // sqrt(c) in [0,1]; already rounded *down* to the stored format
};

struct ConeBuildOptions {
    int threads = 0; // 0: std::thread::hardware_concurrency()
    // Ratios are rounded down to this format's steps, and rg8 maps are built from the heights
    // rounded to 8 bits, as they store them (cone_source_field).
    ConeFormat format = ConeFormat::Rg16;
    // Called now and then with the fraction done (0..1), from the calling thread.
    std::function<void(double)> progress;
    // When set and it turns true, the CPU's threads stop at their next span (the GPU generator
    // before its next dispatch) and the build throws ConeBuildCancelled (the viewer's background builds, when the scene changes or
    // the window closes). Nothing is cached then.
    const std::atomic<bool>* cancel = nullptr;
    // Kind relaxed: march steps per texel (see docs/cone-maps.md). Where the search needs more, the
    // rest of it is replaced by lower bounds, giving a narrower (still valid) relaxed cone, never
    // narrower than the conservative cone. 0: unbounded (exact relaxed cones; slow on large maps).
    // 2048 since the thirty-first session (256 before): wider cones on maps of plateaus, where a
    // ray marches across a whole box top per candidate (builtin:boxes, relaxed-cone: 0.345 of
    // relief's samples per fragment with 256, 0.324 with 2048), at 2-5x the build time
    // (docs/cone-maps.md, "The relaxed march budget").
    int relaxed_budget = 2048;
    // Quadtree nodes one texel's search may visit (both kinds). Where a search needs more (maps on
    // which many far texels limit the cone almost equally, like a long ramp), the nodes left count
    // by their lower bounds: a narrower cone, still conservative. No built-in map comes near it.
    // 0: unbounded (the exact rounded minimum everywhere).
    int node_budget = 1024;
    // Where node_budget runs out, the nodes left go on best first (smallest bound first) for at
    // most this many more, and only then count by their bounds (docs/cone-maps.md, "The search").
    // The GPU generator searches depth first only and hands such texels to the CPU's threads
    // (cone_steps_of_texels), so both give the same map. 0: none.
    int best_first_budget = 1024;
    // GPU generator only: read the max pyramid from storage buffers, as it does by itself where the
    // pyramid has more texels than GL_MAX_TEXTURE_BUFFER_SIZE, instead of from buffer textures
    // (faster on llvmpipe). The same map either way; tests use it to cover that path.
    bool gpu_storage_buffers = false;
    // GPU generator only: how many searches that ran out of nodes one dispatch hands to the CPU
    // with their state (the CPU goes on from there); beyond that, the CPU searches their texels
    // again from the start (the same map, slower). 0: the default, 32768. Tests set it low.
    int gpu_resume_capacity = 0;
    // GPU generator only: where it finds the seeds (ConeSeeds). Auto: on the CPU's threads where
    // the OpenGL renderer is software (llvmpipe: the seeds, far apart, are searched faster there,
    // docs/cone-maps.md "Seeds"), else in the compute shader. The same seeds either way; tests
    // pick each.
    enum class SeedPass { Auto, Cpu, Gpu } gpu_seed_pass = SeedPass::Auto;
};

// The CPU generator's threads take spans of at most kConeSpan texels of a row, one at a time: a
// map of a few long rows (16384 x 1) ran on one thread when a row was the unit (found by an
// exploratory session, forty-sixth). cone_cpu_items: how many spans a width x height map has.
constexpr int kConeSpan = 256;
int cone_cpu_items(int width, int height);

// The threads the CPU generator runs for `items` items (build_cone_map_cpu: cone_cpu_items):
// options.threads, or the machine's with 0, at least 1 and at most one per item.
unsigned cone_cpu_threads(const ConeBuildOptions& options, int items);

// Thrown by build_cone_map_cpu() and build_cone_map_gpu() when ConeBuildOptions::cancel turned true.
class ConeBuildCancelled : public std::runtime_error {
public:
    ConeBuildCancelled() : std::runtime_error("cone-map build cancelled") {}
};

// Multi-threaded CPU generator: spans of rows (kConeSpan) on
// cone_cpu_threads(options, cone_cpu_items(field.width, field.height)) threads.
ConeMap build_cone_map_cpu(const HeightField& field, ConeKind kind, const ConeBuildOptions& options = {});

// Writes R = height, G = ratio as a 2-channel PNG (8 or 16 bits), atomically. Throws pr::Error.
void write_cone_png(const std::filesystem::path& path, const ConeMap& map, ConeFormat format);
// The bytes write_cone_png() writes (errors name `path`), for a caller that stages its outputs.
std::vector<std::uint8_t> encode_cone_png(const std::filesystem::path& path, const ConeMap& map, ConeFormat format);
// Reads a cone map PNG written by write_cone_png. Throws pr::Error naming the file.
ConeMap read_cone_png(const std::filesystem::path& path, ConeKind kind);

// ---- generator details shared by the CPU and GPU paths (docs/cone-maps.md) ----

// Bumped whenever the generator's output changes: part of every cache key. (3: rg8 maps are
// built from their 8-bit heights; 4: rises in the stored height steps, exactly; 5: the search
// goes on best first where the node budget runs out; 6: a relaxed constraint's exit is the
// ray's last step still in the surface; 7: and the level ray through q counts as well; 8: cone
// searches start from seeds, ConeSeeds: the same maps but where a node budget runs out.)
inline constexpr std::uint32_t kConeGeneratorVersion = 8;

// 255 (rg8) or 65535 (rg16): the ratio is stored as k / steps, k an integer.
int cone_format_steps(ConeFormat format);
// The step k a height is stored as (the PNG's R channel): h clamped to [0,1], times steps, rounded
// to nearest. It reads back as float(k) / float(steps).
std::uint32_t cone_height_steps(float h, ConeFormat format);
// The field a map of `format` is built from, and whose heights it holds: a map must be
// conservative against the heights it stores, which a marcher or a reader of the PNG sees. rg16:
// the field itself (every height field has at most 16 bits: 8- or 16-bit images, built-in maps
// quantized to 16 bits). rg8: the field's heights as the R channel stores them (8-bit rounding can
// swap two close heights or bring them closer, which narrows cones), in `storage`; 8-bit fields
// come out bit for bit as they are. Both generators start from it, so they stay equal.
const HeightField& cone_source_field(const HeightField& field, ConeFormat format, HeightField& storage);
// The largest k in [0, steps] with k^2 / steps^2 <= c * (1 - 2^-20): sqrt(c) rounded *down* to the
// format's step, with a relative margin of about 1e-6 on c so that the rounded ratio stays
// conservative under float rounding of k / steps. c is capped at 1.
int cone_ratio_steps(double c, ConeFormat format);
// k / steps as the largest float not above the exact quotient.
float cone_steps_to_ratio(int k, ConeFormat format);
// The other way: the step k a stored ratio stands for (the PNG's G channel), r clamped to [0,1].
std::uint32_t cone_ratio_to_steps(float ratio, ConeFormat format);
// cone_steps_to_ratio(k, format) for every k in [0, steps], built once per process: whole maps
// (the GPU builder's steps, a cache entry, a PNG) convert through it, a lookup per texel instead
// of a division and a check (a 1024² cache read: 89 -> 85 ms).
const std::vector<float>& cone_ratio_table(ConeFormat format);

// The ratios a marcher samples with bilinear filtering: each texel's ratio narrowed to the
// smallest in its 3x3 neighbourhood (wrapping), so that the filtered ratio anywhere in a bilinear
// patch is no wider than the narrowest of the patch's four corners. A map's ratio holds at its
// texel centre; interpolated between a low texel beside a wall (narrow) and the wall's top (wide),
// it let grazing rays jump over the corners of boxes (docs/cone-maps.md, "The marchers").
// `ratios` is row-major, width x height.
std::vector<float> ratios_for_bilinear(const std::vector<float>& ratios, int width, int height);

// A quadtree of maxima over the height texels: level 0 is the texels, level l+1 node (i, j) is the
// maximum of level l nodes (2i..2i+1, 2j..2j+1) that exist; the last level is 1x1. Node (i, j) of
// level l covers texels [i*2^l, min((i+1)*2^l, n)) on each axis.
struct MaxPyramid {
    std::vector<int> widths, heights;  // per level
    std::vector<std::size_t> offsets;  // per level, into `data`
    std::vector<float> data;           // all levels, row-major, bottom row first
    int levels() const { return int(widths.size()); }
    float at(int level, int i, int j) const
    {
        return data[offsets[std::size_t(level)] + std::size_t(j) * std::size_t(widths[std::size_t(level)]) + std::size_t(i)];
    }
};
MaxPyramid build_max_pyramid(const HeightField& field);

// Where the cone searches start (docs/cone-maps.md, "Seeds"): the texels on a grid of every
// kConeSeedSpacing-th column and row are searched first, each from nothing, and each keeps the
// texel whose constraint set its cone (depth first; where the node budget runs out, the best
// found by then). Every texel's cone search then starts from the least constraint of the seeds
// of the four grid texels around it, so that most of its search only proves that nothing lies
// nearer: a threshold from the start prunes what the search would otherwise visit before it
// finds its cone. The seeds of every fourth column and row of the grid are searched from nothing,
// the others start from those (the coarse seeds) in the same way. Relaxed maps have relaxed seeds
// as well, for their relaxed searches (the texel whose relaxed constraint set the relaxed cone),
// found and used alike. Both generators compute the same seeds and start from them alike.
inline constexpr int kSeedShift = 2, kCoarseSeedShift = 4;
inline constexpr int kConeSeedSpacing = 1 << kSeedShift;
inline constexpr std::uint32_t kNoConeSeed = 0xffffffffu; // no texel is higher
struct ConeSeeds {
    int width = 0, height = 0;          // the grid: the field's size over kConeSeedSpacing, rounded up
    std::vector<std::uint32_t> texels;  // per grid texel, row-major: a texel (y * width + x) or kNoConeSeed
    std::vector<std::uint32_t> relaxed; // kind relaxed: the same for the relaxed searches (else empty)
};
// The seeds' grid for `field` and a map of `kind`, every seed kNoConeSeed (`relaxed` empty for
// kind cone).
ConeSeeds cone_seed_grid(const HeightField& field, ConeKind kind);
// The seeds' share of a build's progress: they are a sixteenth of the searches.
inline constexpr double kConeSeedProgress = 1.0 / double(kConeSeedSpacing * kConeSeedSpacing + 1);
// Where one pass of the seeds' searches starts in their progress (0..1), and its share of it: the
// cone seeds, then kind relaxed's relaxed seeds; of each, the coarse seeds, then the others. By the
// searches' count, a relaxed one as four cone ones. Both generators report their passes so.
std::pair<double, double> cone_seed_pass_progress(ConeKind kind, bool relaxed_seeds, bool coarse);
// The seeds of `field` (cone_source_field()'s) for a map of `kind` on options.threads threads;
// options.progress gets the fraction of them done.
ConeSeeds cone_seeds_cpu(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                         const ConeBuildOptions& options);

// Where the GPU generator's depth-first search of one texel stopped because its node budget ran
// out (shaders/conemap.comp, save_search): enough to go on from there on the CPU.
struct ConeSearchState {
    std::uint32_t texel = 0;   // y * width + x
    bool relaxed = false;      // the relaxed search (else the cone search)
    std::uint32_t filled = 0;  // bit l: lists[l] holds nodes left to visit
    int last_level = 0, last_i = 0, last_j = 0; // the node visited last
    double best = 1.0;         // the smallest constraint found
    int march_budget = 0;      // relaxed: march steps left
    // Per level l: the children of the node visited last at level l + 1 still to visit, in order
    // (3 bits count, then 2 bits per child: x + 2 y in its parent, the next one lowest).
    std::uint32_t lists[16] = {};
};

// The CPU generator's ratio, in format steps, of each search listed, each going on from where
// the GPU stopped it (best first, as the CPU's own search does there): k[i] for states[i].
void cone_steps_resumed(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                        const ConeBuildOptions& options, const ConeSeeds& seeds,
                        const std::vector<ConeSearchState>& states, std::vector<std::uint32_t>& k);

// The CPU generator's ratio, in format steps, of each texel listed (y * width + x), written to
// steps[texel]; `field` is cone_source_field()'s, `pyramid` its max pyramid. On options.threads
// threads; options.progress is not called. For the GPU generator's texels whose search ran out of
// nodes there.
void cone_steps_of_texels(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind,
                          const ConeBuildOptions& options, const ConeSeeds& seeds,
                          const std::vector<std::uint32_t>& texels, std::vector<std::uint32_t>& steps);

// The relaxed-cone constraint of texel q on texel p (kind relaxed, see docs/cone-maps.md): the
// least over two rays through q's surface point, the one from p's column at height 1 and the
// level one at h_q, each continued past q in steps of one texel on bilinear heights until it
// leaves the surface after its last step in it, E, of |E - p| / (h_E - h_p) in UV units; q's own
// cone constraint `at_q` (as the caller computes it: the exact ratio of the stored heights) where
// the first step past q is already out. A ray with no exit above h_p sets none; +infinity when
// neither does, or when the marches pass the value `stop` (no smaller result can follow). (dx, dy)
// is the wrapped texel offset from p to q. Within a budget of march steps (decremented): when it
// runs out before the marches end, returns a lower bound of the constraint (the least value
// known, else `at_q`).
double relaxed_constraint(const HeightField& field, int px, int py, int dx, int dy, double stop, int& budget,
                          double at_q);

// Derived-map cache (contract: --cache-dir, default $XDG_CACHE_HOME/prismrelief, else
// ~/.cache/prismrelief, each only when absolute). Entries are keyed by a hash of the height texels,
// size, kind, format and the generator version; they are validated when read (a corrupt entry is
// rebuilt, never trusted) and written atomically. A cache that cannot be written only warns. An
// empty cache_dir is no cache: maps are built, nothing is read or written (default_cache_dir()
// returns it, with one warning, when neither variable is an absolute path).
// `warn_if_none`: false to ask where the cache would be without saying there is none.
std::filesystem::path default_cache_dir(bool warn_if_none = true);
// Refuses an output in the cache's entries' folder (DIR/cone), which the cache's files fill, and
// one that is the cache's folder, the entries' folder or a folder on the way to them, and is not
// a file yet, before the work: the cache creates them, and the output check, which found no file
// there, passed, so the run built the map, filled the cache and only then failed ("cz: is a
// folder"). `outputs` pair an option with its path (empty paths skipped);
// `cache_dir_flag` is --cache-dir's value, empty for the default place (default_cache_dir()).
// Callers with --no-cache do not ask. Throws pr::Error naming the output.
void check_outputs_outside_cache(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs,
                                 const std::filesystem::path& cache_dir_flag);
// Refuses --no-cache next to --cache-dir (every command that takes both). Throws pr::Error.
void check_cache_flags(bool no_cache, const std::string& cache_dir_flag);
struct ConeCacheResult {
    ConeMap map;
    bool from_cache = false;
    std::filesystem::path entry; // the cache file; empty without a cache or where it could not be written
};
ConeCacheResult cached_cone_map(const HeightField& field, ConeKind kind, const std::filesystem::path& cache_dir,
                                const ConeBuildOptions& options = {});
// The same with another generator (the GPU's) called on a miss; its map must equal the CPU's.
using ConeBuilder = std::function<ConeMap(const HeightField&, ConeKind, const ConeBuildOptions&)>;
ConeCacheResult cached_cone_map(const HeightField& field, ConeKind kind, const std::filesystem::path& cache_dir,
                                const ConeBuildOptions& options, const ConeBuilder& build);
// The map's cache entry alone, read and checked as cached_cone_map reads it, without a word:
// nothing where there is no cache, no entry, or one that cannot be read or is wrong (which
// cached_cone_map then rebuilds, saying why). The viewer reads entries so in the frame and has the
// rest built on its thread.
std::optional<ConeMap> read_cached_cone_map(const HeightField& field, ConeKind kind,
                                            const std::filesystem::path& cache_dir,
                                            const ConeBuildOptions& options = {});
// The cache's bound: PRISMRELIEF_CACHE_MAX_MB (MiB; 0: none) if set and valid, else 2048 MiB
// (a relaxed rg16 entry of 1024² takes 6 MiB, of 4096² 96 MiB).
std::uint64_t cone_cache_max_bytes();
// Removes the least recently used entries of cache_dir/cone (by modification time: written, or
// read by cached_cone_map) until the rest take at most max_bytes, never `keep` nor any file that is
// not an entry, and the temporaries of entries (.<entry>.tmpNNNNNN) an hour old, which a SIGKILL
// or a crash left; returns how many entries it removed. cached_cone_map() calls it after each write.
std::size_t trim_cone_cache(const std::filesystem::path& cache_dir, std::uint64_t max_bytes,
                            const std::filesystem::path& keep = {});
// The entry file a map would have (cache_dir/cone/<kind>-<format>-<W>x<H>-<key>.bin).
std::filesystem::path cone_cache_entry(const HeightField& field, ConeKind kind, const ConeBuildOptions& options,
                                       const std::filesystem::path& cache_dir);

} // namespace pr
