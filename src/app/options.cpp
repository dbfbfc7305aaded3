#include "app/options.hpp"

#include "core/camera.hpp"
#include "core/error.hpp"
#include "core/input_file.hpp"
#include "core/transform.hpp"
#include "core/image.hpp"
#include "maps/conemap.hpp"
#include "render/reference_geometry.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <climits>
#include <cerrno>
#include <cmath>
#include <optional>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

namespace pr {

namespace {

std::string list(const std::vector<std::string>& names, const std::string& prefix = "")
{
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + prefix + n;
    return s;
}

// Also refuses what a float cannot hold (1e300 would become infinity).
float finite(double v, const std::string& what)
{
    if (!std::isfinite(v)) throw Error(what, "must be a finite number");
    if (std::abs(v) > std::numeric_limits<float>::max())
        throw Error(what, "must be at most 3.4e38 in magnitude (the renderer's single precision)");
    return static_cast<float>(v);
}

std::string number_text(double v)
{
    std::ostringstream out;
    out << v;
    return out.str();
}

std::string vec_text(const glm::dvec3& v)
{
    return number_text(v.x) + "," + number_text(v.y) + "," + number_text(v.z);
}

// x,y,z: three numbers separated by commas (blanks around them allowed), or nothing. strtod
// rather than stod: stod refuses a value that underflows to a denormal (1e-310), which is still a
// valid, non-zero number.
std::optional<glm::dvec3> three_numbers(const std::string& text)
{
    glm::dvec3 v(0.0);
    std::size_t start = 0;
    for (int n = 0; n < 3; ++n) {
        const std::size_t comma = n < 2 ? text.find(',', start) : std::string::npos;
        if (n < 2 && comma == std::string::npos) return std::nullopt;
        const std::string part = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        // Decimal, as every number flag: strtod reads "0x1" as 1 (--eye 0x1,2,3 was taken where
        // --depth 0x10 is refused).
        if (radix_prefixed(part)) return std::nullopt;
        char* end = nullptr;
        v[n] = std::strtod(part.c_str(), &end); // (the last part: a comma in it is left over)
        if (end == part.c_str() || part.find_first_not_of(kBlanks, std::size_t(end - part.c_str())) != std::string::npos)
            return std::nullopt;
        start = comma + 1;
    }
    return v;
}

std::string vec3_shape_problem(const std::string& text)
{
    return three_numbers(text) ? "" : "expected x,y,z (three decimal numbers), got '" + text + "'";
}

// Parsed in double, so that a direction like 1e-30,0,0 or 1e300,0,0 keeps its meaning until it
// is normalized (unit_direction).
glm::dvec3 parse_dvec3(const std::string& text, const std::string& option)
{
    const std::optional<glm::dvec3> v = three_numbers(text);
    if (!v) throw Error(option, vec3_shape_problem(text));
    for (int n = 0; n < 3; ++n)
        if (!std::isfinite((*v)[n])) throw Error(option, "must be finite numbers, got '" + text + "'");
    return *v;
}

// WIDTHxHEIGHT: two integers around an x (white space around each allowed), or nothing. A side
// with more digits than a long long holds saturates, to be refused as out of range: the stream
// it was read with failed on it, and `--size 64x99999999999999999999` read as the wrong shape
// (usage), where every other integer flag says it is too large (found by an exploratory
// session, thirty-sixth).
std::optional<std::pair<long long, long long>> width_height(const std::string& text)
{
    std::size_t i = 0;
    const auto space = [&] {
        while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
    };
    const auto integer = [&]() -> std::optional<long long> {
        space();
        const bool negative = i < text.size() && text[i] == '-';
        if (i < text.size() && (text[i] == '-' || text[i] == '+')) ++i;
        if (i >= text.size() || !std::isdigit(static_cast<unsigned char>(text[i]))) return std::nullopt;
        long long v = 0;
        for (; i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])); ++i)
            v = v > (LLONG_MAX - 9) / 10 ? LLONG_MAX : v * 10 + (text[i] - '0');
        return negative ? -v : v;
    };
    const std::optional<long long> w = integer();
    if (!w) return std::nullopt;
    space();
    if (i >= text.size() || (text[i] != 'x' && text[i] != 'X')) return std::nullopt;
    ++i;
    const std::optional<long long> h = integer();
    space();
    if (!h || i != text.size()) return std::nullopt;
    return std::pair{*w, *h};
}

std::string size_shape_problem(const std::string& text)
{
    return width_height(text) ? "" : "expected WIDTHxHEIGHT, e.g. 800x600, got '" + text + "'";
}

// A flag's value of the wrong shape is bad usage (exit 2), as a number that is not one is in
// CLI11's own conversions (--steps abc); a value of the right shape out of range, or one a scene
// file gives, is bad input (exit 1), checked where it is used.
CLI::Validator shape_validator(std::string (*problem)(const std::string&), const std::string& name)
{
    return CLI::Validator([problem](std::string& text) { return problem(text); }, name);
}

// A direction (light, up): any finite non-zero vector, returned at unit length.
glm::vec3 direction(const glm::dvec3& v, const std::string& where)
{
    const std::optional<glm::vec3> unit = unit_direction(v);
    if (!unit) throw Error(where, "must not be the zero vector");
    return *unit;
}

// A position (eye, target, a translation): finite (checked when parsed) and within kMaxCoordinate.
glm::dvec3 check_position(const glm::dvec3& v, const std::string& where)
{
    for (int i = 0; i < 3; ++i)
        if (std::abs(v[i]) > kMaxCoordinate)
            throw Error(where, "coordinates must be at most 1e15 in magnitude (the renderer's precision), got " +
                                   vec_text(v));
    return v;
}

void check_depth(double depth, const std::string& where)
{
    if (!std::isfinite(depth) || depth < 0.0) throw Error(where, "must be a finite number >= 0");
}

void check_midlevel(double midlevel, const std::string& where)
{
    if (!std::isfinite(midlevel) || midlevel < 0.0 || midlevel > 1.0)
        throw Error(where, "must be between 0 and 1");
}

// The bounds are exclusive: 0.5 is the narrowest view the depth precision serves, 180 degrees
// is no perspective at all.
void check_fovy(double fovy, const std::string& where)
{
    if (!(fovy > 0.5 && fovy < 179.0)) throw Error(where, "must be more than 0.5 and less than 179 degrees");
}

