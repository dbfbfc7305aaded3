#pragma once
// What render, compare and bench share: the spec from the flags, the loaded scene, a context,
// the renderer with the scene uploaded, the camera and the light.
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "platform/context.hpp"
#include "render/renderer.hpp"

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pr {

struct Session {
    SceneSpec spec;
    Scene scene;
    std::unique_ptr<Context> context;
    std::unique_ptr<Renderer> renderer;
    Camera camera;
    glm::vec3 light{0.0f, 1.0f, 0.0f};
};

// Makes the GL context once the inputs are loaded (the viewer passes one that opens its window
// at the spec's size); empty: the headless context of --backend.
using ContextFactory = std::function<std::unique_ptr<Context>(const SceneSpec& spec)>;

// Inputs are read before any GL work, so bad files fail fast and without a context. `outputs`
// (option, file; empty files skipped) are refused where they are one file with each other or
// with an input: a flag's, or one the scene file names (check_distinct_outputs), once the spec
// is made and before anything is loaded. `check_spec`, if given, is asked about the spec then too
// (compare's grid size, which the spec's image size decides).
using SpecCheck = std::function<void(const SceneSpec& spec)>;
Session open_session(const SceneOptions& options, const std::vector<NamedPath>& outputs,
                     const ContextFactory& make_context = {}, const SpecCheck& check_spec = {});

// A technique as listed by --techniques: its label and how it draws.
struct TechniqueRun {
    std::string label;
    DrawSettings settings;
};
// "flat,pom,relief" (and later "prism:cone") with the shared quality flags. Throws pr::Error(option).
// The lists of --techniques and the viewer's --split refuse prism flags that nothing takes
// (check_prism_flags_used).
std::vector<TechniqueRun> parse_technique_list(const std::string& list, const TechniqueOptions& quality,
                                               const std::string& option = "--techniques");
// Refuses --marcher, --prism-exit or --prism-shell, given, where no entry of `runs` takes it: every
// prism names its own value, or (the shell) an exit that has none. Where the prisms that name one
// all name the flag's value, the flag is redundant and taken (as render takes "prism:cone
// --marcher cone"). `drawn` names the list in the error. With `panel` (the viewer) an entry that
// is not a prism takes the flags, for when the panel turns it to the prism: the shell only with
// the walk.
void check_prism_flags_used(const TechniqueOptions& quality, const std::vector<TechniqueRun>& runs,
                            const std::string& drawn, bool panel);


} // namespace pr
