#pragma once
// Command-line options shared by the subcommands (scene, camera, technique, output), and the
// translation of what was given into a SceneSpec and DrawSettings.
#include "render/scene.hpp"
#include "render/technique.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>

namespace pr {

struct SceneOptions {
    std::string scene_file;
    std::string mesh;
    std::optional<std::string> height; // default: ObjectSpec's (builtin:bumps)
    std::string color;
    std::optional<float> depth;
    std::optional<float> midlevel;
    std::string light, eye, target, up;
    std::optional<float> fovy, elevation, azimuth;
    std::string size = "800x600";
    std::string backend = "osmesa";
    std::size_t max_triangles = MeshOptions{}.max_triangles;
    std::optional<int> max_image_size; // --max-image-size N: images up to NxN (default ImageLimits)
    float uv_scale = MeshOptions{}.uv_scale;
    bool generate_uvs = false;
    std::string cache_dir; // derived maps (cone maps); empty: default_cache_dir()
    std::string cone_backend = "cpu"; // where missing cone maps are built: cpu or gpu

    CLI::Option* size_option = nullptr;
};

struct TechniqueOptions {
    std::string technique = "relief"; // render: --technique
    std::string techniques;            // compare, bench: --techniques (the caller sets the default)
    int steps = DrawSettings{}.steps;
    int refine = DrawSettings{}.refine;
    std::string normal_quality = "sobel";
    std::string marcher = "relief";
    std::string prism_exit = "walk";
    std::string prism_shell = "tight";
    bool depth_write = false;
    std::string shadows = "none";
    int reference_level = 0; // 0: automatic
    std::size_t reference_max_triangles = ReferenceOptions{}.max_triangles;
};

void add_scene_options(CLI::App& app, SceneOptions& o);
// --technique (single) or --techniques (a list), the quality flags and the reference's options.
void add_technique_options(CLI::App& app, TechniqueOptions& o, bool single_technique);
ReferenceOptions make_reference_options(const TechniqueOptions& o);

// Builds the SceneSpec: --scene JSON first (paths relative to the JSON file), then flags on top
// (flags override a single-object scene's object, and the camera/light/size). Throws pr::Error.
SceneSpec make_scene_spec(const SceneOptions& o);
DrawSettings make_draw_settings(const TechniqueOptions& o, const std::string& technique,
                                const std::string& option = "--technique");

// "x,y,z" -> vec3; throws pr::Error(option, …).
glm::vec3 parse_vec3(const std::string& text, const std::string& option);
// "WxH" -> (w, h); throws pr::Error(option, …).
std::pair<int, int> parse_size(const std::string& text, const std::string& option);

} // namespace pr