void check_elevation(double elevation, const std::string& where)
{
    if (!std::isfinite(elevation) || std::abs(elevation) > 90.0)
        throw Error(where, "must be between -90 and 90 degrees");
}

// Any angle a float holds (1e308 said "must be a finite number": it is one, past the float range).
void check_azimuth(double azimuth, const std::string& where)
{
    finite(azimuth, where);
}

} // namespace

glm::vec3 parse_vec3(const std::string& text, const std::string& option)
{
    const glm::dvec3 v = parse_dvec3(text, option);
    return {finite(v.x, option), finite(v.y, option), finite(v.z, option)};
}

std::pair<int, int> parse_size(const std::string& text, const std::string& option)
{
    const auto size = width_height(text);
    if (!size) throw Error(option, size_shape_problem(text));
    const auto [w, h] = *size;
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        throw Error(option, "each side must be between 1 and 16384, got '" + text + "'");
    return {int(w), int(h)};
}

void add_scene_options(CLI::App& app, SceneOptions& o)
{
    app.add_option("--scene", o.scene_file,
                   "Scene file (JSON): several objects with transform, mesh, height, colour, depth, "
                   "midlevel; camera; light; size. Flags override it (see docs/scenes.md)")
        ->group("Scene");
    app.add_option("--mesh", o.mesh, "Mesh file: OBJ, OFF, PLY or STL")->group("Scene");
    app.add_option("--height", o.height,
                   "Height map: image file (PNG, JPEG, BMP, TGA, binary PNM, HDR, GIF, PSD, PIC; 8/16-bit; first channel) or builtin:NAME "
                   "with NAME one of " + list(builtin_height_names()) + " (default builtin:bumps)")
        ->group("Scene");
    app.add_option("--color", o.color, "Colour texture: image file or builtin:NAME (" +
                                           list(builtin_color_names()) + "); default a plain colour")
        ->group("Scene");
    app.add_option("--depth", o.depth,
                   "Displacement depth in scene units (default: 4% of the mesh's bounding-box diagonal)")
        ->transform(a_number())
        ->group("Scene");
    app.add_option("--midlevel", o.midlevel,
                   "Height that stays on the base surface: 0 outward (default), 1 inward, 0.5 centred")
        ->transform(a_number())
        ->group("Scene");
    const CLI::Validator xyz = shape_validator(vec3_shape_problem, "x,y,z");
    app.add_option("--light", o.light,
                   "x,y,z: world direction towards the light (default: above-left of the camera)")
        ->check(xyz)
        ->group("Scene");
    app.add_option("--max-triangles", o.max_triangles, "Refuse meshes with more triangles")
        ->transform(saturating<std::size_t>())
        ->group("Scene")
        ->capture_default_str();
    app.add_option("--max-image-size", o.max_image_size,
                   "Refuse height and colour images (and built-in maps) larger than N pixels per "
                   "side (default 16384 per side and 64 Mpixel in all; 1-16384)")
        ->transform(saturating<int>())
        ->group("Scene");
    o.uv_scale_option = app.add_option("--uv-scale", o.uv_scale,
                   "Generated UVs (meshes without UVs): texture repeats across the largest extent")
        ->transform(a_number())
        ->group("Scene")
        ->capture_default_str();
    app.add_flag("--generate-uvs", o.generate_uvs, "Ignore the mesh's UVs and generate box-projected ones")
        ->group("Scene");

    app.add_option("--eye", o.eye, "x,y,z: camera position (default: auto-framing)")->check(xyz)->group("Camera");
    app.add_option("--target", o.target, "x,y,z: point looked at (default: the shell's centre)")
        ->check(xyz)
        ->group("Camera");
    app.add_option("--up", o.up, "x,y,z: up direction (default 0,1,0)")->check(xyz)->group("Camera");
    app.add_option("--fovy", o.fovy, "Vertical field of view, degrees (default 40)")
        ->transform(a_number())
        ->group("Camera");
    app.add_option("--elevation", o.elevation,
                   "Auto-framing: degrees above the horizontal plane (default 25)")
        ->transform(a_number())
        ->group("Camera");
    app.add_option("--azimuth", o.azimuth, "Auto-framing: degrees around the up axis (default 35)")
        ->transform(a_number())
        ->group("Camera");
    o.size_option = app.add_option("--size", o.size, "Image size WIDTHxHEIGHT")
                        ->check(shape_validator(size_shape_problem, "WIDTHxHEIGHT"))
                        ->group("Camera")
                        ->capture_default_str();
    app.add_option("--backend", o.backend, "OpenGL backend: osmesa (default, llvmpipe) or egl (headless)")
        ->group("Output")
        ->capture_default_str();
    app.add_option("--cache-dir", o.cache_dir,
                   "Folder for derived maps (cone maps); default $XDG_CACHE_HOME/prismrelief, else "
                   "~/.cache/prismrelief; the least recently used go beyond $PRISMRELIEF_CACHE_MAX_MB "
                   "(default 2048)")
        ->group("Output");
    app.add_flag("--no-cache", o.no_cache, "Build derived maps in memory only: neither read nor write the cache")
        ->group("Output");
    o.cone_backend_option = app.add_option("--cone-backend", o.cone_backend,
                   "Where cone maps missing from the cache are built: cpu (threads) or gpu (compute "
                   "shader in the render's context: for a real GPU, with --backend egl)")
        ->group("Output")
        ->capture_default_str();
}

