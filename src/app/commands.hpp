#pragma once
// One function per subcommand: each registers its options on the parser and returns the action
// to run after parsing.
#include "app/options.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "render/renderer.hpp"

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
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

// A float as a report gives it: its 7 digits (0.3, not 0.30000001192092896).
inline double float_json(float v)
{
    char digits[32];
    std::snprintf(digits, sizeof digits, "%.7g", double(v));
    // (+ 0.0: a depth given as -0.0 was reported as -0.0; found by an exploratory session,
    // forty-sixth.)
    return std::strtod(digits, nullptr) + 0.0;
}

// The march's quality a draw took: "depth_write" and, where the technique reads them, "steps",
// "refine" and "normal_quality" (render, and each row of compare and bench; bench's rows had none
// until the twenty-fourth session, only the report's steps and refine: a row drawn with
// --depth-write did not say so). Until the forty-third session every row had steps and refine:
// a reference's or a flat row's read as if it had marched with them.
inline nlohmann::json quality_json(const DrawSettings& s)
{
    nlohmann::json j = {{"depth_write", s.depth_write}};
    if (reads_steps(s)) j["steps"] = s.steps;
    if (reads_refine(s)) j["refine"] = s.refine;
    // (Where the technique reads it: the pictures of gather and sobel differ by up to 12 dB, and
    // the reports could not tell them apart; found by an exploratory session, thirty-fourth.)
    if (reads_normal_quality(s)) j["normal_quality"] = normal_quality_name(s.normal_quality);
    return j;
}

// What each object was drawn with: the mesh and height map as named, and the depth and midlevel
// used (the automatic depth, 4 % of the diagonal, was written nowhere), for every report.
inline nlohmann::json scene_json(const Scene& scene)
{
    nlohmann::json objects = nlohmann::json::array();
    for (const SceneObject& o : scene.objects) {
        // (The height as this object names it: objects naming one file share its field, whose name
        // is the first one's; found by an exploratory session, thirty-seventh.)
        const std::string height = !o.height_name.empty() ? o.height_name : (o.height ? o.height->name : std::string());
        nlohmann::json j = {{"mesh", o.mesh_name},
                            {"height", height},
                            {"depth", float_json(o.depth)},
                            {"midlevel", float_json(o.midlevel)}};
        // The colour map and a transform other than the identity (row by row), where there are
        // (a report left them out: two objects of one mesh read the same; thirty-sixth session).
        // The scene's transform, not the one drawn with, which holds the mesh's origin too: a mesh
        // whose file lies far from 0 was reported moved by it (thirty-seventh session).
        // Or the plain colour it was drawn with: two objects of one mesh in red and in blue read
        // the same (found by an exploratory session, forty-fourth).
        if (o.color)
            j["color"] = o.color_name;
        else
            j["base_color"] = {float_json(o.base_color.r), float_json(o.base_color.g), float_json(o.base_color.b)};
        if (const glm::dmat4& m = o.placement; m != glm::dmat4(1.0)) {
            nlohmann::json rows = nlohmann::json::array();
            // (+ 0.0: a mirror's zeros were -0.0; found by an exploratory session, forty-first.)
            for (int r = 0; r < 4; ++r) rows.push_back({m[0][r] + 0.0, m[1][r] + 0.0, m[2][r] + 0.0, m[3][r] + 0.0});
            j["transform"] = rows;
        }
        objects.push_back(std::move(j));
    }
    return objects;
}

// The shadows a draw drew: "shadows" (none where it draws none: flat),
// and with soft ones "light_size" (degrees, to a float's 7 digits: 0.3, not 0.30000001192092896).
inline nlohmann::json shadows_json(const DrawSettings& s)
{
    nlohmann::json j = {{"shadows", shadows_name(drawn_shadows(s))}};
    if (reads_light_size(s)) j["light_size"] = float_json(s.light_size);
    return j;
}

// "a, b and c".
inline std::string listed_text(const std::vector<std::string>& items)
{
    std::string text;
    for (std::size_t i = 0; i < items.size(); ++i)
        text += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
    return text;
}

// More objects than this are summed up in the reference's lines (their levels are in the JSON).
constexpr std::size_t kObjectsListed = 6;

// "level 3", or "levels 3 to 6": the range of `levels` (not empty).
inline std::string level_range_text(const std::vector<int>& levels)
{
    const auto [lo, hi] = std::minmax_element(levels.begin(), levels.end());
    return *lo == *hi ? "level " + std::to_string(*lo) : "levels " + std::to_string(*lo) + " to " + std::to_string(*hi);
}

// "level 4", or with objects at different levels "levels 5 and 6" (each object's, in order), and
// past kObjectsListed objects "levels 3 to 10 over 50 objects" (a scene of 50 listed 50 levels;
// found by an exploratory session, fifty-third).
inline std::string reference_levels_text(const Renderer::ReferenceStats& stats)
{
    const bool same = std::all_of(stats.levels.begin(), stats.levels.end(), [&](int l) { return l == stats.level; });
    if (same) return "level " + std::to_string(stats.level);
    if (stats.levels.size() > kObjectsListed)
        return level_range_text(stats.levels) + " over " + std::to_string(stats.levels.size()) + " objects";
    std::vector<std::string> levels;
    for (int l : stats.levels) levels.push_back(std::to_string(l));
    return "levels " + listed_text(levels);
}

