// The on-disk cache of cone maps (docs/cone-maps.md, "Cache").
//
// Entry: cache_dir/cone/<kind>-<format>-<W>x<H>-<key>.bin, key = FNV-1a 64 of (generator version,
// kind, format, the generator's three budgets, width, height, the height texels' float bits).
// Layout, little endian:
//   magic "PRCONE01" | u32 version, kind, format, width, height | u64 key | u64 payload FNV-1a |
//   payload: width*height float32 heights, then width*height u16 ratio steps k (ratio = k/steps).
// Every field is checked when read, and the stored heights must equal those the map is built from
// (cone_source_field: rg8 rounds them to 8 bits), so a hash collision cannot serve another map.
// The key hashes the field's own texels: fields that differ only below 8 bits get separate (equal)
// rg8 entries. A bad entry is rebuilt and overwritten with a warning saying why; a cache that
// cannot be written only warns. The cache is bounded: a hit marks its entry used (its
// modification time), and after each write the least recently used entries go until the rest
// fits in cone_cache_max_bytes(); a trim also removes temporaries more than an hour old (left by a
// SIGKILL or a crash: a signal that can be caught removes its own). An empty cache_dir means no
// cache (default_cache_dir() found no place for one): maps are built and kept nowhere.
#include "maps/conemap.hpp"

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/file_kind.hpp"
#include "core/fnv.hpp"
#include "core/input_file.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <regex>
#include <string_view>

namespace pr {
namespace {

constexpr char kMagic[8] = {'P', 'R', 'C', 'O', 'N', 'E', '0', '1'};
constexpr std::size_t kHeaderBytes = 8 + 5 * 4 + 8 + 8;

// The budgets change the map where they bind (ConeBuildOptions), so they are part of the key.
std::uint64_t cache_key(const HeightField& field, ConeKind kind, const ConeBuildOptions& options)
{
    Fnv f;
    f.add32(kConeGeneratorVersion);
    f.add32(std::uint32_t(kind));
    f.add32(std::uint32_t(options.format));
    f.add32(std::uint32_t(std::max(options.relaxed_budget, 0)));
    f.add32(std::uint32_t(std::max(options.node_budget, 0)));
    f.add32(std::uint32_t(std::max(options.best_first_budget, 0)));
    f.add32(std::uint32_t(field.width));
    f.add32(std::uint32_t(field.height));
    f.add(field.texels.data(), field.texels.size() * sizeof(float));
    return f.h;
}

template <typename T>
void put(std::vector<std::uint8_t>& out, T v)
{
    const std::size_t at = out.size();
    out.resize(at + sizeof(T));
    std::memcpy(out.data() + at, &v, sizeof(T));
}

template <typename T>
T get(const std::vector<std::uint8_t>& in, std::size_t at)
{
    T v;
    std::memcpy(&v, in.data() + at, sizeof(T));
    return v;
}

std::vector<std::uint8_t> serialize(const ConeMap& map, ConeFormat format, std::uint64_t key)
{
    const std::size_t n = map.heights.size();
    std::vector<std::uint8_t> payload;
    payload.reserve(n * 6);
    for (float h : map.heights) put(payload, h);
    for (float r : map.ratios) put(payload, std::uint16_t(cone_ratio_to_steps(r, format)));
    Fnv sum;
    sum.add(payload.data(), payload.size());
    std::vector<std::uint8_t> out(kMagic, kMagic + 8);
    put(out, kConeGeneratorVersion);
    put(out, std::uint32_t(map.kind));
    put(out, std::uint32_t(format));
    put(out, std::uint32_t(map.width));
    put(out, std::uint32_t(map.height));
    put(out, key);
    put(out, sum.h);
    out.insert(out.end(), payload.begin(), payload.end());
    return out;
}

// The map in `bytes`, or an empty string explaining why it is not usable.
std::string deserialize(const std::vector<std::uint8_t>& bytes, const HeightField& field, ConeKind kind,
                        ConeFormat format, std::uint64_t key, ConeMap& map)
{
    const std::size_t n = field.texels.size();
    if (bytes.size() < kHeaderBytes || std::memcmp(bytes.data(), kMagic, 8) != 0) return "bad header";
    if (get<std::uint32_t>(bytes, 8) != kConeGeneratorVersion) return "another generator version";
    if (get<std::uint32_t>(bytes, 12) != std::uint32_t(kind) || get<std::uint32_t>(bytes, 16) != std::uint32_t(format))
        return "another kind or format";
    if (get<std::uint32_t>(bytes, 20) != std::uint32_t(field.width) ||
        get<std::uint32_t>(bytes, 24) != std::uint32_t(field.height))
        return "another size";
    if (get<std::uint64_t>(bytes, 28) != key) return "another key";
    if (bytes.size() != kHeaderBytes + n * 6) // cut short, or with bytes appended
        return "size is wrong (expected " + std::to_string(kHeaderBytes + n * 6) + " bytes, found " +
               std::to_string(bytes.size()) + ")";
    Fnv sum;
    sum.add(bytes.data() + kHeaderBytes, n * 6);
    if (get<std::uint64_t>(bytes, 36) != sum.h) return "checksum mismatch";
    HeightField rounded;
    const HeightField& source = cone_source_field(field, format, rounded);
    if (std::memcmp(bytes.data() + kHeaderBytes, source.texels.data(), n * sizeof(float)) != 0)
        return "heights differ from the height map";
    const std::vector<float>& ratio_of = cone_ratio_table(format);
    map.width = field.width;
    map.height = field.height;
    map.kind = kind;
    map.heights = source.texels;
    map.ratios.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const std::size_t k = get<std::uint16_t>(bytes, kHeaderBytes + 4 * n + 2 * i);
        if (k >= ratio_of.size()) return "ratio out of range";
        map.ratios[i] = ratio_of[k];
    }
    return {};
}

std::filesystem::path entry_for_key(const HeightField& field, ConeKind kind, ConeFormat format,
                                    const std::filesystem::path& cache_dir, std::uint64_t key)
{
    if (cache_dir.empty()) return {}; // no cache
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(key));
    return cache_dir / "cone" /
           (cone_kind_name(kind) + "-" + cone_format_name(format) + "-" + std::to_string(field.width) + "x" +
            std::to_string(field.height) + "-" + hex + ".bin");
}

