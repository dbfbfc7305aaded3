// prismrelief render: one scene, one technique, one PNG.
#include "app/commands.hpp"
#include "app/progress.hpp"
#include "app/session.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/image.hpp"
#include "core/number_text.hpp"
#include "render/multisample.hpp"

#include <cstdio>
#include <memory>
#include <optional>

namespace pr {

CommandAction add_render_command(CLI::App& app)
{
    struct State {
        SceneOptions scene;
        TechniqueOptions technique;
        std::string out;
        std::string json;
        int msaa = 1;
        std::string msaa_typed; // --msaa past an int, as typed (saturating)
    };
    auto s = std::make_shared<State>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene with one technique to a PNG (RGBA, alpha = coverage)");
    add_scene_options(*cmd, s->scene);
    add_technique_options(*cmd, s->technique, true);
    cmd->add_option("--out", s->out, "Output PNG file")->required()->group("Output");
    cmd->add_option("--json", s->json,
                    "JSON report: technique and its configuration, time, coverage, camera (README, \"Output\")")
        ->group("Output");
    cmd->add_option("--msaa", s->msaa,
                    "Samples per pixel: 1 (pixel centres), 2, 4, 8 or 16 (standard positions, one pass "
                    "each; alpha = the fraction covered)")
        ->transform(saturating<int>(&s->msaa_typed))
        ->group("Output")
        ->capture_default_str();
    cmd->footer("Example:\n  prismrelief render --mesh meshes/torus.obj --height builtin:bricks "
                "--technique pom --out out/torus.png");

    return [s]() {
        const DrawSettings settings = make_draw_settings(s->technique, s->technique.technique);
        check_prism_flags_apply(s->technique, settings.technique == Technique::Prism,
                                "--technique " + s->technique.technique);
        const ReferenceOptions ref = make_reference_options(s->technique);
        check_quality_flags_apply(s->technique, {settings}, "--technique " + s->technique.technique);
        s->scene.reads_cone_maps =
            check_cone_map_flags_apply(s->scene, {settings}, with_prism_flags(s->technique, "--technique " + s->technique.technique));
        const std::span<const glm::vec2> offsets = sample_offsets(s->msaa, s->msaa_typed); // refuses other counts, naming --msaa
        check_png_output(s->out);
        if (!s->json.empty()) check_output_folder(s->json);
        Session session = open_session(s->scene, {{"--out", s->out}, {"--json", s->json}});
        Renderer& renderer = *session.renderer;
        renderer.check_drawable(settings);
        release_warnings(); // every input accepted (core/error.hpp)
        Renderer::ReferenceStats stats;
        if (settings.technique == Technique::Reference) {
            stats = renderer.prepare_reference(session.scene, session.camera, ref);
            const std::string capped =
                stats.capped ? " (" + (stats.levels.size() <= 1 ? std::string("level") : reference_capped_text(stats)) +
                                   " capped by --reference-max-triangles)"
                             : "";
            std::printf("reference: %s, %zu triangles, %.1f MB, built in %.0f ms%s\n", reference_levels_text(stats).c_str(),
                        stats.triangles, double(stats.bytes) / 1e6, stats.build_ms, capped.c_str());
        }
        // The first draw of a shader variant includes llvmpipe's compile of it (up to about a
        // second); a second draw gives the frame's own time (contract: without loading), when the
        // first was short enough that drawing again costs little. The image is the same. With
        // --msaa, the frame is its passes, one per sample, after the first pass drawn to compile.
        // (A bar, or off a terminal a note after 10 s, over the passes: 4096² at --msaa 16 drew
        // for a minute without a word; found by an exploratory session, forty-fourth.)
        ProgressBar bar("render");
        const double steps = double(offsets.size() + 1);
        DrawSettings pass = settings;
        pass.pixel_offset = offsets[0];
        const double first_ms = renderer.draw(session.camera, session.light, pass);
        bar(1.0 / steps);
        const bool again = first_ms < 2000.0;
        double ms = again ? 0.0 : first_ms;
        SampleResolve resolve;
        for (std::size_t k = 0; k < offsets.size(); ++k) {
            pass.pixel_offset = offsets[k];
            if (again || k > 0) ms += renderer.draw(session.camera, session.light, pass);
            if (offsets.size() > 1) resolve.add(renderer.read_color());
            bar(double(k + 2) / steps);
        }
        bar.clear();
        const RgbaImage image = offsets.size() > 1 ? resolve.result() : renderer.read_color();
        if (settings.technique == Technique::Reference) warn_if_shadow_map_coarse(renderer.shadow_fit(), "render");
        // Covered pixels (alpha >= 128), and whether any alpha at all: an empty picture is a valid
        // one (a view away from the scene), but rarely the one meant (with --msaa a sliver may
        // cover a fraction of a pixel: any alpha counts).
        const std::size_t covered = covered_pixels(image);
        const bool any = !drew_nothing(image);
        const std::size_t pixels = std::size_t(image.width) * image.height;
        // Both outputs staged before either replaces a file: a failure leaves both as they were.
        StagedFile png(s->out, encode_png_for(s->out, image));
        std::optional<StagedFile> json;
        if (!s->json.empty()) {
            nlohmann::json report = {{"technique", s->technique.technique},
                                     {"configuration", configuration_name(settings)},
                                     {"out", s->out},
                                     {"size", {image.width, image.height}},
                                     {"msaa", offsets.size()},
                                     {"ms", ms},
                                     {"first_draw_compiled", !again},
                                     {"covered_px", covered},
                                     {"coverage", double(covered) / double(pixels)},
                                     {"camera", camera_json(session.camera)},
                                     {"objects", scene_json(session.scene)},
                                     {"renderer", session.context->description()}};
            report.update(quality_json(settings));
            report.update(prism_configuration(settings));
            report.update(shadows_json(settings));
            report.update(lighting_json(session.light, session.spec.mesh_options));
            if (settings.technique == Technique::Reference) report["reference"] = reference_json(stats);
            // An object whose shell the prism found too thin to draw (its base mesh drawn, with a
            // warning): the report gave the depth asked for alone (found by an exploratory
            // session, fifty-second).
            if (settings.technique == Technique::Prism)
                for (std::size_t k = 0; k < report["objects"].size(); ++k)
                    if (renderer.prism_shell_too_thin(k)) report["objects"][k]["prism_shell_too_thin"] = true;
            json.emplace(s->json, report_text(report));
        }
        commit_together({&png, json ? &*json : nullptr});
        if (!any) warn_nothing_drawn(s->out);
        // A few covered pixels of a large image are not "0.0%", nor all but a few "100.0%": more
        // digits then (one pixel of 2047² read 0.0000%, 65534 of 65536 100.0%; found by an
        // exploratory session, thirty-fourth).
        const double fraction = 100.0 * double(covered) / double(pixels);
        const std::string percent = bounded_text(fraction, covered > 0 && fraction < 0.1 ? 4 : 1, 0.0, 100.0);
        const std::string passes = offsets.size() > 1 ? " (" + std::to_string(offsets.size()) + " passes)" : "";
        std::printf("%s: %dx%d %s, %.1f ms%s%s, coverage %s%%\n", one_line(s->out).c_str(), image.width, image.height,
                    configuration_name(settings).c_str(), ms, passes.c_str(),
                    again ? "" : " (first draw, with compiling)", percent.c_str());
        if (!s->json.empty()) std::printf("wrote %s\n", one_line(s->json).c_str());
        return kExitOk;
    };
}

} // namespace pr
