// prismrelief view: the interactive viewer (src/view/) on the renderer that render uses. Built
// only when GLFW 3 and Dear ImGui were found at configure time; otherwise it says so (exit 1).
#include "app/commands.hpp"
#include "app/session.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "render/shader_program.hpp"

#ifdef PRISMRELIEF_HAVE_VIEWER
#include "view/glfw_window.hpp"
#include "view/viewer.hpp"
#endif

#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <memory>

namespace pr {

CommandAction add_view_command(CLI::App& app)
{
    struct State {
        SceneOptions scene;
        TechniqueOptions technique;
        std::string split;
        float divider = 0.5f;
        std::string overlay = "none";
        bool reference_overlay = false;
        std::string screenshot;
        int frames = 0;
        std::string shader_dir;
        bool no_panel = false;
        bool screenshot_ui = false;
        float render_scale = 1.0f;
        std::vector<std::string> drops;
        // Given or not (CLI11's count): --split "" and --technique next to --split.
        const CLI::Option* split_flag = nullptr;
        const CLI::Option* technique_flag = nullptr;
        const CLI::Option* backend_flag = nullptr;
    };
    auto s = std::make_shared<State>();
    s->technique.technique = "pom"; // with split on: POM | prism
    // A mesh dropped on the window later is loaded with --uv-scale too, and may have no UVs.
    s->scene.more_meshes_later = true;
    CLI::App* cmd = app.add_subcommand(
        "view", "Interactive viewer (GLFW window, Dear ImGui panel): orbit, compare techniques side by side");
    add_scene_options(*cmd, s->scene);
    add_technique_options(*cmd, s->technique, true);
    s->technique_flag = cmd->get_option("--technique");
    s->backend_flag = cmd->get_option("--backend");
    // Refused (the window's context draws), so not listed with a default as if it worked (found by
    // a docs audit, thirty-fifth session); the footer says so.
    cmd->get_option("--backend")->group("");
    cmd->get_option("--cone-backend")
        ->description("Where cone maps missing from the cache are built: cpu (threads) or gpu (compute shader in "
                      "the window's context)");
    s->split_flag = cmd->add_option("--split", s->split,
                                    "Split-screen compare: A,B (left, right), e.g. pom,prism or pom,prism:cone")
                        ->group("View");
    // (Its numbers are checked as every other command's: --frames "" read as 0, interactive, and a
    // batch script with an unset variable never ended; "010" was octal, "0x3" three.)
    cmd->add_option("--divider", s->divider, "Split position, fraction of the width from the left")
        ->transform(a_number())
        ->group("View")
        ->capture_default_str();
    cmd->add_option("--overlay", s->overlay, "Wireframe overlay: none|base|shell")
        ->group("View")
        ->capture_default_str();
    cmd->add_flag("--reference-overlay", s->reference_overlay,
                  "Tint where the silhouette differs from the reference's (cyan missed, magenta extra)")
        ->group("View");
    cmd->add_option("--screenshot", s->screenshot,
                    "PNG of the view (RGBA, alpha = coverage, framebuffer pixels): written after --frames, "
                    "and by the P key")
        ->group("View"); // (an empty name: refuse_empty_file_names, exit 1 as for every file option)
    cmd->add_flag("--screenshot-ui", s->screenshot_ui,
                  "The screenshot shows the whole window as seen (panel, background; opaque)")
        ->group("View");
    cmd->add_option("--frames", s->frames, "Draw this many frames, print frame times, then exit (0: interactive; up to 1000000)")
        ->transform(saturating<int>())
        ->group("View")
        ->capture_default_str();
    cmd->add_option("--shader-dir", s->shader_dir,
                    "Read shaders from DIR (e.g. shaders/) and reload them when a file changes "
                    "(also PRISMRELIEF_SHADER_DIR)")
        ->group("View");
    cmd->add_option("--render-scale", s->render_scale,
                    "Renderer pixels per window pixel (0.25-1; below 1 is faster on llvmpipe, upscaled)")
        ->transform(a_number())
        ->group("View")
        ->capture_default_str();
    cmd->add_flag("--no-panel", s->no_panel, "Start with the panel hidden (H or Tab shows it)")->group("View");
    cmd->add_option("--drop", s->drops, "Load FILE after the first frame as if dropped on the window (tests)")
        ->group("View");
    cmd->footer("Mouse: left drag orbits, right/middle drag pans, wheel zooms, Ctrl+left drag moves the\n"
                "light, drag the divider in split view. Keys: 1-9,0 technique (Shift: right half), [ ]\n"
                "previous/next, M marcher, S split, W wireframe, D reference difference, R reset view,\n"
                "P screenshot, H/Tab panel, Q/Esc quit. --backend is refused (the window's context draws).\n"
                "Example:\n  prismrelief view --scene meshes/scenes/plane_and_torus.json --split pom,prism");

    return [s]() -> int {
#ifndef PRISMRELIEF_HAVE_VIEWER
        throw Error("view", "this build has no viewer (GLFW 3 and Dear ImGui were not found when it was "
                            "configured; install libglfw3-dev and libimgui-dev and build again)");
#else
        view::ViewerOptions o;
        // (Accepted and ignored until the twenty-fourth session, found by an exploratory session.)
        if (s->backend_flag->count() > 0)
            throw Error("--backend", "has no effect: view draws with its window's OpenGL context (GLFW); "
                                     "--backend picks the headless one of render, compare and bench");
        // The prism's flags as compare checks them, but that a half (or the technique) that is not
        // a prism keeps them for when the panel turns it to the prism (check_prism_flags_used). With
        // --split they went unchecked: a shell for an exit that has none, or a marcher that every
        // half names itself, ran; --technique was ignored, and --split "" ran unsplit.
        if (s->split_flag->count() > 0) {
            if (s->technique_flag->count() > 0)
                throw Error("--technique", "has no effect with --split (the halves are its two techniques)");
            const std::vector<TechniqueRun> runs = parse_technique_list(s->split, s->technique, "--split");
            if (runs.size() != 2) throw Error("--split", "expected two techniques A,B, got '" + s->split + "'");
            o.left = runs[0].settings;
            o.right = runs[1].settings;
        } else {
            o.left = make_draw_settings(s->technique, s->technique.technique); // (checks a prism's flags)
            if (o.left.technique != Technique::Prism)
                check_prism_flags_used(s->technique, {{s->technique.technique, o.left}},
                                       "--technique " + s->technique.technique, true);
        }
        // Unlike render, compare and bench, the viewer does not refuse --steps, --refine,
        // --normal-quality, --depth-write, --shadows or the reference's flags where the techniques
        // it starts with do not read them (check_quality_flags_apply): its panel and keys turn to
        // any technique (the reference, --reference-overlay's too) while it runs, and the flags
        // are the settings it starts them with. The reference's cap next to its level is refused
        // as render refuses it: the panel sets no level, so the cap could never act (it was taken;
        // found by an exploratory session, fifty-second).
        check_reference_flags_pair(s->technique);
        if (!(s->divider >= 0.0f && s->divider <= 1.0f)) throw Error("--divider", "must be between 0 and 1");
        o.divider = s->divider;
        o.overlay = view::parse_wire_overlay(s->overlay);
        if (!(s->render_scale >= 0.25f && s->render_scale <= 1.0f))
            throw Error("--render-scale", "must be between 0.25 and 1");
        o.render_scale = s->render_scale;
        o.reference_overlay = s->reference_overlay;
        o.reference = make_reference_options(s->technique);
        if (s->frames < 0 || s->frames > 1000000) throw Error("--frames", "must be between 0 and 1000000");
        o.frames = s->frames;
        if (!s->screenshot.empty()) check_png_output(s->screenshot);
        o.screenshot = s->screenshot;
        o.screenshot_ui = s->screenshot_ui;
        o.panel = !s->no_panel;
        o.drops = s->drops;
        if (!s->shader_dir.empty()) {
            if (!std::filesystem::is_directory(s->shader_dir))
                throw Error("--shader-dir", s->shader_dir + " is not a folder");
            // shader_program.cpp reads the sources from here from now on.
            setenv("PRISMRELIEF_SHADER_DIR", s->shader_dir.c_str(), 1);
            name_shader_dir("--shader-dir");
        }
        if (const char* dir = std::getenv("PRISMRELIEF_SHADER_DIR"); dir && *dir) o.shader_dir = dir;

        GlfwWindow* window = nullptr;
        const auto open_window = [&](const SceneSpec& spec) -> std::unique_ptr<Context> {
            auto w = GlfwWindow::open(spec.width, spec.height, "prismrelief view");
            window = w.get();
            return w;
        };
        // A dropped file is an input too: `--drop h.png --screenshot h.png` replaced the height map
        // just loaded with the screenshot.
        std::vector<NamedPath> inputs;
        for (const std::string& file : s->drops) inputs.emplace_back("--drop", file);
        // The shaders under --shader-dir by that name (open_session names the variable, which is
        // set from it: "is the PRISMRELIEF_SHADER_DIR input" named a variable that was not set).
        if (!s->shader_dir.empty())
            for (NamedPath& shader : shader_override_inputs()) inputs.emplace_back("--shader-dir", std::move(shader.second));
        check_distinct_outputs({{"--screenshot", s->screenshot}}, inputs);
        Session session = open_session(s->scene, {{"--screenshot", s->screenshot}}, open_window);
        release_warnings(); // every input accepted (core/error.hpp): the window shows them from here
        // (A script that meant a batch run waited for ever without a word; found by an exploratory
        // session. Said once the window is open: a run refused before said it too, in the
        // thirty-third session's docs audit.)
        if (!s->screenshot.empty() && s->frames == 0)
            std::printf("view: without --frames the window stays open: P writes %s, Q quits\n", one_line(s->screenshot).c_str());
        return view::run_viewer(session, *window, o);
#endif
    };
}

} // namespace pr