// Why `folder` could not be made: create_directories says "File exists" where a part of the path
// is a file, or a link to nothing (a --cache-dir link whose target is missing), and "No such file
// or directory" where a folder takes no new entry (/proc: it read as if /proc were missing; found
// by an exploratory session, fiftieth).
std::string folder_problem(const std::filesystem::path& folder, const std::error_code& ec)
{
    std::filesystem::path part, parent;
    for (const std::filesystem::path& name : folder) {
        parent = part;
        part /= name;
        std::error_code e;
        if (const std::string link = broken_link_reason(part.string()); !link.empty())
            return "cannot create it: " + part.string() + " " + link;
        if (std::filesystem::exists(part, e) && !std::filesystem::is_directory(part, e))
            return "cannot create it: " + part.string() + " is not a folder";
        if (!std::filesystem::exists(part, e) && ec == std::errc::no_such_file_or_directory && !parent.empty() &&
            std::filesystem::is_directory(parent, e))
            return "cannot create it: " + parent.string() + " takes no new folder (a file system such as /proc or /sys)";
    }
    return ec.message();
}

// The cache's folders, each missing part made with mode 0700, as the XDG base directory
// specification asks: only the user writes them (entries are checked for accidents, not forgery:
// docs/robustness.md). create_directories made them with the process's umask: under umask 000
// anyone could write forged entries (found by an exploratory session, thirty-fourth). A folder
// that exists keeps its mode.
void create_private_directories(const std::filesystem::path& folder, std::error_code& ec)
{
    std::filesystem::path part;
    for (const std::filesystem::path& name : folder) {
        part /= name;
        if (::mkdir(part.c_str(), 0700) != 0 && errno != EEXIST) {
            ec = std::error_code(errno, std::generic_category());
            return;
        }
    }
    if (!std::filesystem::is_directory(folder, ec) && !ec) ec = std::make_error_code(std::errc::not_a_directory);
}

// The cache's own entries, named as cone_cache_path names them:
// <kind>-<format>-<W>x<H>-<16 hex digits>.bin. The whole pattern: a file of the user's that merely
// began "cone-" and ended ".bin" was counted against the bound and removed (found by an
// exploratory session).
bool is_entry_name(std::string_view name)
{
    static const std::regex entry("(cone|relaxed)-(rg8|rg16)-[1-9][0-9]{0,5}x[1-9][0-9]{0,5}-[0-9a-f]{16}[.]bin");
    return std::regex_match(name.begin(), name.end(), entry);
}

