#include "app/options.hpp"

#include "core/error.hpp"
#include "core/image.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <sstream>

namespace pr {

namespace {

std::string list(const std::vector<std::string>& names, const std::string& prefix = "")
{
    std::string s;
    for (const auto& n : names) s += (s.empty() ? "" : ", ") + prefix + n;
    return s;
}

float finite(double v, const std::string& what)
{
    if (!std::isfinite(v)) throw Error(what, "must be a finite number");
    return static_cast<float>(v);
}

} // namespace

glm::vec3 parse_vec3(const std::string& text, const std::string& option)
{
    glm::vec3 v(0.0f);
    std::istringstream in(text);
    std::string part;
    int n = 0;
    while (std::getline(in, part, ',')) {
        if (n == 3) throw Error(option, "expected x,y,z (three numbers), got '" + text + "'");
        try {
            std::size_t used = 0;
            const double d = std::stod(part, &used);
            if (part.find_first_not_of(" \t", used) != std::string::npos) throw std::invalid_argument("");
            v[n++] = finite(d, option);
        } catch (const std::logic_error&) {
            throw Error(option, "expected x,y,z (three numbers), got '" + text + "'");
        }
    }
    if (n != 3) throw Error(option, "expected x,y,z (three numbers), got '" + text + "'");
    return v;
}

std::pair<int, int> parse_size(const std::string& text, const std::string& option)
{
    int w = 0, h = 0;
    char x = 0, extra = 0;
    std::istringstream in(text);
    if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || (in >> extra))
        throw Error(option, "expected WIDTHxHEIGHT, e.g. 800x600, got '" + text + "'");
    if (w < 1 || h < 1 || w > 16384 || h > 16384)
        throw Error(option, "each side must be between 1 and 16384, got '" + text + "'");
    return {w, h};
}

