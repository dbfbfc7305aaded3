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
std::vector<TechniqueRun> parse_technique_list(const std::string& list, const TechniqueOptions& quality,
                                               const std::string& option = "--techniques");


} // namespace pr
