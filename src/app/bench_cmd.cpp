// prismrelief bench: frame times (interleaved A B A B … so drift cancels in ratios) and GPU
// counters (fragments shaded, height samples per fragment) per technique.
#include "app/commands.hpp"
#include "app/progress.hpp"
#include "app/session.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/stats.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>

namespace pr {

namespace {

struct BenchRow {
    std::string label;
    std::vector<double> ms;
    SampleCounters counters;
    bool drew = false; // the counted frame covers a pixel
};

// The p-th percentile (0..1) of samples per fragment from the counters' histogram: exact below
// 8192, past it the fewest samples of its bin (at most 1/1024 under).
double histogram_percentile(const std::vector<std::uint64_t>& histogram, double p)
{
    std::uint64_t total = 0;
    for (auto n : histogram) total += n;
    if (total == 0) return 0.0;
    const auto rank = static_cast<std::uint64_t>(std::ceil(p * double(total)));
    std::uint64_t seen = 0;
    for (std::size_t i = 0; i < histogram.size(); ++i) {
        seen += histogram[i];
        if (seen >= std::max<std::uint64_t>(rank, 1)) return double(sample_bin_low(i));
    }
    return double(sample_bin_low(histogram.size() - 1));
}

} // namespace

CommandAction add_bench_command(CLI::App& app)
{
    struct State {
        SceneOptions scene;
        TechniqueOptions quality;
        int frames = 20;
        int warmup = 3;
        std::string json;
    };
    auto s = std::make_shared<State>();
    s->quality.techniques = "flat,normal,offset,steep,pom,relief";
    CLI::App* cmd = app.add_subcommand(
        "bench", "Time techniques (interleaved) and count fragments and height samples per fragment on the GPU");
    add_scene_options(*cmd, s->scene);
    add_technique_options(*cmd, s->quality, false);
    cmd->add_option("--frames", s->frames, "Timed frames per technique (1-100000)")
        ->transform(saturating<int>())
        ->group("Bench")
        ->capture_default_str();
    cmd->add_option("--warmup", s->warmup, "Untimed frames per technique first, after one that compiles its shaders (0-1000)")
        ->transform(saturating<int>())
        ->group("Bench")
        ->capture_default_str();
    cmd->add_option("--json", s->json, "JSON report (see docs/benchmarks.md)")->group("Output");

    return [s]() {
        const std::vector<TechniqueRun> runs = parse_technique_list(s->quality.techniques, s->quality);
        const ReferenceOptions ref_options = make_reference_options(s->quality);
        {
            std::vector<DrawSettings> drawn;
            for (const TechniqueRun& run : runs) drawn.push_back(run.settings);
            check_quality_flags_apply(s->quality, drawn, "--techniques " + s->quality.techniques);
            s->scene.reads_cone_maps =
                check_cone_map_flags_apply(s->scene, drawn, with_prism_flags(s->quality, "--techniques " + s->quality.techniques));
        }
        if (s->frames < 1 || s->frames > 100000) throw Error("--frames", "must be between 1 and 100000");
        if (s->warmup < 0 || s->warmup > 1000) throw Error("--warmup", "must be between 0 and 1000");
        if (!s->json.empty()) check_output_folder(s->json);
        Session session = open_session(s->scene, {{"--json", s->json}});
        Renderer& r = *session.renderer;
        for (const TechniqueRun& run : runs) r.check_drawable(run.settings, "--techniques");
        release_warnings(); // every input accepted (core/error.hpp)
        std::optional<Renderer::ReferenceStats> reference; // its geometry, for the JSON's reference row
        for (const TechniqueRun& run : runs)
            if (run.settings.technique == Technique::Reference) {
                reference = r.prepare_reference(session.scene, session.camera, ref_options);
                warn_if_capped(*reference, "bench");
                break;
            }

        std::vector<BenchRow> rows(runs.size());
        // Every frame drawn counts in the progress: the counting ones, one that compiles, the
        // warm-up and the timed ones (the warm-up's were not counted, and 1000 of them at
        // --steps 1024 ran for an hour without a word; found by an exploratory session, forty-fourth).
        ProgressBar bar("bench");
        const double frames_in_all = double(runs.size()) * double(2 + s->warmup + s->frames);
        double frames_drawn = 0.0;
        const auto drawn = [&] { bar(++frames_drawn / frames_in_all); };
        // Counters: one instrumented frame per technique (the same shaders with PR_COUNT_SAMPLES).
        for (std::size_t i = 0; i < runs.size(); ++i) {
            rows[i].label = runs[i].label;
            DrawSettings counted = runs[i].settings;
            counted.count_samples = true;
            r.draw(session.camera, session.light, counted);
            rows[i].counters = r.read_counters();
            rows[i].drew = !drew_nothing(r.read_color());
            drawn();
        }
        // One untimed draw per technique compiles its shaders (the counting frame above built the
        // instrumented variant): with --warmup 0 the first timed frame included the compilation
        // (prism 24 ms against 0.5 ms at 48x32). Then --warmup's frames.
        for (int w = 0; w < 1 + s->warmup; ++w)
            for (const TechniqueRun& run : runs) {
                r.draw(session.camera, session.light, run.settings);
                drawn();
            }
        for (int f = 0; f < s->frames; ++f)
            for (std::size_t i = 0; i < runs.size(); ++i) {
                rows[i].ms.push_back(r.draw(session.camera, session.light, runs[i].settings));
                drawn();
            }
        bar.clear();

        nlohmann::json results = nlohmann::json::array();
        std::printf("%s, %dx%d, %d frame%s per technique (interleaved)\n", session.context->description().c_str(),
                    session.spec.width, session.spec.height, s->frames, s->frames == 1 ? "" : "s");
        int name_width = 14; // as wide as the longest name
        for (const BenchRow& row : rows) name_width = std::max(name_width, int(row.label.size()));
        // `ratio`: the median over the first row's, the figure to compare (the JSON's
        // ms_ratio_to_first; the table had none, so the docs' "table's ratio" was nowhere to be
        // read; found by an exploratory session, thirty-third).
        std::printf("%-*s %9s %9s %9s %7s %11s %9s %9s %9s\n", name_width, "technique", "ms_median", "ms_min", "ms_max",
                    "ratio", "fragments", "spf_mean", "spf_p95", "ppf_mean");
        const double base = median(rows[0].ms);
        for (std::size_t i = 0; i < rows.size(); ++i) {
            const BenchRow& row = rows[i];
            const double med = median(row.ms);
            const double mean = row.counters.fragments ? double(row.counters.samples) / double(row.counters.fragments) : 0.0;
            const double p95 = histogram_percentile(row.counters.histogram, 0.95);
            const auto [mn, mx] = std::minmax_element(row.ms.begin(), row.ms.end());
            // Per fragment, over none (nothing in view): no value, "-" and null, as compare's
            // metrics over no pixels.
            const bool any = row.counters.fragments > 0;
            // The prisms a walk's view ray crosses, per fragment (walk rows only): on a GPU the
            // walk's traversal, not its samples, is the frame (docs/benchmarks.md).
            const bool walk = runs[i].settings.prism_walk();
            const double prisms = any ? double(row.counters.prisms) / double(row.counters.fragments) : 0.0;
            const double ratio = base > 0 ? med / base : 0.0;
            std::printf("%-*s %9.2f %9.2f %9.2f %7s %11llu %9s %9s %9s\n", name_width, row.label.c_str(), med, *mn,
                        *mx, base > 0 ? fixed(ratio, 2).c_str() : "-", static_cast<unsigned long long>(row.counters.fragments), any ? fixed(mean, 2).c_str() : "-",
                        any ? fixed(p95, 0).c_str() : "-", walk && any ? fixed(prisms, 2).c_str() : "-");
            results.push_back({{"technique", row.label},
                               {"ms_median", med},
                               {"ms_min", *mn},
                               {"ms_max", *mx},
                               {"ms_ratio_to_first", ratio},
                               {"fragments", row.counters.fragments},
                               {"samples", row.counters.samples},
                               {"samples_per_fragment_mean", any ? nlohmann::json(mean) : nlohmann::json()},
                               {"samples_per_fragment_p95", any ? nlohmann::json(p95) : nlohmann::json()},
                               {"frames", row.ms.size()}});
            if (walk) {
                results.back()["prisms_per_fragment_mean"] = any ? nlohmann::json(prisms) : nlohmann::json();
                results.back()["prisms_per_fragment_max"] = any ? nlohmann::json(row.counters.prisms_most) : nlohmann::json();
            }
            results.back().update(quality_json(runs[i].settings));
            results.back().update(prism_configuration(runs[i].settings));
            results.back().update(shadows_json(runs[i].settings));
            // The reference's geometry (level, triangles, bytes, build_ms, capped), as render's JSON
            // gives it: a GPU's time for true geometry means little without its size.
            if (reference && runs[i].settings.technique == Technique::Reference)
                results.back()["reference"] = reference_json(*reference);
        }
        // No pixel covered in any technique's counted frame: the times are of an empty view. (By
        // the coverage, as render's warning: fragments count the discarded too, so a prism seen
        // from inside its shell, looking out past the mesh, had fragments and no picture, and
        // bench said nothing; found by an exploratory session, thirty-second.)
        if (std::none_of(rows.begin(), rows.end(), [](const BenchRow& row) { return row.drew; }))
            warn_nothing_drawn("bench");
        if (!s->json.empty()) {
            nlohmann::json report = {{"results", results},
                                     {"size", {session.spec.width, session.spec.height}},
                                     {"objects", scene_json(session.scene)},
                                     // (Times depend on the view: the camera makes a run
                                     // repeatable, as render's and compare's reports do.)
                                     {"camera", camera_json(session.camera)},
                                     {"renderer", session.context->description()}};
            // The list's quality where some row reads it, as the rows give theirs (`--techniques
            // flat` reported "steps": 32 that the same run refused as a flag; found by an
            // exploratory session, fiftieth).
            const auto any_reads = [&](bool (*reads)(const DrawSettings&)) {
                return std::any_of(runs.begin(), runs.end(), [&](const auto& run) { return reads(run.settings); });
            };
            if (any_reads(reads_steps)) report["steps"] = s->quality.steps;
            if (any_reads(reads_refine)) report["refine"] = s->quality.refine;
            report.update(lighting_json(session.light, session.spec.mesh_options));
            write_file_atomic(s->json, report_text(report));
            std::printf("wrote %s\n", one_line(s->json).c_str());
        }
        return kExitOk;
    };
}

} // namespace pr