// What --reference-max-triangles lowered: "level 4" with one object, else which objects' ("object
// 0 at level 4"): with several, the levels of all were said, the ones it left alone too (found by
// a review, thirty-fifth session).
inline std::string reference_capped_text(const Renderer::ReferenceStats& stats)
{
    if (stats.levels.size() <= 1) return "level " + std::to_string(stats.level);
    std::vector<std::string> capped;
    std::vector<int> levels;
    for (std::size_t k = 0; k < stats.levels.size() && k < stats.capped_objects.size(); ++k)
        if (stats.capped_objects[k]) {
            capped.push_back("object " + std::to_string(k) + " at level " + std::to_string(stats.levels[k]));
            levels.push_back(stats.levels[k]);
        }
    if (capped.size() > kObjectsListed) // ("12 objects at levels 3 to 5", "8 objects at level 1")
        return std::to_string(capped.size()) + " objects at " + level_range_text(levels);
    return listed_text(capped);
}

// A reference whose automatic level --reference-max-triangles lowered: said on stderr by the
// commands that measure against it or time it (compare, bench; render prints its level line).
// Until the twenty-fourth session only the JSON said so (found by an exploratory session).
inline void warn_if_capped(const Renderer::ReferenceStats& stats, const std::string& command)
{
    if (!stats.capped) return;
    warn(command + ": the reference is capped at " + reference_capped_text(stats) + " (" +
         std::to_string(stats.triangles) + (stats.levels.size() > 1 ? " triangles in all" : " triangles") +
         ") by --reference-max-triangles, coarser than a texel and a pixel per edge" +
         (command == "compare" ? ": the metrics are against that surface" : ""));
}

// A reference whose shadow map came out coarse against the pixels it shades
// (Renderer::ShadowFit): on 1 % of what the image shows or more, said by compare and render, whose
// reference's shadows then lose detail there (a far or large object in view).
inline void warn_if_shadow_map_coarse(const Renderer::ShadowFit& fit, const std::string& command)
{
    if (fit.coarse_share < 0.01) return;
    warn(fmt::format("{}: the reference's shadow map spans everything the image shows, and on {} % of what it "
                     "shows its texels are wider than two pixels (up to {:.1f}): its shadows lose their detail "
                     "there (a far or large object in view stretches the map; docs/compare.md){}",
                     command, bounded_text(100.0 * fit.coarse_share, 0, 0.0, 100.0), fit.widest,
                     command == "compare" ? ", and the metrics count that against the techniques" : ""));
}

// A view that drew nothing: a valid picture (a view away from the scene) but rarely the one
// meant, said on stderr by render (its --out), compare and bench (the command's name). Until the
// thirtieth session compare reported such a view as a perfect match (IoU 1, PSNR "same") and bench
// as 0 fragments, without a word (found by an exploratory session).
// (--depth too, since the forty-first session: auto-framing fits the displaced shell, and with a
// depth a million times the mesh's size the mesh covered no pixel of the view framed on it; found
// by an exploratory session.)
inline void warn_nothing_drawn(const std::string& subject)
{
    warn(subject + ": nothing was drawn: the scene is out of view or covers no pixel centre "
                   "(check the camera, --fovy and --size; auto-framing fits the displaced shell, which a large "
                   "--depth makes far larger than the mesh)");
}

// Whether an image has no alpha at all (with --msaa a sliver may cover a fraction of a pixel:
// any alpha counts as drawn).
inline bool drew_nothing(const RgbaImage& image)
{
    for (std::size_t i = 3; i < image.pixels.size(); i += 4)
        if (image.pixels[i] > 0) return false;
    return true;
}

// Pixels an image covers: alpha >= 128, the contract's coverage mask.
inline std::size_t covered_pixels(const RgbaImage& image)
{
    std::size_t covered = 0;
    for (std::size_t i = 3; i < image.pixels.size(); i += 4) covered += image.pixels[i] >= 128;
    return covered;
}

// The camera a report's images were drawn with (compare, render); its floats as the shortest
// decimals that read back as them (--fovy 178.9 was reported as 178.89999389648438, the float's
// exact value; found by an exploratory session).
inline nlohmann::json camera_json(const Camera& c)
{
    return {{"eye", {c.eye.x, c.eye.y, c.eye.z}},
            {"target", {c.target.x, c.target.y, c.target.z}},
            {"up", {shortest_decimal(c.up.x), shortest_decimal(c.up.y), shortest_decimal(c.up.z)}},
            {"fovy", shortest_decimal(c.fovy_deg)}};
}

// What else the images were drawn with (render, compare, bench): the direction towards the light
// (unit, in the world: the default one turns with the camera), the scale of generated UVs and
// whether every mesh's UVs were generated (--generate-uvs). The same scene drawn under another
// --light or --uv-scale gave the same report (found by an exploratory session, forty-sixth).
inline nlohmann::json lighting_json(glm::vec3 light, const MeshOptions& mesh)
{
    return {{"light", {shortest_decimal(light.x), shortest_decimal(light.y), shortest_decimal(light.z)}},
            {"uv_scale", float_json(mesh.uv_scale)},
            {"generate_uvs", mesh.force_generated_uvs}};
}

// How the reference geometry was built (compare, render --technique reference).
inline nlohmann::json reference_json(const Renderer::ReferenceStats& r)
{
    return {{"level", r.level}, {"levels", r.levels}, {"triangles", r.triangles}, {"bytes", r.bytes}, {"build_ms", r.build_ms}, {"capped", r.capped}};
}

// A report's text. File names are bytes, not always UTF-8, and JSON strings must be: a byte that
// is not UTF-8 becomes U+FFFD (nlohmann threw "invalid UTF-8 byte", after the work, and nothing
// was written: `conemap --height $'n\xff.png' --json r.json`).
inline std::string report_text(const nlohmann::json& report)
{
    return report.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// A number in a table: `digits` after the point.
inline std::string fixed(double v, int digits)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*f", digits, v);
    return buf;
}

} // namespace pr