void add_scene_options(CLI::App& app, SceneOptions& o)
{
    app.add_option("--scene", o.scene_file,
                   "Scene file (JSON): several objects with transform, mesh, height, colour, depth, "
                   "midlevel; camera; light; size. Flags override it (see docs/scenes.md)")
        ->group("Scene");
    app.add_option("--mesh", o.mesh, "Mesh file: OBJ, OFF, PLY or STL")->group("Scene");
    app.add_option("--height", o.height,
                   "Height map: image file (PNG, JPG, BMP, TGA; 8/16-bit; first channel) or builtin:NAME "
                   "with NAME one of " + list(builtin_height_names()) + " (default builtin:bumps)")
        ->group("Scene");
    app.add_option("--color", o.color, "Colour texture: image file or builtin:NAME (" +
                                           list(builtin_color_names()) + "); default a plain colour")
        ->group("Scene");
    app.add_option("--depth", o.depth,
                   "Displacement depth in scene units (default: 4% of the mesh's bounding-box diagonal)")
        ->group("Scene");
    app.add_option("--midlevel", o.midlevel,
                   "Height that stays on the base surface: 0 outward (default), 1 inward, 0.5 centred")
        ->group("Scene");
    app.add_option("--light", o.light,
                   "x,y,z: world direction towards the light (default: above-left of the camera)")
        ->group("Scene");
    app.add_option("--max-triangles", o.max_triangles, "Refuse meshes with more triangles")
        ->group("Scene")
        ->capture_default_str();
    app.add_option("--max-image-size", o.max_image_size,
                   "Refuse height and colour images (and built-in maps) larger than N pixels per "
                   "side (default 16384 per side and 64 Mpixel in all; 1-16384)")
        ->group("Scene");
    app.add_option("--uv-scale", o.uv_scale,
                   "Generated UVs (meshes without UVs): texture repeats across the largest extent")
        ->group("Scene")
        ->capture_default_str();
    app.add_flag("--generate-uvs", o.generate_uvs, "Ignore the mesh's UVs and generate box-projected ones")
        ->group("Scene");

    app.add_option("--eye", o.eye, "x,y,z: camera position (default: auto-framing)")->group("Camera");
    app.add_option("--target", o.target, "x,y,z: point looked at (default: the shell's centre)")
        ->group("Camera");
    app.add_option("--up", o.up, "x,y,z: up direction (default 0,1,0)")->group("Camera");
    app.add_option("--fovy", o.fovy, "Vertical field of view, degrees (default 40)")->group("Camera");
    app.add_option("--elevation", o.elevation,
                   "Auto-framing: degrees above the horizontal plane (default 25)")
        ->group("Camera");
    app.add_option("--azimuth", o.azimuth, "Auto-framing: degrees around the up axis (default 35)")
        ->group("Camera");
    o.size_option = app.add_option("--size", o.size, "Image size WIDTHxHEIGHT")
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
    app.add_option("--cone-backend", o.cone_backend,
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
                           "; prism:MARCHER[:EXIT] for the prism's options)")
            ->group("Technique")
            ->capture_default_str();
    app.add_option("--steps", o.steps, "Linear search steps over the full height range (1-1024)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--refine", o.refine, "Binary refinement steps after the linear search (0-32)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--marcher", o.marcher, "prism: ray marcher, " + marcher_names() +
                                           " (in lists: prism:MARCHER)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--prism-exit", o.prism_exit,
                   "prism: walk (the ray goes from prism to prism across exact exits; only the shell's "
                   "outside is drawn), exact (each front face of every prism is drawn and marched to its "
                   "exact exit) or vertex (per-vertex plane distances, interpolated). In lists: "
                   "prism:MARCHER:EXIT")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--prism-shell", o.prism_shell,
                   "prism walk: tight (each top cap at the highest the height field gets around its "
                   "corners) or full (top caps at height 1). In lists: prism:MARCHER:walk:SHELL")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--normal-quality", o.normal_quality,
                   "Normal from heights: gather (4-tap), central (differences), sobel (3x3)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--shadows", o.shadows,
                   "Self-shadowing: march from the hit towards the light through the height field "
                   "(none|hard|soft)")
        ->group("Technique")
        ->capture_default_str();
    app.add_flag("--depth-write", o.depth_write,
                 "Base-surface techniques write the depth of the point they show")
        ->group("Technique");
    app.add_option("--reference-level", o.reference_level,
                   "reference: split each triangle into LEVEL^2 (0: automatic, edges about one texel "
                   "or one pixel, whichever is coarser)")
        ->group("Technique")
        ->capture_default_str();
    app.add_option("--reference-max-triangles", o.reference_max_triangles,
                   "reference: lower an automatic level to stay within this many triangles")
        ->group("Technique")
        ->capture_default_str();
}

ReferenceOptions make_reference_options(const TechniqueOptions& o)
{
    if (o.reference_level < 0 || o.reference_level > 256)
        throw Error("--reference-level", "must be between 0 (automatic) and 256");
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
        if (s.technique != Technique::Prism || parts.size() > 4)
            throw Error(option, "'" + technique + "': only prism takes options (prism:MARCHER[:EXIT[:SHELL]])");
        s.marcher = parse_marcher(parts[1], option);
        if (parts.size() >= 3) s.prism_exit = parse_prism_exit(parts[2], option);
        if (parts.size() == 4) {
            if (s.prism_exit != PrismExit::Walk)
                throw Error(option, "'" + technique + "': only the walk takes a shell (prism:MARCHER:walk:SHELL)");
            s.full_shell = parse_prism_shell(parts[3], option);
        }
    }
    if (o.steps < 1 || o.steps > 1024) throw Error("--steps", "must be between 1 and 1024");
    if (o.refine < 0 || o.refine > 32) throw Error("--refine", "must be between 0 and 32");
    s.steps = o.steps;
    s.refine = o.refine;
    s.normal_quality = parse_normal_quality(o.normal_quality);
    s.depth_write = o.depth_write;
    s.shadows = parse_shadows(o.shadows, "--shadows");
    return s;
}

