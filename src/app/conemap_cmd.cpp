// prismrelief conemap: a cone or relaxed-cone map of a height map, as a PNG (R height, G ratio;
// docs/cone-maps.md), through the derived-map cache.
#include "app/commands.hpp"
#include "app/progress.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "maps/conemap.hpp"
#include "platform/context.hpp"
#include "render/conemap_gpu.hpp"
#include "render/shader_program.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>

namespace pr {

namespace {

// A cache entry's absolute path without "." parts (--cache-dir ./cd/ gave "/w/./cd/cone/...";
// found by an exploratory session, forty-sixth). Not lexically_normal(): ".." past a link to a
// folder elsewhere is not the folder before the link.
std::string absolute_entry(const std::filesystem::path& entry)
{
    std::filesystem::path tidy;
    for (const std::filesystem::path& part : std::filesystem::absolute(entry))
        if (!part.empty() && part != ".") tidy /= part;
    return tidy.string();
}

} // namespace

CommandAction add_conemap_command(CLI::App& app)
{
    struct State {
        std::string height;
        std::string out;
        std::string kind = "cone";
        std::string format = "rg16";
        std::string backend = "cpu";
        std::string gl_backend = "osmesa";
        int threads = 0;
        std::string cache_dir;
        bool no_cache = false;
        std::string json;
    };
    auto s = std::make_shared<State>();
    CLI::App* cmd = app.add_subcommand(
        "conemap", "Build a cone or relaxed-cone map of a height map: PNG with R = height, G = sqrt(cone ratio), "
                   "rounded down (docs/cone-maps.md)");
    cmd->add_option("--height", s->height, "Height map: image file or builtin:NAME[@N] (" + [] {
        std::string l;
        for (const auto& n : builtin_height_names()) l += (l.empty() ? "" : ", ") + n;
        return l;
    }() + ")")->required();
    cmd->add_option("--out", s->out, "Output PNG: RGB, R height, G ratio, B 0 (8 or 16 bits)")->required();
    cmd->add_option("--kind", s->kind, "cone (conservative at texel centres) or relaxed (Policarpo & Oliveira)")
        ->capture_default_str();
    cmd->add_option("--format", s->format, "rg8 or rg16: bits per channel; ratios are rounded down to its steps")
        ->capture_default_str();
    cmd->add_option("--backend", s->backend, "cpu (threads) or gpu (compute shader on an OpenGL 4.5 context)")
        ->capture_default_str();
    cmd->add_option("--gl-backend", s->gl_backend, "With --backend gpu: osmesa (llvmpipe) or egl")
        ->capture_default_str();
    cmd->add_option("--threads", s->threads, "CPU threads, 0 to 1024 (0: all cores; no more are started than the map has rows of work)")
        ->transform(saturating<int>())
        ->capture_default_str();
    cmd->add_option("--cache-dir", s->cache_dir,
                    "Derived-map cache (default $XDG_CACHE_HOME/prismrelief, else ~/.cache/prismrelief; the "
                    "least recently used go beyond $PRISMRELIEF_CACHE_MAX_MB, default 2048)");
    cmd->add_flag("--no-cache", s->no_cache, "Neither read nor write the cache");
    cmd->add_option("--json", s->json, "JSON report: height_map, width, height, kind, format, backend, device, ms (a GPU build's search_ms: its dispatches and read-back, and search_cpu_ms of it the CPU's threads finishing the searches that ran out of nodes there, searches_resumed from the GPU's state or texels_restarted; seed_ms of it finding the seeds where seeds says, cpu (the wait for them: begun before the context) or gpu), from_cache, cache_entry, statistics of the stored ratio sqrt(c) (ratio_min, ratio_mean, ratio_max)");
    cmd->footer("Example:\n  prismrelief conemap --height builtin:bricks --kind relaxed --out out/bricks_relaxed.png");

    return [s, cmd]() {
        const ConeKind kind = parse_cone_kind(s->kind, "--kind");
        ConeBuildOptions options;
        options.format = parse_cone_format(s->format, "--format");
        const bool gpu = parse_cone_backend_gpu(s->backend, "--backend");
        const Backend gl_backend = parse_backend(s->gl_backend, "--gl-backend");
        // (It was ignored: flags that change nothing are refused, as the prism's are elsewhere.)
        if (!gpu && cmd->count("--gl-backend") > 0)
            throw Error("--gl-backend", "applies with --backend gpu only (the CPU's threads build the map without OpenGL)");
        if (s->threads < 0 || s->threads > 1024) throw Error("--threads", "must be between 0 (all cores) and 1024");
        options.threads = s->threads;
        if (s->height.empty()) throw Error("--height", "empty file name");
        check_cache_flags(s->no_cache, s->cache_dir);
        check_png_output(s->out);
        if (!s->json.empty()) check_output_folder(s->json);
        std::vector<NamedPath> inputs = {{"--height", s->height}};
        for (NamedPath& shader : shader_override_inputs()) inputs.push_back(std::move(shader));
        check_distinct_outputs({{"--out", s->out}, {"--json", s->json}}, inputs);
        if (!s->no_cache) check_outputs_outside_cache({{"--out", s->out}, {"--json", s->json}}, s->cache_dir);
        // A GPU build loads Mesa on another thread (about 75 ms of its fixed cost on the 2-core
        // machine) while the CPU does its share: with --no-cache, from before the height map is
        // read; else once the cache has missed (build, below), while the max pyramid is built. Not
        // before a cache hit: the process would only wait for it at exit.
        if (gpu && s->no_cache) preload_backend(gl_backend);
        // Said under the flag's name, as render's maps are.
        const HeightField field = [&] {
            try {
                return load_height(s->height);
            } catch (const Error& e) {
                throw e.under("--height");
            }
        }();
        release_warnings(); // every input accepted (core/error.hpp)

        ProgressBar bar("conemap");
        options.progress = [&bar](double f) { bar(f); };
        std::string device = gpu ? "gpu" : "cpu";
        std::optional<ConeGpuReport> gpu_report; // a GPU build's
        const ConeBuilder build = [&](const HeightField& f, ConeKind k, const ConeBuildOptions& o) {
            if (!gpu) {
                const unsigned n = cone_cpu_threads(o, cone_cpu_items(f.width, f.height));
                device = "cpu, " + std::to_string(n) + (n == 1 ? " thread" : " threads");
                return build_cone_map_cpu(f, k, o);
            }
            preload_backend(gl_backend); // (started already with --no-cache)
            std::unique_ptr<Context> context;
            gpu_report.emplace();
            return build_cone_map_gpu(f, k, o, &*gpu_report, [&] {
                context = create_headless_context(gl_backend, "--gl-backend");
                device = "gpu, " + context->description();
            });
        };
        const auto start = std::chrono::steady_clock::now();
        ConeCacheResult result;
        if (s->no_cache) {
            result.map = build(field, kind, options);
        } else {
            const std::filesystem::path dir = s->cache_dir.empty() ? default_cache_dir() : std::filesystem::path(s->cache_dir);
            result = cached_cone_map(field, kind, dir, options, build);
        }
        const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        bar.clear();

        const ConeMap& m = result.map;
        // Of the ratios as the PNG stores them, G over the format's steps: the map's floats are
        // those quotients rounded down to float (cone_steps_to_ratio), which reported 96/255 as
        // 0.37647056 (found by an exploratory session, forty-sixth).
        const double steps = double(cone_format_steps(options.format));
        double sum = 0.0, lo = steps, hi = 0.0;
        for (float r : m.ratios) {
            const double k = double(cone_ratio_to_steps(r, options.format));
            sum += k, lo = std::min(lo, k), hi = std::max(hi, k);
        }
        const double mean = m.ratios.empty() ? 0.0 : sum / double(m.ratios.size()) / steps;
        lo = m.ratios.empty() ? 1.0 : lo / steps;
        hi /= steps;
        const std::string how = result.from_cache ? "from the cache (" + one_line(result.entry.string()) + ")" : "built (" + device + ")";
        // Both outputs or neither: both are staged before either is renamed into place, so a
        // failure to write either leaves both destinations as they were.
        std::optional<StagedFile> json;
        if (!s->json.empty()) {
            const nlohmann::json report = {{"height_map", s->height},
                                           {"width", m.width},
                                           {"height", m.height},
                                           {"kind", cone_kind_name(kind)},
                                           {"format", cone_format_name(options.format)},
                                           {"backend", s->backend},
                                           {"device", result.from_cache ? std::string("cache") : device},
                                           {"from_cache", result.from_cache},
                                           // null without a cache (--no-cache, or no cache location), as search_ms is without a GPU
                                           {"cache_entry", s->no_cache || result.entry.empty() ? nlohmann::json()
                                                                                              : nlohmann::json(absolute_entry(result.entry))},
                                           {"ms", ms},
                                           // A GPU build only (null otherwise): the dispatches and
                                           // read-back, without creating the context, uploading and
                                           // compiling, with the CPU's share: finishing the searches
                                           // that ran out of nodes on the GPU (resumed from its state,
                                           // or restarted where it had no room to save it).
                                           {"search_ms", gpu_report ? nlohmann::json(gpu_report->search_ms) : nlohmann::json()},
                                           {"search_cpu_ms", gpu_report ? nlohmann::json(gpu_report->cpu_ms) : nlohmann::json()},
                                           {"searches_resumed", gpu_report ? nlohmann::json(gpu_report->resumed) : nlohmann::json()},
                                           {"texels_restarted", gpu_report ? nlohmann::json(gpu_report->restarted) : nlohmann::json()},
                                           // Of search_ms, finding the seeds, and where: "cpu" or "gpu".
                                           {"seed_ms", gpu_report ? nlohmann::json(gpu_report->seed_ms) : nlohmann::json()},
                                           {"seeds", gpu_report ? nlohmann::json(gpu_report->seeds_on_cpu ? "cpu" : "gpu") : nlohmann::json()},
                                           {"ratio_min", lo},
                                           {"ratio_mean", mean},
                                           {"ratio_max", hi}};
            json.emplace(s->json, report_text(report));
        }
        StagedFile png(s->out, encode_cone_png(s->out, result.map, options.format));
        commit_together({&png, json ? &*json : nullptr});
        std::printf("%s: %dx%d %s %s, %s in %.0f ms, ratio min %.4f mean %.4f max %.4f\n", one_line(s->out).c_str(), m.width,
                    m.height, cone_kind_name(kind).c_str(), cone_format_name(options.format).c_str(), how.c_str(), ms,
                    lo, mean, hi);
        if (!s->json.empty()) std::printf("wrote %s\n", one_line(s->json).c_str()); // (as render's and compare's)
        return kExitOk;
    };
}

} // namespace pr