// An entry's temporary, as write_file_atomic names it: ".<entry>.tmpNNNNNN".
bool is_entry_temporary(std::string_view name)
{
    const std::size_t at = name.rfind(".tmp");
    if (!name.starts_with(".") || at == std::string_view::npos || at + 4 == name.size()) return false;
    for (const char c : name.substr(at + 4))
        if (c < '0' || c > '9') return false;
    return is_entry_name(name.substr(1, at - 1));
}

} // namespace

std::filesystem::path default_cache_dir(bool warn_if_none)
{
    // Absolute places only: a relative one would put the cache wherever the command runs (the XDG
    // specification says to ignore a relative XDG_CACHE_HOME). And no shared fallback such as
    // /tmp: another user could plant entries there (the checksum catches accidents, not forgery).
    const auto absolute = [](const char* variable) {
        const char* value = std::getenv(variable);
        return value && *value && std::filesystem::path(value).is_absolute() ? std::filesystem::path(value)
                                                                             : std::filesystem::path();
    };
    if (const std::filesystem::path xdg = absolute("XDG_CACHE_HOME"); !xdg.empty()) return xdg / "prismrelief";
    if (const std::filesystem::path home = absolute("HOME"); !home.empty()) return home / ".cache" / "prismrelief";
    if (warn_if_none)
        warn("no cone-map cache: neither XDG_CACHE_HOME nor HOME is an absolute path, so maps are built each time "
             "(--cache-dir DIR keeps them in DIR)");
    return {};
}

void check_cache_flags(bool no_cache, const std::string& cache_dir_flag)
{
    if (no_cache && !cache_dir_flag.empty()) throw Error("--no-cache", "conflicts with --cache-dir");
}

void check_outputs_outside_cache(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs,
                                 const std::filesystem::path& cache_dir_flag)
{
    namespace fs = std::filesystem;
    // (Its warning, if there is no default place, comes where the cache is used.)
    const fs::path dir = cache_dir_flag.empty() ? default_cache_dir(false) : cache_dir_flag;
    if (dir.empty()) return;
    // Compared as absolute paths with the links that exist resolved: `--out ./c --cache-dir c`.
    // An output that is already a regular file is left to the output's own checks.
    const auto resolved = [](const fs::path& p) {
        std::error_code ec;
        fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
        if (ec) return fs::path();
        // Without a trailing separator's empty last element (`--cache-dir cz/` was "a folder the
        // cone-map cache is in" for `--out cz`; found by an exploratory session, thirty-sixth).
        if (!r.has_filename() && r.has_relative_path()) r = r.parent_path();
        return r;
    };
    const fs::path folder = resolved(dir);
    if (folder.empty()) return;
    const fs::path entries = folder / "cone";
    for (const auto& [option, path] : outputs) {
        if (path.empty()) continue;
        const fs::path out = resolved(path);
        if (out.empty()) continue;
        // A file among the entries (one of this run's, say): the cache replaces and trims them
        // (`--out` naming the entry the run reads wrote the PNG over it, and the next run warned
        // of a bad header and built the map again; found by an exploratory session).
        if (out.parent_path() == entries)
            throw Error(path.string(), "is in the cone-map cache's entries' folder (" + (dir / "cone").string() +
                                           "), whose files the cache replaces: name a file elsewhere, or another --cache-dir");
        std::error_code ec;
        if (fs::is_regular_file(out, ec)) continue; // (then the cache cannot be made: it warns)
        // `out` itself, or a folder on the way to the entries (`--out cz --cache-dir cz/sub`).
        const auto [o, e] = std::mismatch(out.begin(), out.end(), entries.begin(), entries.end());
        if (o != out.end()) continue;
        const std::string what = out == entries  ? "the cone-map cache's entries' folder (" + (dir / "cone").string() + ")"
                                 : out == folder ? "the cone-map cache's folder (" + dir.string() + ")"
                                                 : "a folder the cone-map cache is in (" + dir.string() + ")";
        throw Error(path.string(), "is " + what + ", which the run creates: name a file, or another --cache-dir");
    }
}