namespace {

using json = nlohmann::json;

glm::vec3 json_vec3(const json& j, const std::string& where)
{
    if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
        throw Error(where, "expected an array of three numbers");
    return {finite(j[0].get<double>(), where), finite(j[1].get<double>(), where),
            finite(j[2].get<double>(), where)};
}

float json_float(const json& j, const std::string& where)
{
    if (!j.is_number()) throw Error(where, "expected a number");
    return finite(j.get<double>(), where);
}

std::string json_path(const json& j, const std::string& where, const std::filesystem::path& base)
{
    if (!j.is_string()) throw Error(where, "expected a string");
    const std::string s = j.get<std::string>();
    if (s.rfind("builtin:", 0) == 0 || s.empty()) return s;
    const std::filesystem::path p(s);
    return p.is_absolute() ? s : (base / p).lexically_normal().string();
}

glm::mat4 json_transform(const json& j, const std::string& where)
{
    if (!j.is_object()) throw Error(where, "expected an object with translate/rotate/scale or matrix");
    if (j.contains("matrix")) {
        const json& m = j["matrix"];
        if (!m.is_array() || m.size() != 16) throw Error(where + ".matrix", "expected 16 numbers (row-major)");
        glm::mat4 r(1.0f);
        for (int i = 0; i < 16; ++i) r[i % 4][i / 4] = json_float(m[i], where + ".matrix");
        return r;
    }
    glm::mat4 t(1.0f);
    if (j.contains("translate")) t = glm::translate(t, json_vec3(j["translate"], where + ".translate"));
    if (j.contains("rotate")) {
        // Degrees about X, then Y, then Z (applied to the object in that order).
        const glm::vec3 r = json_vec3(j["rotate"], where + ".rotate");
        t = glm::rotate(t, glm::radians(r.z), {0, 0, 1});
        t = glm::rotate(t, glm::radians(r.y), {0, 1, 0});
        t = glm::rotate(t, glm::radians(r.x), {1, 0, 0});
    }
    if (j.contains("scale")) {
        const json& s = j["scale"];
        const glm::vec3 v = s.is_number() ? glm::vec3(json_float(s, where + ".scale"))
                                          : json_vec3(s, where + ".scale");
        if (v.x == 0.0f || v.y == 0.0f || v.z == 0.0f) throw Error(where + ".scale", "must not be zero");
        t = glm::scale(t, v);
    }
    for (const auto& [key, value] : j.items())
        if (key != "matrix" && key != "translate" && key != "rotate" && key != "scale")
            throw Error(where, "unknown key '" + key + "'");
    return t;
}

void read_scene_file(const std::string& file, SceneSpec& spec, std::string& size)
{
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(file, "cannot open");
    json j;
    try {
        j = json::parse(in);
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
                    if (k == "mesh") o.mesh = json_path(v, w, base);
                    else if (k == "height") o.height = json_path(v, w, base);
                    else if (k == "color") o.color = json_path(v, w, base);
                    else if (k == "depth") o.depth = json_float(v, w);
                    else if (k == "midlevel") o.midlevel = json_float(v, w);
                    else if (k == "base_color") o.base_color = json_vec3(v, w);
                    else if (k == "transform") o.transform = json_transform(v, w);
                    else throw Error(ow, "unknown key '" + k + "'");
                }
                if (o.mesh.empty()) throw Error(ow, "has no \"mesh\"");
                spec.objects.push_back(o);
            }
        } else if (key == "camera") {
            if (!value.is_object()) throw Error(where, "expected an object");
            for (const auto& [k, v] : value.items()) {
                const std::string w = where + "." + k;
                if (k == "eye") spec.camera.eye = json_vec3(v, w);
                else if (k == "target") spec.camera.target = json_vec3(v, w);
                else if (k == "up") spec.camera.up = json_vec3(v, w);
                else if (k == "fovy") spec.camera.fovy_deg = json_float(v, w);
                else if (k == "elevation") spec.camera.elevation_deg = json_float(v, w);
                else if (k == "azimuth") spec.camera.azimuth_deg = json_float(v, w);
                else throw Error(where, "unknown key '" + k + "'");
            }
        } else if (key == "light") {
            spec.light = json_vec3(value, where);
        } else if (key == "size") {
            if (!value.is_string()) throw Error(where, "expected \"WIDTHxHEIGHT\"");
            size = value.get<std::string>();
        } else {
            throw Error(file, "unknown key '" + key + "'");
        }
    }
    if (spec.objects.empty()) throw Error(file, "has no \"objects\"");
}

} // namespace

