#pragma once
// Cone maps (contract "Cone maps"): for every texel p of a height field, the widest cone with its
// apex at p's height, opening upward, that holds no higher texel (kind cone: conservative at texel
// centres), or the relaxed cone of Policarpo & Oliveira (kind relaxed: not conservative; marchers
// finish with a binary search). The ratio stored is sqrt(c), c = horizontal distance in UV units
// over height rise, capped at 1, distances wrapping (maps tile).
#include "core/image.hpp"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace pr {

enum class ConeKind { Cone, Relaxed };
enum class ConeFormat { Rg8, Rg16 };

ConeKind parse_cone_kind(const std::string& name, const std::string& option = "--kind");
std::string cone_kind_name(ConeKind kind);       // "cone" | "relaxed"
ConeFormat parse_cone_format(const std::string& name, const std::string& option = "--format");
std::string cone_format_name(ConeFormat format); // "rg8" | "rg16"

// Full-precision cone map, bottom row first like every image in prismrelief.
struct ConeMap {
    int width = 0;
    int height = 0;
    ConeKind kind = ConeKind::Cone;
    std::vector<float> heights; // the height field's texels, unchanged
    std::vector<float> ratios;  // sqrt(c) in [0,1]; already rounded *down* to the stored format
};

struct ConeBuildOptions {
    int threads = 0; // 0: std::thread::hardware_concurrency()
    ConeFormat format = ConeFormat::Rg16; // ratios are rounded down to this format's steps
    // Called now and then with the fraction done (0..1), from the calling thread.
    std::function<void(double)> progress;
};

// Multi-threaded CPU generator.
ConeMap build_cone_map_cpu(const HeightField& field, ConeKind kind, const ConeBuildOptions& options = {});

// Writes R = height, G = ratio as a 2-channel PNG (8 or 16 bits), atomically. Throws pr::Error.
void write_cone_png(const std::filesystem::path& path, const ConeMap& map, ConeFormat format);
// Reads a cone map PNG written by write_cone_png. Throws pr::Error naming the file.
ConeMap read_cone_png(const std::filesystem::path& path, ConeKind kind);

// Derived-map cache (contract: --cache-dir, default $XDG_CACHE_HOME/prismrelief, else
// ~/.cache/prismrelief). Entries are keyed by a hash of the height texels, size, kind, format and
// the generator version; they are validated when read (a corrupt entry is rebuilt, never trusted)
// and written atomically. A cache that cannot be written only warns.
std::filesystem::path default_cache_dir();
struct ConeCacheResult {
    ConeMap map;
    bool from_cache = false;
    std::filesystem::path entry; // the cache file (may not exist when the cache is unwritable)
};
ConeCacheResult cached_cone_map(const HeightField& field, ConeKind kind, const std::filesystem::path& cache_dir,
                                const ConeBuildOptions& options = {});

} // namespace pr