void add_technique_options(CLI::App& app, TechniqueOptions& o, bool single_technique)
{
    if (single_technique)
        app.add_option("--technique", o.technique, "Technique: " + technique_names())
            ->group("Technique")
            ->capture_default_str();
    else
        app.add_option("--techniques", o.techniques,
                       "Comma-separated techniques (" + technique_names() +
                           "; prism:MARCHER[:EXIT[:SHELL]] for the prism's options)")
            ->group("Technique")
            ->capture_default_str();
    o.steps_flag = app.add_option("--steps", o.steps,
                   "Linear search steps over the full height range (1-" + std::to_string(kMaxSteps) + ")")
        ->transform(saturating<int>())
        ->group("Technique")
        ->capture_default_str();
    o.refine_flag = app.add_option("--refine", o.refine,
                   "Binary refinement steps after the linear search (0-" + std::to_string(kMaxRefine) + ")")
        ->transform(saturating<int>())
        ->group("Technique")
        ->capture_default_str();
    o.marcher_flag = app.add_option("--marcher", o.marcher, "prism: ray marcher, " + marcher_names() +
                                           " (in lists: prism:MARCHER)")
        ->group("Technique")
        ->capture_default_str();
    o.prism_exit_flag = app.add_option("--prism-exit", o.prism_exit,
                   "prism: walk (the ray goes from prism to prism across exact exits; only the shell's "
                   "outside is drawn), exact (each front face of every prism is drawn and marched to its "
                   "exact exit) or vertex (per-vertex plane distances, interpolated). In lists: "
                   "prism:MARCHER:EXIT")
        ->group("Technique")
        ->capture_default_str();
    o.prism_shell_flag = app.add_option("--prism-shell", o.prism_shell,
                   "prism walk: tight (each top cap at the highest the height field gets around its "
                   "corners) or full (top caps at height 1). In lists: prism:MARCHER:walk:SHELL")
        ->group("Technique")
        ->capture_default_str();
    o.normal_quality_flag = app.add_option("--normal-quality", o.normal_quality,
                   "Normal from heights: gather (4-tap), central (differences), sobel (3x3)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--shadows", o.shadows,
                   "Self-shadowing: march from the hit towards the light through the height field "
                   "(none|hard|soft)")
        ->group("Technique")
        ->capture_default_str();
    o.light_size_flag = app.add_option("--light-size", o.light_size,
                   "Soft shadows: the light's angular diameter in degrees, more than 0 and at most " +
                       std::to_string(int(kMaxLightSize)) + " (the sun: about 0.5)")
        ->transform(a_number())
        ->group("Technique")
        ->capture_default_str();
    o.depth_write_flag = app.add_flag("--depth-write", o.depth_write,
                 "Base-surface techniques write the depth of the point they show")
        ->group("Technique");
    o.reference_level_flag = app.add_option("--reference-level", o.reference_level,
                   "reference: split each triangle into LEVEL^2 (0: automatic, edges about one texel "
                   "or one pixel, whichever is coarser, but no coarser than about 262,000 triangles "
                   "in all where the texels are finer; see docs/compare.md)")
        ->transform(saturating<int>())
        ->group("Technique")
        ->capture_default_str();
    o.reference_max_triangles_flag = app.add_option("--reference-max-triangles", o.reference_max_triangles,
                   "reference: lower automatic levels to stay within this many triangles (the scene's, all objects')")
        ->transform(saturating<std::size_t>())
        ->group("Technique")
        ->capture_default_str();
}

void check_prism_flags_apply(const TechniqueOptions& o, bool any_prism, const std::string& drawn)
{
    if (any_prism) return;
    for (const CLI::Option* flag : {o.marcher_flag, o.prism_exit_flag, o.prism_shell_flag})
        if (flag != nullptr && flag->count() > 0)
            throw Error(flag->get_name(), "applies to the prism technique only, and " + drawn + " draws none");
}

std::string with_prism_flags(const TechniqueOptions& o, const std::string& drawn)
{
    std::string with = drawn;
    for (const CLI::Option* flag : {o.marcher_flag, o.prism_exit_flag})
        if (flag != nullptr && flag->count() > 0) with += " " + flag->get_name() + " " + flag->as<std::string>();
    return with;
}

void check_quality_flags_apply(const TechniqueOptions& o, const std::vector<DrawSettings>& drawn_settings,
                               const std::string& drawn)
{
    const auto any = [&](bool (*reads)(const DrawSettings&)) {
        return std::any_of(drawn_settings.begin(), drawn_settings.end(), reads);
    };
    if (parse_shadows(o.shadows, "--shadows") != Shadows::None && !any(reads_shadows))
        throw Error("--shadows", "has no effect: " + drawn + " draws no self-shadowing (flat never does)");
    const auto given = [](const CLI::Option* flag) { return flag != nullptr && flag->count() > 0; };
    // Each flag, what reads it, and what the draws do not do without it.
    const struct {
        const CLI::Option* flag;
        bool (*reads)(const DrawSettings&);
        const char* not_done;
    } unread[] = {
        {o.steps_flag, reads_steps,
         "takes no linear steps (flat and reference never do; normal, offset and the prism's max-mip with the "
         "exact or vertex exit only with --shadows)"},
        {o.refine_flag, reads_refine,
         "refines no hit (only relief does, and relief, cone and relaxed-cone as the prism's marcher, and the "
         "prism's walk with max-mip; the cone and relaxed-cone techniques meet the surface exactly)"},
        {o.normal_quality_flag, reads_normal_quality, "takes no normal from the heights (flat shades with the mesh's)"},
        {o.light_size_flag, reads_light_size,
         "draws no shadows (flat never does)"},
        {o.depth_write_flag, reads_depth_write,
         "writes the same depth without it (only steep, pom, relief, cone and relaxed-cone show points below the "
         "polygon; the prism always writes its depth)"},
    };
    // (Said as "pom draws no soft shadows" where --shadows soft was not given: pom draws them with
    // it; found by an exploratory session, thirty-fifth.)
    if (given(o.light_size_flag) && parse_shadows(o.shadows, "--shadows") != Shadows::Soft && any(reads_shadows))
        throw Error(o.light_size_flag->get_name(), "has no effect without --shadows soft (it is the soft light's "
                                                   "size): add --shadows soft, or leave it out");
    const std::string drawn_with = with_prism_flags(o, drawn);
    for (const auto& u : unread)
        if (given(u.flag) && !any(u.reads))
            throw Error(u.flag->get_name(), "has no effect: " + drawn_with + " " + u.not_done + ": leave it out");
    const bool reference = std::any_of(drawn_settings.begin(), drawn_settings.end(),
                                       [](const DrawSettings& s) { return s.technique == Technique::Reference; });
    if (!reference)
        for (const CLI::Option* flag : {o.reference_level_flag, o.reference_max_triangles_flag})
            if (given(flag))
                throw Error(flag->get_name(), "applies to the reference technique only, and " + drawn +
                                                  " draws none: draw reference too, or leave the flag out");
    check_reference_flags_pair(o);
}

