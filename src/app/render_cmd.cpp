// prismrelief render: one scene, one technique, one PNG.
#include "app/commands.hpp"
#include "app/options.hpp"
#include "core/error.hpp"
#include "platform/context.hpp"
#include "render/renderer.hpp"

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
        const SceneSpec spec = make_scene_spec(s->scene);
        const DrawSettings settings = make_draw_settings(s->technique, s->technique.technique);
        if (s->out.empty()) throw Error("--out", "empty file name");
        // Inputs are read before any GL work, so bad files fail fast and without a context.
        const Scene scene = load_scene(spec);
        auto context = create_headless_context(parse_backend(s->scene.backend));
        Renderer renderer(spec.width, spec.height);
        renderer.upload(scene);
        const Camera camera = scene_camera(spec, scene);
        const double ms = renderer.draw(camera, scene_light(spec, camera), settings);
        const RgbaImage image = renderer.read_color();
        std::size_t covered = 0;
        for (std::size_t i = 3; i < image.pixels.size(); i += 4) covered += image.pixels[i] >= 128;
        write_png(s->out, image);
        std::printf("%s: %dx%d %s, %.1f ms, coverage %.1f%%\n", s->out.c_str(), spec.width, spec.height,
                    technique_name(settings.technique).c_str(), ms,
                    100.0 * double(covered) / double(std::size_t(spec.width) * spec.height));
        return kExitOk;
    };
}

} // namespace pr
