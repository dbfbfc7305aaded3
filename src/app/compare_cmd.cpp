// prismrelief compare: every listed technique against the reference (true displaced geometry),
// as a labelled grid PNG, a JSON report and a table on the terminal.
#include "app/commands.hpp"
#include "app/session.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "eval/grid.hpp"
#include "eval/metrics.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <iterator>
#include <optional>

namespace pr {

namespace {

// Fewer covered pixels in the reference than this: compare says its metrics rest on too few.
constexpr std::size_t kFewReferencePixels = 100;

// A depth error in the table: 5 decimals, or 3 significant digits under 0.001 (at 5 decimals a
// scene a thousandth of a unit across, or the prism's 4e-6 on the bundled meshes, read 0.00000,
// as the reference's exact 0 does; found by an exploratory session, thirty-sixth).
std::string depth_text(double v)
{
    if (v == 0.0 || std::abs(v) >= 1e-3) return fixed(v, 5);
    return fmt::format("{:.2e}", v);
}

FrameCapture capture(Session& s, const DrawSettings& settings, double& ms)
{
    Renderer& r = *s.renderer;
    r.draw(s.camera, s.light, settings); // first draw of a variant includes llvmpipe's JIT
    ms = r.draw(s.camera, s.light, settings);
    FrameCapture c;
    c.color = r.read_color();
    c.depth = r.read_depth();
    c.camera = s.camera;
    return c;
}

nlohmann::json optional_number(const std::optional<double>& v)
{
    return v ? nlohmann::json(*v) : nlohmann::json(nullptr);
}

} // namespace

CommandAction add_compare_command(CLI::App& app)
{
    struct State {
        SceneOptions scene;
        TechniqueOptions quality;
        std::string out;
        std::string json;
        std::string tiles;
    };
    auto s = std::make_shared<State>();
    s->quality.techniques = "flat,pom,relief";
    CLI::App* cmd = app.add_subcommand(
        "compare", "Compare techniques with the reference (true displaced geometry): grid PNG, JSON, table");
    add_scene_options(*cmd, s->scene);
    add_technique_options(*cmd, s->quality, false);
    cmd->add_option("--out", s->out, "Grid PNG: each technique, and its silhouette difference to the reference")
        ->group("Output");
    cmd->add_option("--json", s->json, "JSON report (see docs/compare.md)")->group("Output");
    cmd->add_option("--tiles", s->tiles,
                    "Existing folder for each image alone, as render writes it (RGBA, alpha = coverage): "
                    "reference.png and one per technique, named as in the list with ':' as '_'")
        ->group("Output");
    cmd->footer("Silhouette-difference tiles: magenta = covered only by the technique, cyan = only by the\n"
                "reference. Metrics are the contract's (docs/compare.md).");

    return [s]() {
        std::vector<TechniqueRun> runs = parse_technique_list(s->quality.techniques, s->quality);
        const ReferenceOptions ref_options = make_reference_options(s->quality);
        // The reference is drawn too, with the same flags: it reads --normal-quality and the
        // reference's own flags, whatever the list.
        const DrawSettings ref_settings = make_draw_settings(s->quality, "reference");
        {
            std::vector<DrawSettings> drawn = {ref_settings};
            for (const TechniqueRun& run : runs) drawn.push_back(run.settings);
            check_quality_flags_apply(s->quality, drawn, "--techniques " + s->quality.techniques);
            s->scene.reads_cone_maps =
                check_cone_map_flags_apply(s->scene, drawn, with_prism_flags(s->quality, "--techniques " + s->quality.techniques));
        }
        if (!s->out.empty()) check_png_output(s->out);
        if (!s->json.empty()) check_output_folder(s->json);
        std::vector<NamedPath> outputs = {{"--out", s->out}, {"--json", s->json}};
        // Each image alone (the grid's tiles sit over a checker, with labels): tile_files[0] is
        // the reference's, then one per listed technique other than the reference itself.
        std::vector<std::filesystem::path> tile_files;
        if (!s->tiles.empty()) {
            std::error_code ec;
            if (!std::filesystem::is_directory(s->tiles, ec))
                throw Error("--tiles", s->tiles + (std::filesystem::exists(s->tiles, ec) ? " is not a folder"
                                                                                           : " does not exist"));
            const auto tile = [&](std::string name) {
                std::replace(name.begin(), name.end(), ':', '_');
                tile_files.push_back(std::filesystem::path(s->tiles) / (name + ".png"));
                check_png_output(tile_files.back());
                outputs.emplace_back("--tiles", tile_files.back());
            };
            tile("reference");
            for (const TechniqueRun& run : runs)
                if (run.settings.technique != Technique::Reference) tile(run.label);
        }
        // The grid's size before anything is loaded or drawn: past what the PNG encoder takes it
        // failed after every technique was drawn, or ran out of memory first (found by an
        // exploratory session).
        const auto check_grid = [&](const SceneSpec& spec) {
            if (s->out.empty()) return;
            const Tile cell{"name\nIoU", RgbaImage{spec.width, spec.height, {}}};
            const GridLayout grid = plan_grid(std::vector<Tile>(2 * (runs.size() + 1), cell), int(runs.size() + 1));
            if (!png_encodable(grid.width, grid.height))
                throw Error("--out", fmt::format("the grid would be {}x{} pixels, more than the PNG encoder takes (2 GiB of "
                                                 "rows): give fewer --techniques or a smaller --size, or only --tiles "
                                                 "and --json",
                                                 grid.width, grid.height));
        };
        Session session = open_session(s->scene, outputs, {}, check_grid);
        for (const TechniqueRun& run : runs) session.renderer->check_drawable(run.settings, "--techniques");
        release_warnings(); // every input accepted (core/error.hpp)

        const auto ref_stats = session.renderer->prepare_reference(session.scene, session.camera, ref_options);
        warn_if_capped(ref_stats, "compare");
        double ref_ms = 0.0;
        const FrameCapture reference = capture(session, ref_settings, ref_ms);
        warn_if_shadow_map_coarse(session.renderer->shadow_fit(), "compare");

        // The grid's cells are kept for --out alone, and each tile is staged (written to its
        // temporary) as soon as it is drawn: with --json alone every technique's image and its
        // silhouette diff were kept to the end, 8 bytes a pixel each (16384 x 16384: 2.1 GB a
        // technique; found by an exploratory session, fifty-second).
        const bool grid_wanted = !s->out.empty();
        std::vector<std::unique_ptr<StagedFile>> tiles;
        const auto stage_tile = [&](const RgbaImage& image) {
            const std::filesystem::path& file = tile_files[tiles.size()];
            tiles.push_back(std::make_unique<StagedFile>(file, encode_png_for(file, image)));
        };
        if (!tile_files.empty()) stage_tile(reference.color);
        std::vector<Tile> top, bottom;
        if (grid_wanted) {
            top.push_back({"reference", reference.color});
            bottom.push_back({"silhouette diff", reference.color});
            for (auto& p : bottom[0].image.pixels) p = 0; // an empty tile under the reference: legend only
        }
        bool nothing_drawn = drew_nothing(reference.color); // by the reference and every technique
        bool technique_covers = false; // a technique covers a pixel (alpha of one half or more, as the metrics count)
        // A reference of a few pixels: each is a large share of the IoU, and the depth error and
        // PSNR rest on as few. At such a size every technique samples the height map far below its
        // texels, so the numbers compare aliasing (an object a few pixels across, in a 3x3 image
        // or 150 units off, reported as any other; found by an exploratory session, thirty-fifth).
        const std::size_t reference_px = covered_pixels(reference.color);
        if (reference_px > 0 && reference_px < kFewReferencePixels)
            warn(fmt::format("compare: the reference covers {} pixel{}: one pixel more or less moves the IoU by about "
                             "{:.3g} %, and the other metrics rest on as few (a larger --size, or the camera closer)",
                             reference_px, reference_px == 1 ? "" : "s", 100.0 / double(reference_px)));
        nlohmann::json results = nlohmann::json::array();
        // The names' column as wide as the longest ("prism:relief:exact" pushed the row out of line).
        int name_width = 14;
        for (const TechniqueRun& run : runs) name_width = std::max(name_width, int(run.label.size()));
        std::printf("%-*s %8s %10s %12s %12s %8s %9s\n", name_width, "technique", "iou", "sil_wrong", "depth_mean",
                    "depth_max", "psnr", "ms");
        for (const TechniqueRun& run : runs) {
            double ms = ref_ms;
            const FrameCapture frame = run.settings.technique == Technique::Reference
                                           ? reference
                                           : capture(session, run.settings, ms);
            const CompareMetrics m = compare_frames(frame, reference);
            nothing_drawn = nothing_drawn && drew_nothing(frame.color);
            technique_covers = technique_covers || covered_pixels(frame.color) > 0;
            nlohmann::json row = {{"technique", run.label},
                                  {"iou", m.iou},
                                  {"silhouette_wrong_px", m.silhouette_wrong_px},
                                  {"only_in_technique_px", m.only_in_technique},
                                  {"only_in_reference_px", m.only_in_reference},
                                  {"both_px", m.both},
                                  {"depth_error_mean", optional_number(m.depth_error_mean)},
                                  {"depth_error_max", optional_number(m.depth_error_max)},
                                  {"depth_error_median", optional_number(m.depth_error_median)},
                                  {"psnr", optional_number(m.psnr)},
                                  {"identical", m.identical},
                                  {"ms", ms}};
            row.update(quality_json(run.settings));
            row.update(prism_configuration(run.settings));
            row.update(shadows_json(run.settings));
            results.push_back(row);
            std::printf("%-*s %8s %10zu %12s %12s %8s %9.2f\n", name_width, run.label.c_str(), iou_text(m.iou).c_str(),
                        m.silhouette_wrong_px,
                        m.depth_error_mean ? depth_text(*m.depth_error_mean).c_str() : "-",
                        m.depth_error_max ? depth_text(*m.depth_error_max).c_str() : "-",
                        m.psnr ? fixed(*m.psnr, 2).c_str() : (m.identical ? "same" : (m.both > 0 ? "inf" : "-")), ms);
            // The name and the IoU on lines of their own, each cut at the strip's end where it is
            // too long (on one line, at 128 px the IoU of "prism:max-mip" read "IoU 0"; with the
            // number first, at 256 px "prism:relaxed-cone" read "prism:re").
            if (!tile_files.empty() && run.settings.technique != Technique::Reference) stage_tile(frame.color);
            if (grid_wanted) {
                top.push_back({run.label + "\nIoU " + iou_text(m.iou), frame.color});
                bottom.push_back({std::to_string(m.silhouette_wrong_px) + " px wrong",
                                  silhouette_diff_tile(frame.color, reference.color)});
            }
        }

        nlohmann::json report = {
            {"results", results},
            {"reference", [&] {
                 nlohmann::json r = reference_json(ref_stats);
                 r["ms"] = ref_ms;
                 r["covered_px"] = reference_px;
                 r.update(shadows_json(ref_settings));
                 return r;
             }()},
            {"size", {session.spec.width, session.spec.height}},
            {"objects", scene_json(session.scene)},
            {"camera", camera_json(session.camera)},
            {"renderer", session.context->description()}};
        report.update(lighting_json(session.light, session.spec.mesh_options));
        // Both outputs staged before either replaces a file: a failure leaves both as they were.
        std::optional<StagedFile> grid, json;
        // (The grid takes the images over instead of copying them: a copy of every image at once,
        // 9 techniques at 4096², was another 1.2 GB.)
        if (grid_wanted) {
            const int columns = static_cast<int>(top.size());
            std::vector<Tile> cells = std::move(top);
            cells.insert(cells.end(), std::make_move_iterator(bottom.begin()), std::make_move_iterator(bottom.end()));
            grid.emplace(s->out, encode_png_for(s->out, compose_grid(cells, columns)));
        }
        if (!s->json.empty()) json.emplace(s->json, report_text(report));
        std::vector<StagedFile*> staged = {grid ? &*grid : nullptr, json ? &*json : nullptr};
        for (const auto& t : tiles) staged.push_back(t.get());
        commit_together(staged);
        // Every metric then compares two empty images: IoU 1 (the contract's, for an empty union)
        // and "same" are true, and mean nothing.
        if (nothing_drawn) warn_nothing_drawn("compare");
        // No reference at all, but a technique drew (the eye between the base surface and the
        // displaced one, or inside the shell): every pixel a technique covers counts as wrong,
        // and neither depth error nor PSNR has a value (forty-first session: said nothing, the
        // few-pixels warning above starts at one; found by an audit).
        // (Covered as the metrics count it: with --msaa a reference of slivers alone drew
        // something and covered nothing.)
        else if (reference_px == 0 && technique_covers)
            warn("compare: the reference covers no pixel, the techniques do: each pixel they cover counts as "
                 "wrong, and depth error and PSNR have no value (the camera may be inside the shell or under the "
                 "displaced surface)");
        if (!s->out.empty()) std::printf("wrote %s\n", one_line(s->out).c_str());
        if (!s->json.empty()) std::printf("wrote %s\n", one_line(s->json).c_str());
        if (!tile_files.empty()) std::printf("wrote %zu tile%s in %s\n", tile_files.size(), tile_files.size() == 1 ? "" : "s",
                                             one_line(s->tiles).c_str());
        return kExitOk;
    };
}

} // namespace pr
