#pragma once
// Command-line options shared by the subcommands (scene, camera, technique, output), and the
// translation of what was given into a SceneSpec and DrawSettings.
#include "render/scene.hpp"
#include "render/technique.hpp"

#include <CLI/CLI.hpp>

#include <limits>
#include <optional>
#include <regex>
#include <stdexcept>
#include <string>
#include <string_view>

namespace pr {

struct SceneOptions {
    std::string scene_file;
    std::string mesh;
    std::optional<std::string> height; // default: ObjectSpec's (builtin:bumps)
    std::string color;
    std::optional<double> depth; // double: a value past the float range is refused, not made infinite
    std::optional<double> midlevel; // doubles, as depth: checked before they become floats
    std::string light, eye, target, up;
    std::optional<double> fovy, elevation, azimuth;
    std::string size = "800x600";
    std::string backend = "osmesa";
    std::size_t max_triangles = MeshOptions{}.max_triangles;
    std::optional<int> max_image_size; // --max-image-size N: images up to NxN (default ImageLimits)
    double uv_scale = MeshOptions{}.uv_scale;
    bool generate_uvs = false;
    std::string cache_dir; // derived maps (cone maps); empty: default_cache_dir()
    bool no_cache = false; // --no-cache: derived maps in memory only
    std::string cone_backend = "cpu"; // where missing cone maps are built: cpu or gpu

