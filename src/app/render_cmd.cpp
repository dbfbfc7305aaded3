// prismrelief render: one scene, one technique, one PNG.
#include "app/commands.hpp"
#include "app/session.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"

#include <cstdio>
#include <memory>

namespace pr {

CommandAction add_render_command(CLI::App& app)
{
    struct State {
        SceneOptions scene;
        TechniqueOptions technique;
        std::string out;
    };
    auto s = std::make_shared<State>();
    CLI::App* cmd = app.add_subcommand("render", "Render a scene with one technique to a PNG (RGBA, alpha = coverage)");
    add_scene_options(*cmd, s->scene);
    add_technique_options(*cmd, s->technique, true);
    cmd->add_option("--out", s->out, "Output PNG file")->required()->group("Output");
    cmd->footer("Example:\n  prismrelief render --mesh meshes/torus.obj --height builtin:bricks "
                "--technique pom --out out/torus.png");

    return [s]() {
        const DrawSettings settings = make_draw_settings(s->technique, s->technique.technique);
        const ReferenceOptions ref = make_reference_options(s->technique);
        check_png_output(s->out);
        check_distinct_outputs({{"--out", s->out}}, scene_inputs(s->scene));
        Session session = open_session(s->scene);
        Renderer& renderer = *session.renderer;
        if (settings.technique == Technique::Reference) {
            const auto stats = renderer.prepare_reference(session.scene, session.camera, ref);
            std::printf("reference: level %d, %zu triangles, %.1f MB, built in %.0f ms%s\n", stats.level,
                        stats.triangles, double(stats.bytes) / 1e6, stats.build_ms,
                        stats.capped ? " (level capped by --reference-max-triangles)" : "");
        }
        // The first draw of a shader variant includes llvmpipe's compile of it (up to about a
        // second); a second draw gives the frame's own time (contract: without loading), when the
        // first was short enough that drawing again costs little. The image is the same.
        const double first_ms = renderer.draw(session.camera, session.light, settings);
        const bool again = first_ms < 2000.0;
        const double ms = again ? renderer.draw(session.camera, session.light, settings) : first_ms;
        const RgbaImage image = renderer.read_color();
        std::size_t covered = 0;
        for (std::size_t i = 3; i < image.pixels.size(); i += 4) covered += image.pixels[i] >= 128;
        write_png(s->out, image);
        // A few covered pixels of a large image are not "0.0%": more digits then.
        const double percent = 100.0 * double(covered) / double(std::size_t(image.width) * image.height);
        std::printf("%s: %dx%d %s, %.1f ms%s, coverage %.*f%%\n", s->out.c_str(), image.width, image.height,
                    technique_name(settings.technique).c_str(), ms, again ? "" : " (first draw, with compiling)",
                    covered > 0 && percent < 0.1 ? 4 : 1, percent);
        return kExitOk;
    };
}

} // namespace pr