SceneSpec make_scene_spec(const SceneOptions& o)
{
    SceneSpec spec;
    std::string size = o.size;
    std::string scene_size;
    if (!o.scene_file.empty()) read_scene_file(o.scene_file, spec, scene_size);
    // Size: the flag if given, else the scene file's, else the default.
    if (!scene_size.empty() && !(o.size_option && o.size_option->count())) size = scene_size;
    const auto [w, h] = parse_size(size, "--size");
    spec.width = w;
    spec.height = h;

    if (!o.mesh.empty()) {
        if (spec.objects.size() > 1)
            throw Error("--mesh", "cannot override the mesh of a scene with several objects");
        if (spec.objects.empty()) spec.objects.emplace_back();
        spec.objects[0].mesh = o.mesh;
    }
    if (spec.objects.empty()) throw Error("--mesh", "required (or --scene FILE.json)");
    // Object flags apply to every object of the scene (for one object: override it).
    for (ObjectSpec& obj : spec.objects) {
        if (o.height) obj.height = *o.height;
        if (!o.color.empty()) obj.color = o.color;
        if (o.depth) obj.depth = *o.depth;
        if (o.midlevel) obj.midlevel = *o.midlevel;
        if (obj.depth && (!std::isfinite(*obj.depth) || *obj.depth < 0.0f))
            throw Error("--depth", "must be a finite number >= 0");
        if (!std::isfinite(obj.midlevel) || obj.midlevel < 0.0f || obj.midlevel > 1.0f)
            throw Error("--midlevel", "must be between 0 and 1");
    }
    if (!o.light.empty()) {
        spec.light = parse_vec3(o.light, "--light");
        if (glm::length(*spec.light) == 0.0f) throw Error("--light", "must not be the zero vector");
    }
    if (!o.eye.empty()) spec.camera.eye = parse_vec3(o.eye, "--eye");
    if (!o.target.empty()) spec.camera.target = parse_vec3(o.target, "--target");
    if (!o.up.empty()) spec.camera.up = parse_vec3(o.up, "--up");
    if (glm::length(spec.camera.up) == 0.0f) throw Error("--up", "must not be the zero vector");
    if (o.fovy) spec.camera.fovy_deg = *o.fovy;
    if (!(spec.camera.fovy_deg > 0.5f && spec.camera.fovy_deg < 179.0f))
        throw Error("--fovy", "must be between 0.5 and 179 degrees");
    if (o.elevation) spec.camera.elevation_deg = *o.elevation;
    if (o.azimuth) spec.camera.azimuth_deg = *o.azimuth;
    if (!std::isfinite(spec.camera.elevation_deg) || std::abs(spec.camera.elevation_deg) > 90.0f)
        throw Error("--elevation", "must be between -90 and 90 degrees");
    if (!std::isfinite(spec.camera.azimuth_deg)) throw Error("--azimuth", "must be a finite number");
    if (o.max_triangles < 1) throw Error("--max-triangles", "must be at least 1");
    spec.mesh_options.max_triangles = o.max_triangles;
    if (o.max_image_size) {
        if (*o.max_image_size < 1 || *o.max_image_size > 16384)
            throw Error("--max-image-size", "must be between 1 and 16384 pixels per side");
        spec.image_limits.max_dimension = *o.max_image_size;
        spec.image_limits.max_pixels = std::int64_t(*o.max_image_size) * *o.max_image_size;
    }
    if (!(o.uv_scale > 0.0f) || !std::isfinite(o.uv_scale)) throw Error("--uv-scale", "must be > 0");
    spec.mesh_options.uv_scale = o.uv_scale;
    spec.mesh_options.force_generated_uvs = o.generate_uvs;
    return spec;
}

} // namespace pr