    CLI::Option* size_option = nullptr;
    const CLI::Option* cone_backend_option = nullptr; // given or not: check_cone_map_flags_apply
    // Whether the command may read a cone map (check_cone_map_flags_apply; the viewer's panel turns
    // to any technique): where not, no output is checked against the cache's folder (open_session).
    bool reads_cone_maps = true;
    // Given or not: --uv-scale where every mesh has UVs of its own is refused (open_session).
    const CLI::Option* uv_scale_option = nullptr;
    // The viewer: a mesh dropped on its window later is loaded with these options too, and may
    // have no UVs, so --uv-scale is kept whatever the meshes given first.
    bool more_meshes_later = false;
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
    // The flags above, to tell given from default (CLI11's count): render refuses a technique
    // that names another marcher, exit or shell than one given ("prism:cone --marcher relief").
    const CLI::Option* marcher_flag = nullptr;
    const CLI::Option* prism_exit_flag = nullptr;
    const CLI::Option* prism_shell_flag = nullptr;
    bool depth_write = false;
    std::string shadows = "none";
    double light_size = kDefaultLightSize; // degrees
    int reference_level = 0; // 0: automatic
    std::size_t reference_max_triangles = ReferenceOptions{}.max_triangles;
    // These flags too, given or not: one that nothing drawn reads is refused
    // (check_quality_flags_apply).
    const CLI::Option* steps_flag = nullptr;
    const CLI::Option* refine_flag = nullptr;
    const CLI::Option* normal_quality_flag = nullptr;
    const CLI::Option* depth_write_flag = nullptr;
    const CLI::Option* light_size_flag = nullptr;
    const CLI::Option* reference_level_flag = nullptr;
    const CLI::Option* reference_max_triangles_flag = nullptr;
};

// White space around a flag's number, dropped by every number flag (std::isspace's, C locale).
inline constexpr std::string_view kBlanks = " \t\n\r\f\v";

// `text` without the white space around it.
inline std::string_view trimmed(std::string_view text)
{
    const std::size_t first = text.find_first_not_of(kBlanks);
    return first == std::string_view::npos ? std::string_view()
                                           : text.substr(first, text.find_last_not_of(kBlanks) + 1 - first);
}

// Whether a number begins, after white space and a sign, with a radix prefix (0x, 0b, 0o), which
// C's and CLI11's readers take where the flags take decimal numbers alone.
inline bool radix_prefixed(std::string_view text)
{
    text = trimmed(text);
    if (!text.empty() && (text[0] == '+' || text[0] == '-')) text.remove_prefix(1);
    return text.size() >= 2 && text[0] == '0' && std::string_view("xXbBoO").find(text[1]) != std::string_view::npos;
}

// For an integer flag (->transform(saturating<int>())): a whole number beyond the type's range
// becomes the type's limit, so the flag's own range check reports it as out of range (exit 1,
// bad input) rather than CLI11's "Could not convert" (exit 2, usage: --steps 99999999999999).
// Anything else (12.5, 1e3, abc) is left to CLI11's conversion: the wrong shape, usage. Whole
// numbers are decimal: "0x10" is refused, "010" is ten. `typed`, if given, receives the text of a
// value that was clamped, as typed, for a message that echoes it (--msaa 2147483648 said "got
// 2147483647").
template <typename T>
CLI::Validator saturating(std::string* typed = nullptr)
{
    return CLI::Validator(
        [typed](std::string& text) {
            // (CLI11 reads "" as 0 for an integer: --steps "" said "must be between 1 and 1024, got 0".)
            if (text.empty()) return std::string("expected a whole number, got an empty value");
            static const std::regex whole(R"(\s*[+-]?[0-9]+\s*)");
            static const std::regex prefixed(R"(\s*[+-]?0[xXbBoO].*)");
            if (std::regex_match(text, prefixed)) return "expected a decimal whole number, got '" + text + "'";
            if (!std::regex_match(text, whole)) return std::string();
            const bool negative = text.find('-') != std::string::npos;
            const std::string as_typed(trimmed(text));
            if (typed) typed->clear();
            const auto clamp_to = [&](T limit) {
                if (typed) *typed = as_typed;
                text = std::to_string(limit);
            };
            try {
                const long double v = std::stold(text);
                if (v > static_cast<long double>(std::numeric_limits<T>::max()))
                    clamp_to(std::numeric_limits<T>::max());
                else if (v < static_cast<long double>(std::numeric_limits<T>::min()))
                    clamp_to(std::numeric_limits<T>::min());
                else // in decimal without leading zeros: CLI11 read "010" as octal (8)
                    text = negative ? std::to_string(static_cast<long long>(v))
                                    : std::to_string(static_cast<unsigned long long>(v));
            } catch (const std::out_of_range&) {
                clamp_to(negative ? std::numeric_limits<T>::min() : std::numeric_limits<T>::max());
            }
            return std::string();
        },
        "", "");
}

// For a flag taking a number: not empty, and decimal (CLI11 reads "0x10" as 16, "0b11" as 3).
// An empty value is usage (exit 2): CLI11 reads "" as no value for an optional (--depth "" drew
// the default depth, exit 0). (An empty file name is bad input, exit 1: refuse_empty_file_names.)
// White space around the number is dropped, as the whole-number and x,y,z flags drop it (CLI11
// refused --depth "1 " where it took --steps "1 ").
inline CLI::Validator a_number()
{
    return CLI::Validator(
        [](std::string& text) {
            if (text.empty()) return std::string("expected a number, got an empty value");
            if (!trimmed(text).empty()) text = std::string(trimmed(text));
            if (radix_prefixed(text)) return "expected a decimal number, got '" + text + "'";
            return std::string();
        },
        "", "");
}

void add_scene_options(CLI::App& app, SceneOptions& o);
// --technique (single) or --techniques (a list), the quality flags and the reference's options.
void add_technique_options(CLI::App& app, TechniqueOptions& o, bool single_technique);
ReferenceOptions make_reference_options(const TechniqueOptions& o);

// Builds the SceneSpec: --scene JSON first (paths relative to the JSON file), then flags on top
// (flags override a single-object scene's object, and the camera/light/size). Throws pr::Error.
SceneSpec make_scene_spec(const SceneOptions& o);
DrawSettings make_draw_settings(const TechniqueOptions& o, const std::string& technique,
                                const std::string& option = "--technique");
// Refuses --marcher, --prism-exit and --prism-shell where nothing drawn is a prism (`drawn`:
// the technique or list, named in the error): they were ignored silently (render, compare,
// bench; the viewer keeps them for when its panel turns to the prism: check_prism_flags_used).
void check_prism_flags_apply(const TechniqueOptions& o, bool any_prism, const std::string& drawn);
// Refuses a quality flag given where nothing drawn reads it: they were ignored silently (render,
// compare, bench; not the viewer, whose panel may turn to another technique or change the flag's
// setting). `drawn_settings`: every draw (compare: its reference's too), named `drawn` in the
// error ("--technique flat", "--techniques flat,pom"). In this order:
// - --shadows hard|soft where no draw reads it (flat never: reads_shadows;
//   --shadows none asks for nothing, and is taken anywhere);
// - --steps, --refine, --normal-quality, --depth-write and --light-size where no draw reads them
//   (reads_steps and the others, render/technique.hpp);
// - --reference-level and --reference-max-triangles where the reference is not drawn (compare
//   always draws it), and the cap next to a level (check_reference_flags_pair).
// Whether anything drawn reads a cone map (render, compare, bench); where nothing does,
// --cone-backend is refused, as the quality flags are. --no-cache next to --cache-dir is refused.
bool check_cone_map_flags_apply(const SceneOptions& o, const std::vector<DrawSettings>& drawn_settings,
                                const std::string& drawn);
void check_quality_flags_apply(const TechniqueOptions& o, const std::vector<DrawSettings>& drawn_settings,
                               const std::string& drawn);
// `drawn` ("--technique prism") with the --marcher and --prism-exit given, which decide what the
// prism steps, refines and reads: the errors above say them ("--technique prism refines no hit"
// read as if no prism did, where the default one does and --marcher linear was the cause; an
// exploratory session, forty-ninth; "--technique prism reads no cone map", where --marcher
// max-mip was the cause, fifty-third).
std::string with_prism_flags(const TechniqueOptions& o, const std::string& drawn);
// --reference-max-triangles next to a --reference-level: the cap bounds the automatic level only
// (check_quality_flags_apply's last check; the viewer's too, whose panel sets no level).
void check_reference_flags_pair(const TechniqueOptions& o);

// "x,y,z" -> vec3; throws pr::Error(option, …).
glm::vec3 parse_vec3(const std::string& text, const std::string& option);
// "WxH" -> (w, h); throws pr::Error(option, …).
std::pair<int, int> parse_size(const std::string& text, const std::string& option);

} // namespace pr