void check_reference_flags_pair(const TechniqueOptions& o)
{
    if (o.reference_max_triangles_flag != nullptr && o.reference_max_triangles_flag->count() > 0 && o.reference_level > 0)
        throw Error("--reference-max-triangles", "has no effect: it bounds the automatic level only, and --reference-level " +
                                                     std::to_string(o.reference_level) + " is given");
}

bool check_cone_map_flags_apply(const SceneOptions& o, const std::vector<DrawSettings>& drawn_settings,
                                const std::string& drawn)
{
    check_cache_flags(o.no_cache, o.cache_dir); // (before the other checks of the run, as open_session)
    const bool reads = std::any_of(drawn_settings.begin(), drawn_settings.end(), [](const DrawSettings& d) {
        return d.aux_map() == AuxMap::Cone || d.aux_map() == AuxMap::Relaxed;
    });
    const bool backend_given = o.cone_backend_option != nullptr && o.cone_backend_option->count() > 0;
    if (backend_given) parse_cone_backend_gpu(o.cone_backend, "--cone-backend"); // (a bad value is said as such first)
    // (--cone-backend was accepted and ignored, found by an exploratory session, thirty-third.
    // --cache-dir and --no-cache are taken anywhere: they say where derived data may live, not
    // what is drawn, and a script gives them to every technique of a loop.)
    if (!reads && backend_given)
        throw Error("--cone-backend", "has no effect: " + drawn +
                                          " reads no cone map (cone, relaxed-cone and the prism's cone marchers do): "
                                          "leave it out");
    return reads;
}

ReferenceOptions make_reference_options(const TechniqueOptions& o)
{
    // (An automatic level may be finer than 256 on large triangles: a two-triangle floor under a
    // map repeated many times took 362, which the flag could not ask for.)
    if (o.reference_level < 0 || o.reference_level > kMaxReferenceLevel)
        throw Error("--reference-level", "must be between 0 (automatic) and " + std::to_string(kMaxReferenceLevel));
    if (o.reference_max_triangles < 1) throw Error("--reference-max-triangles", "must be at least 1");
    ReferenceOptions r;
    r.level = o.reference_level;
    r.max_triangles = o.reference_max_triangles;
    return r;
}

DrawSettings make_draw_settings(const TechniqueOptions& o, const std::string& technique,
                                const std::string& option)
{
    DrawSettings s;
    // "prism:relief", "prism:relief:vertex" or "prism:relief:walk:full" name the marcher, the exit
    // and the walk's shell inside the technique (lists of --techniques).
    std::vector<std::string> parts;
    for (std::size_t start = 0;;) {
        const std::size_t colon = technique.find(':', start);
        parts.push_back(technique.substr(start, colon - start));
        if (colon == std::string::npos) break;
        start = colon + 1;
    }
    s.technique = parse_technique(parts[0], option);
    s.marcher = parse_marcher(o.marcher, "--marcher");
    s.prism_exit = parse_prism_exit(o.prism_exit, "--prism-exit");
    s.full_shell = parse_prism_shell(o.prism_shell, "--prism-shell");
    if (parts.size() > 1) {
        if (s.technique != Technique::Prism)
            throw Error(option, "'" + technique + "': only prism takes options (prism:MARCHER[:EXIT[:SHELL]])");
        if (parts.size() > 4)
            throw Error(option, "'" + technique + "': too many options, '" + parts[4] +
                                    "' is one too many (prism:MARCHER[:EXIT[:SHELL]] takes at most three)");
        s.marcher = parse_marcher(parts[1], option);
        if (parts.size() >= 3) s.prism_exit = parse_prism_exit(parts[2], option);
        if (parts.size() == 4) {
            if (s.prism_exit != PrismExit::Walk)
                throw Error(option, "'" + technique + "': only the walk takes a shell (prism:MARCHER:walk:SHELL)");
            s.full_shell = parse_prism_shell(parts[3], option);
        }
    }
    // One technique (render, view) and a flag that says otherwise than its name: the name won,
    // silently ("prism:cone --marcher relief" drew cone). In lists the flags are what entries
    // that name nothing take, and each entry may name its own.
    if (option == "--technique" && s.technique == Technique::Prism) {
        const auto given = [](const CLI::Option* flag) { return flag != nullptr && flag->count() > 0; };
        const auto conflict = [&](const CLI::Option* flag, const char* what, const std::string& named,
                                  const std::string& flagged) {
            if (given(flag) && named != flagged)
                throw Error(option, "'" + technique + "' names the " + what + " " + named + ", " + flag->get_name() +
                                        " " + flagged + ": give one");
        };
        if (parts.size() > 1) conflict(o.marcher_flag, "marcher", parts[1], o.marcher);
        if (parts.size() > 2) conflict(o.prism_exit_flag, "exit", parts[2], o.prism_exit);
        if (parts.size() > 3) conflict(o.prism_shell_flag, "shell", parts[3], o.prism_shell);
        // A shell for an exit that takes none: the list form refuses it; the flags ignored it.
        if (given(o.prism_shell_flag) && !s.prism_walk())
            throw Error("--prism-shell", "only the walk takes a shell (the exit is " + prism_exit_name(s.prism_exit) +
                                             ")");
    }
    if (o.steps < 1 || o.steps > kMaxSteps)
        throw Error("--steps", "must be between 1 and " + std::to_string(kMaxSteps));
    if (o.refine < 0 || o.refine > kMaxRefine)
        throw Error("--refine", "must be between 0 and " + std::to_string(kMaxRefine));
    s.steps = o.steps;
    s.refine = o.refine;
    s.normal_quality = parse_normal_quality(o.normal_quality);
    s.depth_write = o.depth_write;
    s.shadows = parse_shadows(o.shadows, "--shadows");
    // (Not past the model: the light is the part of its disc above the occluder's edge over the
    // disc's diameter, a small-angle estimate.)
    if (!(o.light_size > 0.0 && o.light_size <= double(kMaxLightSize)))
        throw Error("--light-size", "must be more than 0 and at most " + std::to_string(int(kMaxLightSize)) +
                                        " degrees (--shadows hard is a point light)");
    // (Under float's range it became 0, which the check above refuses, and reports said 0; found by
    // an exploratory session, thirty-fourth.)
    if (!(static_cast<float>(o.light_size) >= std::numeric_limits<float>::min()))
        throw Error("--light-size", "must be at least 1.2e-38 degrees (the renderer's single precision; --shadows "
                                    "hard is a point light)");
    s.light_size = static_cast<float>(o.light_size);
    return s;
}

