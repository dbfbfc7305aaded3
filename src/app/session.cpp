#include "app/session.hpp"

#include "app/commands.hpp"
#include "app/progress.hpp"
#include "core/error.hpp"
#include "maps/conemap.hpp"
#include "render/shader_program.hpp"

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>

namespace pr {

namespace {

// The files the scene file names, by their place in it ("s.json: objects[0].height"), unless a
// flag replaced them: from the spec already made, so that the scene file is read once (a second
// read of `--scene <(cat s.json)` found the pipe empty).
std::vector<NamedPath> scene_file_inputs(const SceneOptions& options, const SceneSpec& spec)
{
    std::vector<NamedPath> inputs;
    if (options.scene_file.empty()) return inputs;
    for (std::size_t i = 0; i < spec.objects.size(); ++i) {
        const ObjectSpec& o = spec.objects[i];
        const std::string at = options.scene_file + ": objects[" + std::to_string(i) + "].";
        if (options.mesh.empty()) inputs.emplace_back(at + "mesh", o.mesh);
        if (!options.height) inputs.emplace_back(at + "height", o.height); // (the default is builtin:bumps)
        if (options.color.empty()) inputs.emplace_back(at + "color", o.color);
    }
    return inputs;
}

} // namespace

Session open_session(const SceneOptions& options, const std::vector<NamedPath>& outputs,
                     const ContextFactory& make_context, const SpecCheck& check_spec)
{
    check_cache_flags(options.no_cache, options.cache_dir);
    Session s;
    const bool cone_maps_on_gpu = parse_cone_backend_gpu(options.cone_backend, "--cone-backend");
    // The flags' files before the scene file is read (an output over it is refused unread), the
    // files it names once it is.
    std::vector<NamedPath> inputs = {{"--scene", options.scene_file},
                                     {"--mesh", options.mesh},
                                     {"--height", options.height.value_or("")},
                                     {"--color", options.color}};
    for (NamedPath& shader : shader_override_inputs()) inputs.push_back(std::move(shader));
    check_distinct_outputs(outputs, inputs);
    // (Only where the run may create the cache: a relief render was refused an --out in the
    // default cache's place, "which the run creates"; found by an exploratory session, thirty-sixth.)
    if (!options.no_cache && options.reads_cone_maps) check_outputs_outside_cache(outputs, options.cache_dir);
    s.spec = make_scene_spec(options);
    check_distinct_outputs(outputs, scene_file_inputs(options, s.spec));
    if (check_spec) check_spec(s.spec);
    const Backend backend = parse_backend(options.backend);
    if (!make_context) preload_backend(backend); // loads Mesa while the scene is read
    s.scene = load_scene(s.spec);
    // --uv-scale sizes generated UVs only: where every mesh has its own (and --generate-uvs does
    // not replace them), it was ignored silently. Known once the meshes are read, before any GL.
    const bool uv_scale_given = options.uv_scale_option != nullptr && options.uv_scale_option->count() > 0;
    if (uv_scale_given && !options.generate_uvs && !options.more_meshes_later &&
        std::all_of(s.scene.objects.begin(), s.scene.objects.end(), [](const SceneObject& o) { return o.mesh.had_uvs; }))
        throw Error("--uv-scale", std::string("has no effect: ") +
                                      (s.scene.objects.size() > 1 ? "every mesh has" : "the mesh has") +
                                      " UVs of its own (it sizes generated ones; --generate-uvs generates them "
                                      "instead of the file's)");
    s.camera = scene_camera(s.spec, s.scene); // before the context: a bad camera fails fast, without GL
    s.light = scene_light(s.spec, s.camera);
    s.context = make_context ? make_context(s.spec) : create_headless_context(backend);
    s.renderer = std::make_unique<Renderer>(s.spec.width, s.spec.height);
    if (!options.cache_dir.empty()) s.renderer->set_cache_dir(options.cache_dir);
    if (options.no_cache) s.renderer->disable_cache();
    s.renderer->set_cone_maps_on_gpu(cone_maps_on_gpu);
    // A cone map built on first use can take seconds (a relaxed map of 1024²: about 8 s on two
    // cores): a bar on a terminal says what the wait is for.
    auto progress = std::make_shared<TaskProgress>();
    s.renderer->set_cone_progress([progress](const std::string& what, double f) { (*progress)(what, f); });
    s.renderer->upload(s.scene);
    return s;
}

void check_prism_flags_used(const TechniqueOptions& quality, const std::vector<TechniqueRun>& runs,
                            const std::string& drawn, bool panel)
{
    const CLI::Option* flags[3] = {quality.marcher_flag, quality.prism_exit_flag, quality.prism_shell_flag};
    const char* what[3] = {"marcher", "exit", "shell"};
    // How many of the marcher, exit and shell an entry names itself (prism:cone:walk: two); the
    // flags give it the rest.
    const auto named = [](const TechniqueRun& r) {
        return std::size_t(std::count(r.label.begin(), r.label.end(), ':'));
    };
    // The value an entry draws with, and the flag's, as text.
    const auto value = [](const DrawSettings& s, int k) {
        return k == 0 ? marcher_name(s.marcher)
               : k == 1 ? prism_exit_name(s.prism_exit)
                        : std::string(s.full_shell ? "full" : "tight");
    };
    const std::string flagged[3] = {quality.marcher, quality.prism_exit, quality.prism_shell};
    for (int k = 0; k < 3; ++k) {
        if (flags[k] == nullptr || flags[k]->count() == 0) continue;
        const bool used = std::any_of(runs.begin(), runs.end(), [&](const TechniqueRun& r) {
            const bool prism = r.settings.technique == Technique::Prism;
            return (prism || panel) && named(r) <= std::size_t(k) &&
                   (k < 2 || r.settings.prism_exit == PrismExit::Walk);
        });
        if (used) continue;
        // No entry takes it, because every prism names its own value: a flag that says what each
        // of those names says is redundant, and taken as render takes "prism:cone --marcher cone";
        // one that says otherwise is refused (the names won, silently), as render refuses
        // "prism:cone --marcher relief".
        const auto names_it = [&](const TechniqueRun& r) {
            return r.settings.technique == Technique::Prism && named(r) > std::size_t(k);
        };
        const auto other = std::find_if(runs.begin(), runs.end(), [&](const TechniqueRun& r) {
            return names_it(r) && value(r.settings, k) != flagged[k];
        });
        if (other == runs.end() && std::any_of(runs.begin(), runs.end(), names_it)) continue;
        // A name that says otherwise: the words of render's refusal (make_draw_settings).
        if (other != runs.end())
            throw Error(flags[k]->get_name(), "'" + other->label + "' in " + drawn + " names the " + what[k] + " " +
                                                  value(other->settings, k) + ", " + flags[k]->get_name() + " " +
                                                  flagged[k] + ": give one");
        // In the viewer an entry that takes the exit from --prism-exit would take the shell too,
        // but for that exit: the message of a single prism (make_draw_settings).
        const bool flag_exit = panel && std::any_of(runs.begin(), runs.end(), [&](const TechniqueRun& r) {
            return r.settings.technique != Technique::Prism || named(r) <= 1;
        });
        if (k == 2 && flag_exit)
            throw Error(flags[k]->get_name(), "only the walk takes a shell (the exit is " + quality.prism_exit + ")");
        throw Error(flags[k]->get_name(),
                    (k < 2 ? "has no effect: every prism in " + drawn + " names its own " + what[k]
                           : "has no effect: no prism in " + drawn +
                                 " takes it (each names its own shell, or an exit that has none)"));
    }
}

std::vector<TechniqueRun> parse_technique_list(const std::string& list, const TechniqueOptions& quality,
                                               const std::string& option)
{
    std::vector<TechniqueRun> runs;
    std::istringstream in(list);
    std::string item;
    // (getline yields no empty item after a final comma: "pom," ran pom alone.)
    if (!list.empty() && list.back() == ',') throw Error(option, "empty entry in '" + list + "'");
    while (std::getline(in, item, ',')) {
        if (item.empty()) throw Error(option, "empty entry in '" + list + "'");
        TechniqueRun run{item, make_draw_settings(quality, item, option)};
        for (const TechniqueRun& r : runs) {
            if (r.label == item) throw Error(option, "'" + item + "' is listed twice");
            // Different names of one configuration ("prism" and "prism:relief:walk:tight" with
            // the default flags) would draw the same thing twice.
            const DrawSettings &a = r.settings, &b = run.settings;
            const bool same = a.technique == b.technique &&
                              (a.technique != Technique::Prism ||
                               prism_configuration(a) == prism_configuration(b));
            if (same) throw Error(option, "'" + item + "' draws the same as '" + r.label + "', listed before it");
        }
        runs.push_back(std::move(run));
    }
    if (runs.empty()) throw Error(option, "no technique given");
    // A prism flag with no prism in the list (check_prism_flags_apply, as render's), or one that
    // every prism entry overrides by naming its own value (prism:cone with --marcher relief), did
    // nothing, silently. The viewer's --split is checked the same way, but for its panel
    // (check_prism_flags_used): it ran with such flags, and with a shell for an exit that has none.
    if (option == "--techniques" || option == "--split") {
        const std::string drawn = option + " " + list;
        const bool panel = option == "--split";
        if (!panel) {
            const bool any_prism = std::any_of(runs.begin(), runs.end(), [](const TechniqueRun& r) {
                return r.settings.technique == Technique::Prism;
            });
            check_prism_flags_apply(quality, any_prism, drawn);
        }
        check_prism_flags_used(quality, runs, drawn, panel);
    }
    return runs;
}

} // namespace pr