std::uint64_t cone_cache_max_bytes()
{
    constexpr std::uint64_t kDefaultMiB = 2048;
    const char* env = std::getenv("PRISMRELIEF_CACHE_MAX_MB");
    if (!env || !*env) return kDefaultMiB << 20;
    std::uint64_t mib = 0;
    const char* end = env + std::strlen(env);
    const auto [at, ec] = std::from_chars(env, end, mib);
    // A size past 2^43 MiB (8 EiB), or past 64 bits, bounds nothing a disk holds: no bound, as 0
    // (it fell back to the default, 2048 MiB, said as "not a size"; found by an exploratory
    // session, fifty-third).
    if (at == end && (ec == std::errc::result_out_of_range || (ec == std::errc() && mib > (std::uint64_t(1) << 43))))
        return std::numeric_limits<std::uint64_t>::max();
    if (ec != std::errc() || at != end) {
        warn(std::string("PRISMRELIEF_CACHE_MAX_MB: '") + env + "' is not a size in MiB; the cache keeps " +
             std::to_string(kDefaultMiB) + " MiB");
        return kDefaultMiB << 20;
    }
    return mib == 0 ? std::numeric_limits<std::uint64_t>::max() : mib << 20;
}

std::size_t trim_cone_cache(const std::filesystem::path& cache_dir, std::uint64_t max_bytes,
                            const std::filesystem::path& keep)
{
    namespace fs = std::filesystem;
    struct Entry {
        fs::path path;
        fs::file_time_type used;
        std::uint64_t bytes;
    };
    if (cache_dir.empty()) return 0; // no cache
    std::vector<Entry> entries;
    std::uint64_t total = 0;
    std::error_code ec;
    // A temporary written to for an hour is no longer being written (an entry takes seconds).
    const fs::file_time_type stale = fs::file_time_type::clock::now() - std::chrono::hours(1);
    for (fs::directory_iterator it(cache_dir / "cone", ec), end; !ec && it != end; it.increment(ec)) {
        // Only the cache's own entries and their temporaries: never anything else.
        const std::string name = it->path().filename().string();
        std::error_code e;
        if (is_entry_temporary(name)) {
            if (it->is_regular_file(e) && it->last_write_time(e) < stale && !e) fs::remove(it->path(), e);
            continue;
        }
        if (!is_entry_name(name) || !it->is_regular_file(e)) continue;
        const std::uint64_t bytes = it->file_size(e);
        const fs::file_time_type used = e ? fs::file_time_type::min() : it->last_write_time(e);
        if (e) continue; // gone meanwhile (another process trimming)
        entries.push_back({it->path(), used, bytes});
        total += bytes;
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
    std::size_t removed = 0;
    for (const Entry& e : entries) {
        if (total <= max_bytes) break;
        if (e.path == keep) continue;
        std::error_code re;
        if (fs::remove(e.path, re)) ++removed;
        total -= e.bytes; // (removed by another process if not by us)
    }
    return removed;
}

std::filesystem::path cone_cache_entry(const HeightField& field, ConeKind kind, const ConeBuildOptions& options,
                                       const std::filesystem::path& cache_dir)
{
    return entry_for_key(field, kind, options.format, cache_dir, cache_key(field, kind, options));
}

namespace {

// The entry's map, read as the user's own files are (core/input_file.hpp): a huge file cannot
// fill memory (no more than twice the size of this map's entry is read; within that,
// deserialize() says what is wrong), and a FIFO put in the entry's place between the check and
// the read is refused after a second without a writer (one with a writer that never writes could
// still hold it: the cache folder is the user's own, docs/robustness.md). Empty `why`: read;
// else why not, `gone` where the entry was removed since the check (another process's trim: a miss).
struct EntryRead {
    ConeMap map;
    std::string why;
    bool gone = false;
};
EntryRead read_entry(const std::filesystem::path& entry, const HeightField& field, ConeKind kind,
                     ConeFormat format, std::uint64_t key)
{
    EntryRead r;
    std::error_code ec;
    const std::uint64_t entry_bytes = kHeaderBytes + field.texels.size() * 6;
    std::vector<std::uint8_t> bytes;
    try {
        bytes = read_input_bytes(entry.string(), {2 * entry_bytes, "a cone-map cache entry", "not this map's entry"});
    } catch (const Error& e) {
        r.why = e.problem();
        r.gone = !std::filesystem::exists(std::filesystem::symlink_status(entry, ec));
        return r;
    }
    r.why = deserialize(bytes, field, kind, format, key, r.map);
    // Used now: the last entries a trim removes (a read-only cache keeps its times).
    if (r.why.empty()) std::filesystem::last_write_time(entry, std::filesystem::file_time_type::clock::now(), ec);
    return r;
}

// Why what is where an entry goes is not one (not_a_file_reason), or a link that loops; "" where
// it is a file or nothing is there (a dangling link reads as nothing: a miss).
std::string entry_not_a_file_reason(const std::filesystem::path& entry)
{
    if (std::string why = not_a_file_reason(entry.c_str()); !why.empty()) return why;
    // (The entry's own link: a loop in the cache's folder said every entry there loops; found by
    // an exploratory session, fiftieth. The write says what is wrong with the folder.)
    struct stat st {};
    if (::lstat(entry.c_str(), &st) == 0 && S_ISLNK(st.st_mode) && ::stat(entry.c_str(), &st) != 0 && errno == ELOOP)
        return "is a symbolic link that loops";
    return "";
}

} // namespace

std::optional<ConeMap> read_cached_cone_map(const HeightField& field, ConeKind kind,
                                            const std::filesystem::path& cache_dir, const ConeBuildOptions& options)
{
    if (cache_dir.empty()) return std::nullopt;
    const std::uint64_t key = cache_key(field, kind, options);
    const std::filesystem::path entry = entry_for_key(field, kind, options.format, cache_dir, key);
    std::error_code ec;
    if (!std::filesystem::is_regular_file(entry, ec)) return std::nullopt;
    EntryRead r = read_entry(entry, field, kind, options.format, key);
    if (!r.why.empty()) return std::nullopt;
    return std::move(r.map);
}

ConeCacheResult cached_cone_map(const HeightField& field, ConeKind kind, const std::filesystem::path& cache_dir,
                                const ConeBuildOptions& options, const ConeBuilder& build)
{
    ConeCacheResult result;
    if (cache_dir.empty()) { // no cache
        result.map = build(field, kind, options);
        return result;
    }
    const std::uint64_t key = cache_key(field, kind, options); // hashes every texel: once
    result.entry = entry_for_key(field, kind, options.format, cache_dir, key);
    std::error_code ec;
    if (std::filesystem::is_regular_file(result.entry, ec)) {
        EntryRead r = read_entry(result.entry, field, kind, options.format, key);
        if (r.why.empty()) {
            result.map = std::move(r.map);
            result.from_cache = true;
            // (No progress: on a terminal a hit drew "building … 100%" for a moment; found by an
            // exploratory session, thirty-second.)
            return result;
        }
        // (An entry that went between the check and the read said "cannot open: No such file or
        // directory; rebuilding it", a warning meant for entries that are wrong; found by an
        // exploratory session, thirty-second.)
        if (!r.gone) warn("cone-map cache entry " + result.entry.string() + ": " + r.why + "; rebuilding it");
    } else if (const std::string why = entry_not_a_file_reason(result.entry);
               !why.empty() && !(std::filesystem::is_directory(result.entry, ec) && !std::filesystem::is_empty(result.entry, ec))) {
        // An empty folder, a FIFO, a link to a device or a link that loops where the entry goes:
        // replaced below, and said as any entry that is wrong is (they went without a word; found
        // by exploratory sessions, forty-first and forty-ninth). (A folder with anything in it
        // stays, and the write below says so.)
        warn("cone-map cache entry " + result.entry.string() + ": " + why + "; rebuilding it");
    }
    result.map = build(field, kind, options);
    try {
        create_private_directories(result.entry.parent_path(), ec);
        if (ec) throw Error(result.entry.parent_path().string(), folder_problem(result.entry.parent_path(), ec));
        // A FIFO, socket or device node where the entry goes, or an empty folder: the cache is
        // the user's own and the entry is being rebuilt, so it goes (written over, it stayed, and
        // every run rebuilt the map and warned; found by an exploratory session, thirty-fourth).
        // A folder with anything in it is left, and said.
        std::error_code se;
        const std::filesystem::file_status st = std::filesystem::symlink_status(result.entry, se);
        if (!se && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) &&
            !std::filesystem::is_symlink(st))
            std::filesystem::remove(result.entry, se);
        write_file_atomic(result.entry, serialize(result.map, options.format, key), OldMode::Drop);
        trim_cone_cache(cache_dir, cone_cache_max_bytes(), result.entry);
    } catch (const Error& e) {
        warn("cone-map cache not written: " + std::string(e.what()));
        result.entry.clear(); // (conemap --json's cache_entry named a file that was never written)
    }
    return result;
}

ConeCacheResult cached_cone_map(const HeightField& field, ConeKind kind, const std::filesystem::path& cache_dir,
                                const ConeBuildOptions& options)
{
    return cached_cone_map(field, kind, cache_dir, options, build_cone_map_cpu);
}

} // namespace pr