namespace {

using json = nlohmann::json;

glm::dvec3 json_dvec3(const json& j, const std::string& where)
{
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw Error(where, "expected an array of three numbers");
    const glm::dvec3 v(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        throw Error(where, "must be finite numbers");
    return v;
}

double json_number(const json& j, const std::string& where)
{
    if (!j.is_number()) throw Error(where, "expected a number");
    const double v = j.get<double>();
    if (!std::isfinite(v)) throw Error(where, "must be a finite number");
    return v;
}

// A number of the file checked as its flag is (check_depth, check_fovy, ...), under its place
// in the file.
float json_checked(const json& j, const std::string& where, void (*check)(double, const std::string&))
{
    const double v = json_number(j, where);
    check(v, where);
    return finite(v, where);
}

// `maps`: a height or colour map, which may name a built-in one ("builtin:NAME"); a mesh has none,
// so "builtin:rock.obj" is a file in the scene's folder (it was looked for in the working folder;
// found by an exploratory session, fifty-third).
std::string json_path(const json& j, const std::string& where, const std::filesystem::path& base, bool maps = true)
{
    if (!j.is_string()) throw Error(where, "expected a string");
    const std::string s = j.get<std::string>();
    // (The system reads a name up to its first NUL: "a\u0000b.obj" opened the file "a", and the
    // report named the other; found by an exploratory session, thirty-fifth.)
    if (s.find('\0') != std::string::npos) throw Error(where, "a file name cannot hold a NUL character");
    if ((maps && s.rfind("builtin:", 0) == 0) || s.empty()) return s;
    const std::filesystem::path p(s);
    // Not lexically_normal(): "scn/../meshes/m.obj" is not "meshes/m.obj" where scn is a link to
    // a folder elsewhere (the kernel goes up from where the link leads; the scene loaded another
    // file, or none; found by an exploratory session, thirty-fifth).
    return p.is_absolute() ? s : (base / p).string();
}

// An object's transform must leave a solid object where floats can draw it: a singular matrix
// flattens it (the prism shell then has no thickness, and nothing was drawn), and the ratio of
// its largest to its smallest stretch (the condition number) is kept to 1e6, so that float
// rounding of the larger axes stays well below the smaller (floats carry about 7 digits).
// Mirrors (negative determinant) are fine.
void check_linear_part(const glm::dmat4& t, const std::string& subject)
{
    const glm::dmat3 a(t);
    double largest = 0.0;
    for (int c = 0; c < 3; ++c) largest = std::max(largest, glm::length(a[c]));
    if (largest > kMaxCoordinate) throw Error(subject, "scales by more than 1e15 (float precision)");
    // (All zero is singular, said as such: it read "scales by less than 1e-15"; found by an
    // exploratory session, forty-ninth.)
    if (largest > 0.0 && largest < 1.0 / kMaxCoordinate) throw Error(subject, "scales by less than 1e-15 (float precision)");
    if (largest == 0.0 || glm::determinant(a) == 0.0)
        throw Error(subject, "is singular: it flattens the object (to a plane, a line or a point)");
    const double condition = condition_number(a);
    // (With 7 digits: a shear of 1000, just over the bound, read "condition number 1e+06, at
    // most 1e6"; found by an exploratory session, forty-sixth.)
    if (!(condition <= 1e6)) // NaN too
        throw Error(subject, fmt::format("is nearly singular: it flattens the object (condition number {:.7g}, "
                                         "more than the 1e6 allowed)",
                                         condition));
}

// The keys a scene's objects take: the file's own, an object's, the camera's, a transform's
// (read_scene_file and json_transform read them). SceneKeys refuses any other as the file is
// parsed, so the readers meet none.
const std::set<std::string, std::less<>> kSceneKeys{"objects", "camera", "light", "size"};
// The most objects a scene holds (SceneParser).
constexpr std::size_t kMaxSceneObjects = 10000;
const std::set<std::string, std::less<>> kObjectKeys{"mesh",     "height",     "color",    "depth",
                                                     "midlevel", "base_color", "transform"};
const std::set<std::string, std::less<>> kCameraKeys{"eye", "target", "up", "fovy", "elevation", "azimuth"};
const std::set<std::string, std::less<>> kTransformKeys{"matrix", "translate", "rotate", "scale"};

glm::dmat4 json_transform(const json& j, const std::string& where)
{
    if (!j.is_object()) throw Error(where, "expected an object with translate/rotate/scale or matrix");
    glm::dmat4 t(1.0);
    if (j.contains("matrix")) {
        // docs/scenes.md: either a matrix or the parts; with both, one of them was ignored.
        if (j.size() > 1) throw Error(where, "either \"matrix\" or translate/rotate/scale, not both");
        const std::string w = where + ".matrix";
        const json& m = j["matrix"];
        if (!m.is_array() || m.size() != 16) throw Error(w, "expected 16 numbers (row-major)");
        for (int i = 0; i < 16; ++i) t[i % 4][i / 4] = json_number(m[i], w);
        // A projective matrix makes w vary over the mesh: each technique divides by it at another
        // stage (vertices, shell, per-pixel rays), so they drew different shapes.
        if (t[0][3] != 0.0 || t[1][3] != 0.0 || t[2][3] != 0.0 || t[3][3] != 1.0)
            throw Error(w, "must be affine: last row 0 0 0 1");
        for (int i = 0; i < 3; ++i)
            if (std::abs(t[3][i]) > kMaxCoordinate)
                throw Error(w, "its translation must be at most 1e15 in magnitude (the renderer's precision)");
        check_linear_part(t, w);
        return t;
    }
    if (j.contains("translate")) {
        const std::string w = where + ".translate";
        t = glm::translate(t, check_position(json_dvec3(j["translate"], w), w));
    }
    if (j.contains("rotate")) {
        // Degrees about X, then Y, then Z (applied to the object in that order).
        const glm::dvec3 r = json_dvec3(j["rotate"], where + ".rotate");
        // (As an azimuth is: 1e300 degrees drew at an angle of no meaning; found by an
        // exploratory session, forty-sixth.)
        for (int i = 0; i < 3; ++i) finite(r[i], where + ".rotate");
        t = glm::rotate(t, glm::radians(r.z), glm::dvec3(0, 0, 1));
        t = glm::rotate(t, glm::radians(r.y), glm::dvec3(0, 1, 0));
        t = glm::rotate(t, glm::radians(r.x), glm::dvec3(1, 0, 0));
    }
    if (j.contains("scale")) {
        const std::string w = where + ".scale";
        const json& s = j["scale"];
        // (A number or three: "expected an array of three numbers" for [1, 2] left the first out.)
        if (!s.is_number() && !(s.is_array() && s.size() == 3))
            throw Error(w, "expected a number (uniform) or an array of three numbers");
        const glm::dvec3 v = s.is_number() ? glm::dvec3(json_number(s, w)) : json_dvec3(s, w);
        if (v.x == 0.0 || v.y == 0.0 || v.z == 0.0) throw Error(w, "must not be zero");
        t = glm::scale(t, v);
        check_linear_part(t, w); // rotations are orthonormal: only the scale can degenerate
    }
    return t;
}

// nlohmann::json keeps the last of duplicate keys, so a scene saying "mesh" twice (a typo, a merge
// gone wrong) passed silently, which docs/scenes.md promises it does not. The parser tells this
// of every key before storing it; it tracks where it is (objects[0].transform) to name the
// place of a key its object already has, and refuses a key the place does not take there and
// then: refused after the parse, an unknown key at the start of a 62 MB scene took 10 s and 1 GB
// (the values are checked after it, in read_scene_file; where the file's shape is not a scene's,
// it refuses that shape before it reads any key). A SAX handler in front of the library's own
// document builder, not the library's parse callback: after each object the callback's parser
// searches the array holding it for a value the callback discarded, so an array of n objects
// took n^2 / 2 steps (400,000 empty objects, a 1.2 MB file: 29 s; a file under the size limit
// could take a day; found by an exploratory session, fifty-third).
class SceneParser : public nlohmann::json_sax<json> {
public:
    SceneParser(std::string file, json& result) : file_(std::move(file)), dom_(result) {}

    bool null() override { return value(), dom_.null(); }
    bool boolean(bool v) override { return value(), dom_.boolean(v); }
    bool number_integer(number_integer_t v) override { return value(), dom_.number_integer(v); }
    bool number_unsigned(number_unsigned_t v) override { return value(), dom_.number_unsigned(v); }
    bool number_float(number_float_t v, const string_t& text) override { return value(), dom_.number_float(v, text); }
    bool string(string_t& v) override { return value(), dom_.string(v); }
    bool binary(binary_t& v) override { return value(), dom_.binary(v); }
    bool start_object(std::size_t n) override { return enter(false), dom_.start_object(n); }
    bool end_object() override { return levels_.pop_back(), dom_.end_object(); }
    bool start_array(std::size_t n) override { return enter(true), dom_.start_array(n); }
    bool end_array() override { return levels_.pop_back(), dom_.end_array(); }
    bool key(string_t& k) override
    {
        Level& level = levels_.back();
        level.key = k;
        if (!level.keys.insert(level.key).second) throw Error(where(), "\"" + level.key + "\" is given twice");
        if (const auto* keys = keys_taken(); keys && !keys->contains(level.key))
            throw Error(where(), "unknown key '" + level.key + "'");
        return dom_.key(k);
    }
    // (Throws the library's parse error, which read_scene_file words.)
    bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& e) override
    {
        return dom_.parse_error(position, token, e);
    }

private:
    struct Level {
        bool array = false;
        std::size_t elements = 0; // arrays: elements seen so far
        std::string key;          // objects: the latest key
        std::set<std::string> keys;
        std::string name; // "objects" (in the top-level object), "[0]", ".transform"
    };

    // A scene nests five levels at most, its own object counted (objects[k].transform.translate); a file of nothing but
    // brackets nested millions deep took about 270 bytes a level here and in the parser, gigabytes
    // for a file under the size limit, and ran out of memory naming no file (found by an
    // exploratory session).
    static constexpr std::size_t kMaxDepth = 64;

    // A value in the level being parsed: counted where that is an array. Past kMaxSceneObjects in
    // the scene's "objects", refused there and then (each object is read, uploaded and drawn on
    // its own: 100,000 objects naming a one-triangle mesh took 18 s and 823 MB before the size's
    // check refused them; a file under the size limit holds a million).
    void value()
    {
        if (levels_.empty() || !levels_.back().array) return;
        if (++levels_.back().elements > kMaxSceneObjects && levels_.size() == 2 && levels_[1].name == "objects")
            throw Error(file_ + ": objects", "more than " + std::to_string(kMaxSceneObjects) +
                                                 " objects (a scene holds at most that many; put meshes that "
                                                 "share their maps into one file)");
    }

    void enter(bool array)
    {
        if (levels_.size() >= kMaxDepth) // (named by its top-level key: the whole path is 64 names long)
            throw Error(file_ + (levels_.size() > 1 ? ": " + levels_[1].name : std::string()),
                        "nested deeper than " + std::to_string(kMaxDepth) + " levels (a scene needs 5)");
        Level level;
        level.array = array;
        if (!levels_.empty()) {
            const Level& parent = levels_.back();
            level.name = parent.array ? "[" + std::to_string(parent.elements) + "]"
                                      : (levels_.size() > 1 ? "." : "") + parent.key;
        }
        value();
        levels_.push_back(std::move(level));
    }

    // The keys the object being parsed takes, where it stands in a scene's place for one (null
    // elsewhere: a value of the wrong type is refused after the parse).
    const std::set<std::string, std::less<>>* keys_taken() const
    {
        const std::size_t n = levels_.size();
        if (n == 1) return &kSceneKeys;
        if (n == 2 && levels_[1].name == "camera") return &kCameraKeys;
        const bool in_objects = n >= 3 && levels_[1].name == "objects" && levels_[1].array;
        if (n == 3 && in_objects) return &kObjectKeys;
        if (n == 4 && in_objects && levels_[3].name == ".transform") return &kTransformKeys;
        return nullptr;
    }

    std::string where() const
    {
        std::string path;
        for (const Level& l : levels_) path += l.name;
        return path.empty() ? file_ : file_ + ": " + path;
    }

    std::string file_;
    std::vector<Level> levels_;
    // The library's document builder, as json::parse's (its detail namespace: one template
    // parameter in nlohmann-json 3.11, Debian 12's and 13's; 3.12 adds an input adapter's).
    nlohmann::detail::json_sax_dom_parser<json> dom_;
};

// The whole file, or a message that names it: an ifstream on a folder threw libstdc++'s own
// "basic_filebuf::underflow error reading the file". Bounded, so that --scene /dev/zero ends.
// Through core/input_file: a FIFO with no writer, a device, more than 64 MiB are refused by name.
std::string read_scene_text(const std::string& file)
{
    return read_input_text(file, {std::uint64_t(64) << 20, "a scene file", "not a scene file"});
}

// What the scene file set that flags may override (make_scene_spec names the right source).
struct SceneFileValues {
    std::string size;
    bool up = false;
};

// Every value is checked here, under its place in the file ("s.json: objects[0].depth"), whether
// or not a flag overrides it; flags are checked under their own names by make_scene_spec.
SceneFileValues read_scene_file(const std::string& file, SceneSpec& spec)
{
    SceneFileValues found;
    json j;
    const std::string text = read_scene_text(file);
    // (The JSON reader ends its input at a NUL byte: a file with one after the object was taken
    // whole, whatever followed; found by an exploratory session, thirtieth.)
    if (const auto nul = text.find('\0'); nul != std::string::npos)
        throw Error(file, "not valid JSON (a NUL byte at offset " + std::to_string(nul) + ")");
    try {
        SceneParser parser(file, j);
        json::sax_parse(text, &parser);
    } catch (const json::exception& e) {
        std::string what = e.what();
        throw Error(file, "not valid JSON (" + what.substr(what.find(']') + 2) + ")");
    }
    if (!j.is_object()) throw Error(file, "expected a JSON object");
    const std::filesystem::path base = std::filesystem::path(file).parent_path();
    for (const auto& [key, value] : j.items()) {
        const std::string where = file + ": " + key;
        if (key == "objects") {
            if (!value.is_array() || value.empty()) throw Error(where, "expected a non-empty array");
            for (std::size_t i = 0; i < value.size(); ++i) {
                const json& oj = value[i];
                const std::string ow = file + ": objects[" + std::to_string(i) + "]";
                if (!oj.is_object()) throw Error(ow, "expected an object");
                ObjectSpec o;
                for (const auto& [k, v] : oj.items()) {
                    const std::string w = ow + "." + k;
                    // (An empty name: "mesh" said the object had none, "color" drew the plain
                    // colour without a word; found by an exploratory session.)
                    if (k == "mesh") {
                        o.mesh = json_path(v, w, base, false);
                        o.mesh_place = w;
                        if (o.mesh.empty()) throw Error(w, "empty file name");
                    } else if (k == "height") {
                        o.height = json_path(v, w, base);
                        o.height_place = w;
                        if (o.height.empty()) throw Error(w, "empty file name"); // (said ": cannot open")
                    } else if (k == "color") {
                        o.color = json_path(v, w, base);
                        o.color_place = w;
                        if (o.color.empty()) throw Error(w, "empty file name");
                    }
                    else if (k == "depth") {
                        o.depth = json_checked(v, w, check_depth);
                        o.depth_place = w;
                    }
                    else if (k == "midlevel") o.midlevel = json_checked(v, w, check_midlevel);
                    else if (k == "base_color") {
                        const glm::dvec3 c = json_dvec3(v, w);
                        for (int n = 0; n < 3; ++n)
                            if (c[n] < 0.0 || c[n] > 1.0)
                                throw Error(w, "must be three numbers between 0 and 1, got " + vec_text(c));
                        o.base_color = glm::vec3(c);
                    } else if (k == "transform") o.transform = json_transform(v, w);
                }
                if (o.mesh.empty()) throw Error(ow, "has no \"mesh\"");
                // A colour map replaces the plain colour: both in one object, base_color did
                // nothing without a word (the docs' own example gave both; found by an
                // exploratory session, thirty-third). (--color over a scene's base_color is the
                // user's own choice, not refused.)
                if (oj.contains("base_color") && !o.color.empty())
                    throw Error(ow + ".base_color", "has no effect next to \"color\", whose map gives the colour: "
                                                    "give one of them");
                spec.objects.push_back(o);
            }
        } else if (key == "camera") {
            if (!value.is_object()) throw Error(where, "expected an object");
            for (const auto& [k, v] : value.items()) {
                const std::string w = where + "." + k;
                if (k == "eye") {
                    spec.camera.eye = check_position(json_dvec3(v, w), w);
                    spec.camera.eye_place = where; // (scene_camera's subject: the target may be the shell's centre)
                }
                else if (k == "target") spec.camera.target = check_position(json_dvec3(v, w), w);
                else if (k == "up") {
                    spec.camera.up = direction(json_dvec3(v, w), w);
                    spec.camera.up_given = true;
                    spec.camera.up_place = w;
                    found.up = true;
                } else if (k == "fovy") spec.camera.fovy_deg = json_checked(v, w, check_fovy);
                else if (k == "elevation") spec.camera.elevation_deg = json_checked(v, w, check_elevation);
                else if (k == "azimuth") spec.camera.azimuth_deg = json_checked(v, w, check_azimuth);
            }
            // Auto-framing's angles next to an eye: the eye wins, and they were ignored silently.
            for (const char* angle : {"elevation", "azimuth"})
                if (value.contains("eye") && value.contains(angle))
                    throw Error(where + "." + angle, "has no effect with camera.eye (it places the auto-framed "
                                                     "camera; an eye given is where the camera is)");
        } else if (key == "light") {
            spec.light = direction(json_dvec3(value, where), where);
        } else if (key == "size") {
            if (!value.is_string()) throw Error(where, "expected \"WIDTHxHEIGHT\"");
            found.size = value.get<std::string>();
            parse_size(found.size, where);
        }
    }
    if (spec.objects.empty()) throw Error(file, "has no \"objects\"");
    return found;
}

} // namespace

