#pragma once
// One function per subcommand: each registers its options on the parser and returns the action
// to run after parsing.
#include "app/options.hpp"
#include "core/atomic_file.hpp"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <exception>
#include <functional>
#include <string>
#include <vector>

namespace pr {

using CommandAction = std::function<int()>;

CommandAction add_render_command(CLI::App& app);
CommandAction add_compare_command(CLI::App& app);
CommandAction add_bench_command(CLI::App& app);
CommandAction add_conemap_command(CLI::App& app); // conemap_cmd.cpp
CommandAction add_view_command(CLI::App& app);    // view_cmd.cpp

// A report row's description of a prism run beyond its label: the marcher, exit and shell it
// used (a label "prism" does not say which: --marcher, --prism-exit and --prism-shell set them).
// Empty for the other techniques.
inline nlohmann::json prism_configuration(const DrawSettings& s)
{
    if (s.technique != Technique::Prism) return nlohmann::json::object();
    return {{"marcher", marcher_name(s.marcher)},
            {"prism_exit", prism_exit_name(s.prism_exit)},
            {"prism_shell", s.full_shell || s.prism_exit != PrismExit::Walk ? "full" : "tight"}}; // (other exits: full)
}

// The files a command reads, for check_distinct_outputs(): an output must not overwrite one of
// them. Those a scene file names count too, found as the scene's loader finds them (make_scene_spec:
// relative to the scene file's folder) and named by their place in it ("s.json: objects[0].height"),
// unless a flag replaces them (then they are not read). A scene file that cannot be read adds
// none: its error comes, as it would have, when the scene is loaded.
inline std::vector<NamedPath> scene_inputs(const SceneOptions& s)
{
    std::vector<NamedPath> inputs = {
        {"--scene", s.scene_file}, {"--mesh", s.mesh}, {"--height", s.height.value_or("")}, {"--color", s.color}};
    if (s.scene_file.empty()) return inputs;
    SceneOptions file_only; // the file's values, not checked against the flags
    file_only.scene_file = s.scene_file;
    SceneSpec spec;
    try {
        spec = make_scene_spec(file_only);
    } catch (const std::exception&) {
        return inputs;
    }
    for (std::size_t i = 0; i < spec.objects.size(); ++i) {
        const ObjectSpec& o = spec.objects[i];
        const std::string at = s.scene_file + ": objects[" + std::to_string(i) + "].";
        if (s.mesh.empty()) inputs.emplace_back(at + "mesh", o.mesh);
        if (!s.height) inputs.emplace_back(at + "height", o.height); // (the default is builtin:bumps)
        if (s.color.empty()) inputs.emplace_back(at + "color", o.color);
    }
    return inputs;
}

} // namespace pr