SceneSpec make_scene_spec(const SceneOptions& o)
{
    SceneSpec spec;
    SceneFileValues file;
    if (!o.scene_file.empty()) file = read_scene_file(o.scene_file, spec);
    // Size: the flag if given, else the scene file's (checked there), else the default.
    const bool size_flag = o.size_option && o.size_option->count();
    const auto [w, h] = !size_flag && !file.size.empty() ? parse_size(file.size, o.scene_file + ": size")
                                                         : parse_size(o.size, "--size");
    spec.width = w;
    spec.height = h;

    if (!o.mesh.empty()) {
        if (spec.objects.size() > 1)
            throw Error("--mesh", "cannot override the mesh of a scene with several objects");
        if (spec.objects.empty()) spec.objects.emplace_back();
        spec.objects[0].mesh = o.mesh;
        spec.objects[0].mesh_place.clear();
    }
    if (spec.objects.empty()) throw Error("--mesh", "required (or --scene FILE.json)");
    if (o.height && o.height->empty()) throw Error("--height", "empty file name"); // (said ": cannot open")
    if (o.depth) check_depth(*o.depth, "--depth");
    if (o.midlevel) check_midlevel(*o.midlevel, "--midlevel");
    // Object flags apply to every object of the scene (for one object: override it).
    struct Replaced {
        std::string spec, place;
        bool color;
    };
    std::vector<Replaced> replaced;
    for (ObjectSpec& obj : spec.objects) {
        // A map that cannot be read is said under its flag's name, as a scene's under its place:
        // `--height q.png --color q.png` said "q.png: …" of either (found by an exploratory
        // session, thirty-third).
        // A scene file's built-in map that a flag replaces is still checked (below): the file
        // is wrong without the flag ("color": "builtin:nah" under --color was taken).
        if (o.height) {
            if (!obj.height_place.empty()) replaced.push_back({obj.height, obj.height_place, false});
            obj.height = *o.height;
            obj.height_place = "--height";
        }
        if (!o.color.empty()) {
            if (!obj.color_place.empty()) replaced.push_back({obj.color, obj.color_place, true});
            obj.color = o.color;
            obj.color_place = "--color";
        }
        if (o.depth) {
            obj.depth = finite(*o.depth, "--depth"); // (past the float range: refused, as in a scene file)
            obj.depth_place = "--depth";
        }
        if (o.midlevel) obj.midlevel = float(*o.midlevel);
    }
    if (!o.light.empty()) spec.light = direction(parse_dvec3(o.light, "--light"), "--light");
    if (!o.eye.empty()) {
        spec.camera.eye = check_position(parse_dvec3(o.eye, "--eye"), "--eye");
        spec.camera.eye_place = "--eye";
    }
    if (!o.target.empty()) spec.camera.target = check_position(parse_dvec3(o.target, "--target"), "--target");
    if (!o.up.empty()) {
        spec.camera.up = direction(parse_dvec3(o.up, "--up"), "--up");
        spec.camera.up_given = true;
        spec.camera.up_place = "--up";
    }
    if (o.fovy) {
        check_fovy(*o.fovy, "--fovy");
        spec.camera.fovy_deg = float(*o.fovy);
    }
    if (o.elevation) {
        check_elevation(*o.elevation, "--elevation");
        spec.camera.elevation_deg = float(*o.elevation);
    }
    if (o.azimuth) {
        check_azimuth(*o.azimuth, "--azimuth");
        spec.camera.azimuth_deg = float(*o.azimuth);
    }
    // Flags override the file: --elevation or --azimuth over a scene's camera.eye frames the
    // scene from those angles (around its camera.target, if it gives one), as --eye over a
    // scene's angles places the camera there. (They were refused until the sixteenth session.)
    if (spec.camera.eye && o.eye.empty() && (o.elevation || o.azimuth)) spec.camera.eye.reset();
    // Auto-framing's angles with an eye given: nothing frames, and they were ignored silently.
    if (spec.camera.eye && (o.elevation || o.azimuth))
        throw Error(o.elevation ? "--elevation" : "--azimuth",
                    "has no effect with --eye (it places the auto-framed camera; an eye given is where the camera is)");
    // An explicit camera is checked here, where it is known whether each value came from a flag
    // or from the file; without a target (the shell's centre), scene_camera checks it once the
    // scene is loaded (CameraSpec's places name the file or the flag).
    if (spec.camera.eye && spec.camera.target) {
        const std::string eye_subject = !o.eye.empty()      ? "--eye"
                                        : !o.target.empty() ? "--target"
                                                            : o.scene_file + ": camera.eye";
        const ViewProblem problem =
            view_problem(glm::dvec3(*spec.camera.eye), glm::dvec3(*spec.camera.target), glm::dvec3(spec.camera.up));
        if (problem == ViewProblem::SamePoint) throw Error(eye_subject, "eye and target are the same point");
        if (problem == ViewProblem::UpAlongView) {
            if (!o.up.empty()) throw Error("--up", "up is parallel to the viewing direction");
            // (Where a flag moved the eye or target, it is said: the file's up alone read as the fault.)
            if (file.up)
                throw Error(o.scene_file + ": camera.up",
                            "up is parallel to the viewing direction" +
                                (eye_subject.starts_with("--") ? " that " + eye_subject + " gives (give --up)" : std::string()));
            throw Error(eye_subject, std::string("looks straight along the default up direction 0,1,0 (give ") +
                                         (eye_subject.rfind("--", 0) == 0 ? "--up" : "camera.up or --up") + ")");
        }
    }
    if (o.max_triangles < 1) throw Error("--max-triangles", "must be at least 1");
    spec.mesh_options.max_triangles = o.max_triangles;
    if (o.max_image_size) {
        if (*o.max_image_size < 1 || *o.max_image_size > 16384)
            throw Error("--max-image-size", "must be between 1 and 16384 pixels per side");
        spec.image_limits.max_dimension = *o.max_image_size;
        spec.image_limits.max_pixels = std::int64_t(*o.max_image_size) * *o.max_image_size;
    }
    for (const Replaced& r : replaced) {
        try {
            check_builtin_name(r.spec, r.color, spec.image_limits);
        } catch (const Error& e) {
            throw e.under(r.place);
        }
    }
    // A double, checked before it becomes a float: 1e300 was infinity, which said "must be > 0".
    const float uv_scale = finite(o.uv_scale, "--uv-scale");
    if (!(o.uv_scale > 0.0)) throw Error("--uv-scale", "must be > 0");
    if (!(uv_scale >= std::numeric_limits<float>::min()))
        throw Error("--uv-scale", "must be at least 1.2e-38 (the renderer's single precision)");
    spec.mesh_options.uv_scale = uv_scale;
    spec.mesh_options.force_generated_uvs = o.generate_uvs;
    return spec;
}

} // namespace pr
