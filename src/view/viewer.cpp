// The viewer's frame loop, input and panel. Drawing is the Renderer's (render/renderer.hpp); this
// file only decides what to draw with which settings, copies the result to the window through
// the Compositor, and draws the Dear ImGui panel on top.
#include "view/viewer.hpp"

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/stats.hpp"
#include "gl/gl.hpp"
#include "maps/conemap.hpp"
#include "render/shader_program.hpp"
#include "view/compositor.hpp"
#include "view/glfw_window.hpp"
#include "view/orbit.hpp"
#include "view/shader_watch.hpp"

#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_opengl3.h>
#include <imgui_internal.h> // (ClosePopupsOverWindow: Esc closes an open list)

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <future>
#include <memory>
#include <mutex>
#include <set>
#include <utility>

namespace pr::view {

WireOverlay parse_wire_overlay(const std::string& name, const std::string& option)
{
    if (name == "none") return WireOverlay::None;
    if (name == "base") return WireOverlay::Base;
    if (name == "shell") return WireOverlay::Shell;
    throw Error(option, "unknown overlay '" + name + "' (expected none|base|shell)");
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t)
{
    return std::chrono::duration<double>(Clock::now() - t).count();
}

std::string lower_extension(const std::string& path)
{
    std::string ext = std::filesystem::path(path).extension().string();
    for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return ext;
}

// A combo box over `options`, each shown by `name`; true when the user picked one.
template <typename T, typename Name>
bool choice_combo(const std::string& id, T& value, const std::vector<T>& options, Name name)
{
    bool changed = false;
    if (ImGui::BeginCombo(id.c_str(), name(value).c_str())) {
        for (const T& option : options) {
            if (ImGui::Selectable(name(option).c_str(), option == value)) {
                value = option;
                changed = true;
            }
        }
        ImGui::EndCombo();
    }
    return changed;
}

// "pom", "prism:relief", "prism:relief:exact", "prism:cone:walk:full": as --techniques lists name
// them (the default walk with its tight shell is left out).
std::string display_name(const DrawSettings& d)
{
    const std::string t = technique_name(d.technique);
    if (d.technique != Technique::Prism) return t;
    std::string name = t + ":" + marcher_name(d.marcher);
    if (d.prism_exit != PrismExit::Walk) return name + ":" + prism_exit_name(d.prism_exit);
    return d.full_shell ? name + ":walk:full" : name;
}

// What the panel shows for one technique (one half of the split view).
struct HalfStats {
    double draw_ms = 0.0;              // smoothed
    std::vector<double> draws;         // every timed draw (median at exit)
    double samples_per_fragment = -1.0; // < 0: not counted yet
    double prisms_per_fragment = -1.0;  // the prism walk's (bench's ppf_mean); < 0: none
    std::uint64_t fragments = 0;
};

// The technique drawn while the cone maps of `d` are built: relief, the linear search the cone
// marchers skip through, and the default inside the prism.
DrawSettings while_cone_maps_build(DrawSettings d)
{
    if (d.technique == Technique::Cone || d.technique == Technique::RelaxedCone) d.technique = Technique::Relief;
    if (d.technique == Technique::Prism) d.marcher = Marcher::Relief;
    return d;
}

// Cone maps the viewer builds on a thread while it goes on drawing (a relaxed map of 1024² takes
// seconds): what for (`map`), how far (`done`, 0..1 over all of them), and the maps.
struct ConeJob {
    using Maps = std::vector<std::pair<std::shared_ptr<const HeightField>, ConeMap>>;
    struct Result {
        Maps maps;
        bool built = false; // a map was built, not all read from the cache
    };
    AuxMap map = AuxMap::None;
    std::string what; // "relaxed cone map of builtin:noise@1024"
    Clock::time_point start = Clock::now();
    std::shared_ptr<std::atomic<double>> done = std::make_shared<std::atomic<double>>(0.0);
    std::shared_ptr<std::atomic<bool>> cancel = std::make_shared<std::atomic<bool>>(false);
    std::future<Result> maps;
    int frames_meanwhile = 0; // frames drawn with while_cone_maps_build()
    std::vector<const HeightField*> fields; // what it builds for
};

class Viewer {
public:
    Viewer(Session& session, GlfwWindow& window, const ViewerOptions& options)
        : s_(session), window_(window), o_(options)
    {
        half_[0] = options.left;
        half_[1] = options.right ? *options.right : options.left;
        split_ = options.right.has_value();
        if (!split_) // the right half when split is switched on later: prism (or POM next to prism)
            half_[1].technique = half_[0].technique == Technique::Prism ? Technique::Pom : Technique::Prism;
        divider_ = std::clamp(options.divider, 0.0f, 1.0f);
        render_scale_ = std::clamp(options.render_scale, 0.05f, 1.0f);
        overlay_ = options.overlay;
        reference_overlay_ = options.reference_overlay;
        initial_camera_ = s_.camera;
        angles_from_direction(s_.light, s_.spec.camera.up, light_azimuth_, light_elevation_);
        remember_scene();
        if (!o_.shader_dir.empty()) watch_.emplace(o_.shader_dir);
        pending_drops_ = o_.drops;
        // The panel's log shows the warnings stderr shows: the scene's as loaded, then a dropped
        // file's, a cone map's cache's (they reached the terminal only; thirty-fifth session).
        observe_warnings([this](const std::string& message) {
            std::lock_guard lock(warned_mutex_);
            warned_.push_back(message);
        });
    }

    ~Viewer()
    {
        observe_warnings({});
        cancel_cone_job();
    }
    Viewer(const Viewer&) = delete;
    Viewer& operator=(const Viewer&) = delete;

    int run();

private:
    // `d`, or while its cone maps are built on a thread (started here when neither the renderer
    // nor the cache has them) what is drawn meanwhile. Frames that draw it do not count towards
    // --frames (run), so that the screenshot, the times and the counts are the technique's own.
    DrawSettings drawable(const DrawSettings& d);
    void poll_cone_job(); // hands finished maps to the renderer
    void cancel_cone_job();
    void remember_scene();
    void init_imgui();
    void shutdown_imgui();
    void handle_input();
    void handle_keys();
    void handle_drop(const std::string& path);
    void reload_scene(SceneSpec spec, bool reset_camera, bool keep_first_height = false);
    void apply_displacement();
    void render_scene();
    void draw_panel();
    void draw_build_box();
    void technique_combo(int half);
    bool take_screenshot(const std::string& path); // false where it could not (said)
    void screenshot_now(); // key P and the panel's button, once the frame is drawn: --screenshot's path, else a numbered name
    void reset_view();     // key R and the panel's button
    void reload_shaders(); // the watcher and the panel's button
    RgbaImage read_window() const;
    bool half_needs_reference() const;
    // Framebuffer pixels per window unit, and the cursor's column in framebuffer pixels.
    static float framebuffer_scale()
    {
        const float s = ImGui::GetIO().DisplayFramebufferScale.x;
        return s > 0.0f ? s : 1.0f;
    }
    static float cursor_column() { return ImGui::GetIO().MousePos.x * framebuffer_scale(); }
    // The first renderer column of the right half.
    int divider_column() const
    {
        const int w = s_.renderer->width();
        return std::clamp(int(std::lround(divider_ * float(w))), 0, w);
    }
    std::string settings_key() const;
    void request_screenshot(); // P: a screenshot of the technique's own picture, as soon as drawn
    bool screenshot_stale() const; // a P waits for settings changed since it was pressed
    void drop_screenshots(const char* why, bool as_error); // the pending Ps, said in the log (and stderr)
    // Each object's bounds grown as the scene's (apply_displacement), so that a far-away object
    // does not push the near plane past the near ones, and by the carve of its depth now.
    void fit_planes() { fit_scene_clip_planes(s_.camera, s_.scene, bounds_.radius - base_radius_); }
    void error(const std::string& message); // warns, and shows it in the panel's log
    void note(const std::string& message);  // the panel's log only (newest last, the last six)
    void log_warnings();                    // the warnings said since, in the panel's log

    Session& s_;
    GlfwWindow& window_;
    const ViewerOptions& o_;
    std::optional<ConeJob> cone_job_;
    // Cache entries drawable() found it could not read (damaged): not read again every frame while
    // they wait for a build (each read hashed every texel and read the file).
    std::set<std::pair<const HeightField*, ConeKind>> unreadable_entries_;
    bool cone_builds_inline_ = false; // after a background build failed: in the draw, as render does
    std::optional<Compositor> compositor_;
    std::optional<ShaderWatch> watch_;
    Clock::time_point last_watch_ = Clock::now();

    std::array<DrawSettings, 2> half_;
    std::array<HalfStats, 2> stats_;
    bool split_ = false;
    float divider_ = 0.5f;
    WireOverlay overlay_ = WireOverlay::None;
    bool reference_overlay_ = false;
    bool reference_ready_ = false;
    bool count_samples_ = true;
    float render_scale_ = 1.0f; // renderer pixels per framebuffer pixel (panel: faster on llvmpipe)
    bool continuous_ = false;
    bool show_panel_ = true;
    bool dirty_ = true;
    int frame_ = 0;
    int rendered_ = 0;
    bool presented_ = false; // the compositor has drawn once (run: before the scene's first draw)
    bool scene_drawn_ = false; // this loop turn drew the scene (not the panel alone)
    // --frames counts the frames drawn with the techniques themselves: a frame that drew a half
    // with relief while its cone maps were built (drew_meanwhile_) is not one of them.
    int counted_ = 0;
    bool drew_meanwhile_ = false;
    // The picture shown was drawn with a half meanwhile (which halves): P waits for the technique's
    // own picture, and the panel says what the half waits for.
    bool image_meanwhile_ = false;
    std::array<bool, 2> half_meanwhile_{};
    bool screenshot_waiting_ = false; // said once that P waits
    std::string screenshot_key_;      // the settings P waits to draw (settings_key)
    bool screenshot_settled_ = false; // its picture drawn once, under a panel laid out after it

    Camera initial_camera_;
    Sphere bounds_;
    float light_azimuth_ = 0.0f, light_elevation_ = 0.0f;
    // Displacement as loaded (per object) and the panel's edits of it.
    std::vector<float> base_depth_;
    std::vector<float> base_midlevel_;
    double base_radius_ = 1.0; // the scene's shell radius at the depth it was loaded with
    float depth_ = 0.0f;    // object 0's depth; the others follow (follow_panel)
    float midlevel_ = 0.0f; // object 0's midlevel; the others follow

    enum class Drag { None, Orbit, Pan, Light, Divider };
    Drag drag_ = Drag::None;

    std::string shader_error_;  // the last compile error (panel), cleared by a good draw
    // compositor.frag's, cleared by its good reload (a good draw of the scene cleared it: it was
    // never shown in red; found by an exploratory session, thirty-fifth)
    std::string compositor_error_;
    // Shaders were reloaded this frame: its draw compiles them, and it is not timed (a reload's
    // compile, up to a second on llvmpipe, went into the frame times; found by a review).
    bool frame_compiles_ = false;
    std::string blocked_key_;   // settings that failed to draw; retried when they or shaders change
    std::vector<int> held_taps_; // keys tapped before this frame, held down for Dear ImGui in it
    std::vector<std::string> pending_drops_;
    std::deque<std::string> log_; // load errors, warnings and notices (newest last)
    std::mutex warned_mutex_;     // (warnings come from the cone maps' thread too)
    std::vector<std::string> warned_; // warnings not yet in the log
    float panel_width_ = 0.0f;    // the panel's width as the user left it (0: not drawn yet)
    float panel_content_y_ = 0.0f; // the height of what the panel held in its last layout
    bool panel_refit_ = false;     // what it holds changed in the last layout: lay it out again
    std::deque<float> frame_ms_; // recent frame times (plot)
    std::vector<double> all_frame_ms_;
    int screenshot_counter_ = 0;
    // P (or the panel's button) this frame: taken once the frame is drawn (screenshot_now). It was
    // taken when the key was read, before the frame's draw: the picture lagged a frame behind (a
    // technique key and P in one frame saved the technique before; P in the first frame, nothing).
    // A count: two P in one frame (or while a map builds) write two files (numbered names).
    int screenshot_pending_ = 0;
    std::array<std::string, 2> warmed_; // each half's variant last drawn plain (variant_key)
};

void Viewer::error(const std::string& message)
{
    warn_each_time(message);
    note(one_line(message)); // (as the warning's observer hands it on: log_warnings skips it)
}

void Viewer::note(const std::string& message)
{
    log_.push_back(message);
    while (log_.size() > 6) log_.pop_front();
}

void Viewer::log_warnings()
{
    std::vector<std::string> warned;
    {
        std::lock_guard lock(warned_mutex_);
        warned.swap(warned_);
    }
    for (const std::string& message : warned)
        if (std::find(log_.begin(), log_.end(), message) == log_.end()) // (error() put it there)
            note("warning: " + message);
}

void Viewer::remember_scene()
{
    base_depth_.clear();
    base_midlevel_.clear();
    for (const SceneObject& o : s_.scene.objects) {
        base_depth_.push_back(o.depth);
        base_midlevel_.push_back(o.midlevel);
    }
    depth_ = base_depth_.empty() ? 0.0f : base_depth_[0];
    midlevel_ = base_midlevel_.empty() ? 0.0f : base_midlevel_[0];
    bounds_ = s_.scene.shell_bounds;
    base_radius_ = bounds_.radius;
    reference_ready_ = false;
}

// Depth and midlevel from the panel: the renderer copies them at upload, so upload again (the
// meshes and textures are small next to a frame on llvmpipe). The shell's bounds grow by at most
// how far any corner moved, which keeps the clip planes safe.
void Viewer::apply_displacement()
{
    float grow = 0.0f;
    for (std::size_t i = 0; i < s_.scene.objects.size(); ++i) {
        SceneObject& o = s_.scene.objects[i];
        const PanelDisplacement d = follow_panel(base_depth_[0], base_midlevel_[0], depth_, midlevel_,
                                                 base_depth_[i], base_midlevel_[i], i == 0);
        o.depth = d.depth;
        o.midlevel = d.midlevel;
        const glm::mat3 m(o.transform);
        const float scale = std::max({glm::length(m[0]), glm::length(m[1]), glm::length(m[2])});
        const float moved = std::abs(o.depth - base_depth_[i]) + o.depth * std::abs(o.midlevel - base_midlevel_[i]) +
                            base_depth_[i] * std::abs(o.midlevel - base_midlevel_[i]);
        grow = std::max(grow, moved * scale);
    }
    bounds_.radius = base_radius_ + grow;
    try {
        s_.renderer->upload(s_.scene);
    } catch (const Error& e) {
        error(e.what());
    }
    reference_ready_ = false;
    fit_planes();
    dirty_ = true;
}

void Viewer::reload_scene(SceneSpec spec, bool reset_camera, bool keep_first_height)
{
    Scene scene = load_scene(spec); // throws pr::Error naming the file: the old scene stays
    unreadable_entries_.clear(); // (of the old height fields)
    const bool keep = keep_first_height && !scene.objects.empty() && !s_.scene.objects.empty();
    // A dropped mesh keeps the first object's height map: the very field, so its cone maps, held
    // or building, serve on. The build was cancelled and started again for the same map (5 s of a
    // relaxed builtin:noise@768 lost; found by an exploratory session, thirty-second). A build
    // that is not for it alone is for height maps no longer drawn too: cancelled.
    if (keep) scene.objects[0].height = s_.scene.objects[0].height;
    if (!keep || (cone_job_ && (cone_job_->fields.size() != 1 ||
                                cone_job_->fields.front() != scene.objects[0].height.get())))
        cancel_cone_job(); // (one for other maps too: the kept one's is restarted, from the cache if built)
    try {
        s_.renderer->upload(scene);
    } catch (const Error&) {
        s_.renderer->upload(s_.scene);
        throw;
    }
    s_.scene = std::move(scene);
    s_.spec = std::move(spec);
    remember_scene();
    if (reset_camera) {
        s_.camera = scene_camera(s_.spec, s_.scene);
        initial_camera_ = s_.camera;
    } else {
        fit_planes();
    }
    // The counts were the old scene's: the next frame counts again (samples are counted every
    // tenth frame, and a short --frames run after a drop reported the old scene's figure).
    // (And the --frames summary's draws: they were the old scene's, found by an exploratory session,
    // thirty-eighth.)
    for (HalfStats& st : stats_) {
        st.samples_per_fragment = -1.0, st.prisms_per_fragment = -1.0, st.fragments = 0;
        st.draws.clear();
    }
    all_frame_ms_.clear();
    // And each half's next draw warms up again, untimed: llvmpipe makes a shader's code anew for
    // textures of another format, so the first draw after a drop compiled and was timed (pom
    // 81-172 ms after an 8-bit height image replaced builtin:bricks, Mesa's shader cache off;
    // found by an exploratory session, fifty-second).
    warmed_ = {};
    rendered_ = 0;
    dirty_ = true;
}

// A mesh replaces the scene by that mesh (keeping the first object's height and colour, with
// automatic depth and framing); a height image replaces every object's height map.
void Viewer::handle_drop(const std::string& path)
{
    const std::string ext = lower_extension(path);
    try {
        // The file's load warnings wait until it is taken: a refused one said "no texture
        // coordinates" before its error (found by an exploratory session, forty-ninth).
        ThreadWarningHold held;
        // Said alike whatever the name ends in: a folder "adir" read "cannot load this file type"
        // where "fold.obj" read "is a folder", and a missing "x.png" "cannot open: No such file or
        // directory" where "x.obj" read "does not exist" (an exploratory session, forty-ninth).
        std::error_code ec;
        const std::filesystem::file_status status = std::filesystem::status(path, ec);
        if (status.type() == std::filesystem::file_type::not_found) throw Error(path, "does not exist");
        if (status.type() == std::filesystem::file_type::directory)
            throw Error(path, "is a folder (drop a mesh or a height image)");
        SceneSpec spec = s_.spec;
        if (ext == ".obj" || ext == ".off" || ext == ".ply" || ext == ".stl") {
            ObjectSpec obj = spec.objects.at(0);
            obj.mesh = path;
            obj.mesh_place.clear(); // (its errors are the dropped file's, not the flag's or the scene's)
            obj.depth.reset();
            obj.depth_place.clear();
            obj.transform = glm::dmat4(1.0);
            spec.objects = {obj};
            spec.camera.eye.reset();
            spec.camera.target.reset();
            reload_scene(std::move(spec), true, true);
        } else if (const auto images = {".png", ".jpg", ".jpeg", ".bmp", ".tga", ".pgm", ".ppm", ".pnm", ".hdr",
                                        ".gif", ".psd", ".pic"};
                   std::find(images.begin(), images.end(), ext) != images.end()) {
            // (A dropped map that cannot be read was said under --height or the scene's place;
            // found by an exploratory session, thirty-third.)
            for (ObjectSpec& obj : spec.objects) {
                obj.height = path;
                obj.height_place.clear();
            }
            // The panel's depth and midlevel stay, over the loaded ones as before the drop (the
            // scene came back at the command line's: found by an exploratory session,
            // thirty-eighth); the loaded ones stay the bases the other objects follow the panel
            // from (an image changes neither the objects nor their depths).
            const std::vector<float> base_depth = base_depth_, base_midlevel = base_midlevel_;
            const float depth = depth_, midlevel = midlevel_;
            reload_scene(std::move(spec), false);
            if (base_depth_ == base_depth && base_midlevel_ == base_midlevel && (depth != depth_ || midlevel != midlevel_)) {
                depth_ = depth;
                midlevel_ = midlevel;
                apply_displacement();
            }
        } else {
            throw Error(path, "cannot load this file type (drop a mesh: OBJ, OFF, PLY, STL; or a height "
                              "image: PNG, JPEG, BMP, TGA, binary PNM, HDR, GIF, PSD, PIC)");
        }
        held.release();
        note("loaded " + path);
    } catch (const Error& e) {
        error(e.what());
    } catch (const std::exception& e) {
        error(path + ": " + e.what());
    }
}

bool Viewer::half_needs_reference() const
{
    return half_[0].technique == Technique::Reference || (split_ && half_[1].technique == Technique::Reference);
}

DrawSettings Viewer::drawable(const DrawSettings& d)
{
    const AuxMap map = d.aux_map();
    // (--cone-backend gpu builds in the draw: the compute shader needs this thread's context.)
    if (cone_builds_inline_ || s_.renderer->cone_maps_on_gpu() || (map != AuxMap::Cone && map != AuxMap::Relaxed))
        return d;
    if (cone_job_ && cone_job_->map == map) return while_cone_maps_build(d);
    std::vector<Renderer::ConeMapNeed> needs = s_.renderer->missing_cone_maps(map);
    // What the cache holds is read here, as the draw read it (no frame of relief before a cached
    // map), but without building: an entry that cannot be read or is wrong is left to the thread,
    // which rebuilds it (saying why) while relief is drawn. The draw rebuilt it in the frame, and
    // the window stopped for the build's time: 10.5 s for the relaxed map of builtin:noise@768
    // (thirty-third session; a split half next to another's build too, found by an exploratory
    // session).
    std::erase_if(needs, [&](const Renderer::ConeMapNeed& need) {
        if (!need.cached || unreadable_entries_.count({need.field.get(), need.kind})) return false;
        std::optional<ConeMap> read = read_cached_cone_map(*need.field, need.kind, s_.renderer->cache_dir());
        if (!read) {
            unreadable_entries_.insert({need.field.get(), need.kind});
            return false;
        }
        s_.renderer->provide_cone_map(need.field, std::move(*read));
        return true;
    });
    if (needs.empty()) return d;
    if (!cone_job_) { // one build at a time: the other half's maps follow
        ConeJob& job = cone_job_.emplace();
        job.map = map;
        // Every height map it builds for (plane_and_torus.json's two were named by the first
        // alone; found by an exploratory session), each once (a relaxed map needs a cone map too).
        std::vector<const HeightField*> fields;
        for (const Renderer::ConeMapNeed& need : needs)
            if (std::find(fields.begin(), fields.end(), need.field.get()) == fields.end())
                fields.push_back(need.field.get());
        job.fields = fields;
        job.what = cone_map_label(map == AuxMap::Relaxed ? ConeKind::Relaxed : ConeKind::Cone, *fields.front());
        for (std::size_t i = 1; i < fields.size(); ++i)
            job.what += (i + 1 == fields.size() ? " and " : ", ") +
                        (fields[i]->name.empty() ? std::string("another height map") : fields[i]->name);
        // (An entry that could not be read above is read again here: cached_cone_map says why it
        // rebuilds it. One that another process wrote meanwhile is read: nothing to say then.)
        job.maps = std::async(std::launch::async, [needs = std::move(needs), dir = s_.renderer->cache_dir(),
                                                   done = job.done, cancel = job.cancel]() {
            ConeJob::Result result;
            for (std::size_t i = 0; i < needs.size(); ++i) {
                ConeBuildOptions options;
                options.cancel = cancel.get();
                options.progress = [&done, i, n = needs.size()](double f) { *done = (double(i) + f) / double(n); };
                ConeCacheResult got = cached_cone_map(*needs[i].field, needs[i].kind, dir, options);
                result.built |= !got.from_cache;
                result.maps.emplace_back(needs[i].field, std::move(got.map));
            }
            return result;
        });
    }
    return while_cone_maps_build(d);
}

void Viewer::poll_cone_job()
{
    if (!cone_job_ || cone_job_->maps.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    ConeJob job = std::move(*cone_job_);
    cone_job_.reset();
    dirty_ = true;
    try {
        ConeJob::Result result = job.maps.get();
        for (auto& [field, map] : result.maps) s_.renderer->provide_cone_map(field, std::move(map));
        // The technique is drawn now, whatever failed while relief stood in for it (the settings
        // it was blocked on are the same: a relief that failed kept the technique undrawn after
        // the build; found by an exploratory session, thirty-second).
        blocked_key_.clear();
        // All read from the cache after all (an entry the frame could not read, mended meanwhile
        // by another process): nothing was built, nothing to say.
        if (!result.built) return;
        // The technique's first draw follows: it counts samples and is left out of the times, as
        // the first frame is (it compiles the technique's shaders). It was timed: --frames printed
        // that one draw, about 190 ms for 3 ms, and no samples per fragment.
        rendered_ = 0;
        char line[256];
        std::snprintf(line, sizeof line, "built the %s in %.1f s (%d frame%s drawn with relief meanwhile)",
                      job.what.c_str(), seconds_since(job.start), job.frames_meanwhile,
                      job.frames_meanwhile == 1 ? "" : "s");
        note(line);
        if (o_.frames > 0) std::printf("view: %s\n", line);
    } catch (const ConeBuildCancelled&) {
    } catch (const std::exception& e) {
        // Reported once; from now on the draws build what they need themselves (and report it).
        error(job.what + ": " + e.what());
        cone_builds_inline_ = true;
    }
}

void Viewer::cancel_cone_job()
{
    if (!cone_job_) return;
    *cone_job_->cancel = true;
    cone_job_->maps.wait(); // the generator stops at its next span of a row
    cone_job_.reset();
}

// What picks a half's shader variant (and its light's size).
std::string variant_key(const DrawSettings& d)
{
    return std::to_string(int(d.technique)) + "," + std::to_string(int(d.marcher)) + "," +
           std::to_string(int(d.normal_quality)) + "," + std::to_string(int(d.shadows)) + "," +
           std::to_string(int(d.prism_exit)) + "," + std::to_string(d.full_shell) + "," +
           std::to_string(d.depth_write) + "," + std::to_string(d.light_size) + ";";
}

std::string Viewer::settings_key() const
{
    std::string key;
    for (int h = 0; h < (split_ ? 2 : 1); ++h) key += variant_key(half_[h]);
    return key + std::to_string(int(overlay_)) + std::to_string(reference_overlay_);
}

void Viewer::render_scene()
{
    if (!blocked_key_.empty() && blocked_key_ == settings_key()) return; // waits for a change
    blocked_key_.clear();
    Renderer& r = *s_.renderer;
    const int w = r.width(), h = r.height(); // the render scale's pixels
    try {
        if ((reference_overlay_ || half_needs_reference()) && !reference_ready_) {
            r.prepare_reference(s_.scene, s_.camera, o_.reference);
            reference_ready_ = true;
        }
        const int halves = split_ ? 2 : 1;
        const int divider_px = divider_column();
        // Count samples on the first frame and every 10th after (the instrumented variant is
        // slower; its frames are left out of the times).
        const bool count = count_samples_ && rendered_ % 10 == 0;
        // Half k's columns: [edges[k], edges[k + 1]).
        const int edges[3] = {0, split_ ? divider_px : w, w};
        // What each half draws, first: a frame where a half draws relief meanwhile is not one of
        // --frames' frames, and the other half's draw is not timed for its summary either (it was,
        // and with the build sharing the cores pom's median read 29.5 ms against 15.2 once the map
        // was cached; found by an exploratory session, thirty-second). (Halves with no columns are
        // not drawn, and start no build.)
        drew_meanwhile_ = false;
        std::array<DrawSettings, 2> drawn;
        for (int k = 0; k < halves; ++k) {
            half_meanwhile_[k] = false;
            if (edges[k + 1] <= edges[k]) continue;
            drawn[k] = drawable(half_[k]);
            half_meanwhile_[k] = drawn[k].technique != half_[k].technique || drawn[k].marcher != half_[k].marcher;
            drew_meanwhile_ |= half_meanwhile_[k];
        }
        for (int k = 0; k < halves; ++k) {
            const int x0 = edges[k], x1 = edges[k + 1];
            if (x1 <= x0) continue;
            if (split_) {
                // Each half only draws its own columns (the renderer's clears and draws honour it).
                glEnable(GL_SCISSOR_TEST);
                glScissor(x0, 0, x1 - x0, h);
            }
            DrawSettings d = drawn[k];
            const bool meanwhile = half_meanwhile_[k];
            // A frame that counts samples draws the plain variant first, untimed, where this half
            // has not drawn it yet, and a plain draw that compiles its variant is not timed: the
            // next frame's plain draw compiled it, and `--frames 2` printed the compile's time as
            // the draw's (prism:cone 1,120 ms against 5 ms with more frames; found by an
            // exploratory session).
            const std::string variant = variant_key(d);
            const bool fresh = warmed_[k] != variant;
            // A half whose settings changed forgets the figures of the ones before and counts its
            // samples in this frame: the panel showed the previous technique's samples under the
            // new one's name until the next tenth frame, and blended its time from 0 (found by an
            // exploratory session). Also where it draws relief meanwhile (it showed the previous
            // technique's figures under the new name while the map was built; a second one).
            HalfStats& st = stats_[k];
            if (fresh) {
                // (The --frames summary's draws and whole frames too: it printed the median of the
                // technique before and this one's under this one's name; found by an exploratory
                // session, thirty-eighth. Its count of frames is the run's.)
                st.draws.clear();
                all_frame_ms_.clear();
                st.draw_ms = 0.0;
                st.samples_per_fragment = -1.0;
                st.prisms_per_fragment = -1.0;
                st.fragments = 0;
            }
            d.count_samples = (count || (fresh && count_samples_)) && !meanwhile;
            if (fresh && d.count_samples) {
                DrawSettings plain = d;
                plain.count_samples = false;
                r.draw(s_.camera, s_.light, plain);
            }
            const double ms = r.draw(s_.camera, s_.light, d);
            warmed_[k] = variant;
            if (fresh) frame_compiles_ = true; // (nor is the whole frame timed: after a drop it was)
            if (meanwhile) {
                // Not this technique's figures: its line says what is being built instead.
            } else if (d.count_samples) {
                const SampleCounters c = r.read_counters();
                st.fragments = c.fragments;
                st.samples_per_fragment = c.fragments ? double(c.samples) / double(c.fragments) : 0.0;
                st.prisms_per_fragment =
                    d.prism_walk() ? (c.fragments ? double(c.prisms) / double(c.fragments) : 0.0) : -1.0;
            } else if (fresh) {
                // (Compiled in this draw: not its time.)
            } else {
                st.draw_ms = st.draw_ms <= 0.0 ? ms : 0.8 * st.draw_ms + 0.2 * ms;
                if (o_.frames > 0 && !drew_meanwhile_) st.draws.push_back(ms); // for the --frames summary only
            }
            if (overlay_ != WireOverlay::None) {
                const auto kind = overlay_ == WireOverlay::Base ? Renderer::Overlay::BaseMesh
                                                                : Renderer::Overlay::PrismShell;
                const glm::vec4 color = overlay_ == WireOverlay::Base ? glm::vec4(1.0f, 0.85f, 0.2f, 1.0f)
                                                                      : glm::vec4(0.25f, 0.9f, 1.0f, 1.0f);
                r.draw_overlay(s_.camera, kind, color, d);
            }
            glDisable(GL_SCISSOR_TEST);
            compositor_->copy_view(r.framebuffer(), x0, x1, w, h);
        }
        if (reference_overlay_) {
            DrawSettings ref = half_[0];
            ref.technique = Technique::Reference;
            ref.count_samples = false;
            ref.shadows = Shadows::None; // (its coverage is what the overlay shows: no shadow map to draw)
            r.draw(s_.camera, s_.light, ref);
            compositor_->copy_reference(r.framebuffer(), w, h);
        }
        if (drew_meanwhile_ && cone_job_) ++cone_job_->frames_meanwhile;
        image_meanwhile_ = drew_meanwhile_;
        shader_error_.clear();
        ++rendered_;
        scene_drawn_ = true;
    } catch (const Error& e) {
        glDisable(GL_SCISSOR_TEST);
        const std::string what = e.what();
        // --frames (tests, docs figures): a frame that cannot be drawn fails the run (exit 1, no
        // screenshot) rather than saving a blank image; interactively the viewer goes on.
        if (o_.frames > 0) throw;
        if (dynamic_cast<const ShaderError*>(&e)) shader_error_ = what;
        error(what);
        blocked_key_ = settings_key();
    }
}

bool Viewer::take_screenshot(const std::string& path)
{
    try {
        // Never over a file the scene reads now: the start checks --screenshot against the inputs
        // it was given, but a height image dropped later was replaced by P's screenshot (found by
        // an exploratory session).
        // (check_distinct_outputs passes over empty and built-in names.)
        std::vector<NamedPath> inputs;
        for (const ObjectSpec& obj : s_.spec.objects) {
            inputs.emplace_back("mesh", obj.mesh);
            inputs.emplace_back("height map", obj.height);
            inputs.emplace_back("colour map", obj.color);
        }
        check_distinct_outputs({{"--screenshot", path}}, inputs);
        write_png(path, o_.screenshot_ui ? read_window() : compositor_->read_view());
        note("wrote " + path);
        if (o_.frames > 0) std::printf("%s: %dx%d\n", one_line(path).c_str(), compositor_->width(), compositor_->height());
        return true;
    } catch (const Error& e) {
        if (o_.frames > 0) throw; // --frames --screenshot: the PNG is the result; failing to write it fails
        error(e.what());
        return false;
    }
}

// Said where a P that waited for a cone map is dropped, its settings changed meanwhile.
constexpr const char* kScreenshotSettingsChanged =
    "P: no screenshot: the technique or its settings changed while it waited for its cone map";

void Viewer::request_screenshot()
{
    // A P pressed while an earlier one waits for settings since changed: the earlier is dropped
    // here, as it would be once drawn, and this one asks for what is set now (the later P dropped
    // it with itself; then, pressed in the frame of the change, both were saved, of the new
    // settings; found by two reviews, thirty-sixth).
    if (screenshot_stale()) drop_screenshots(kScreenshotSettingsChanged, false);
    ++screenshot_pending_;
}

bool Viewer::screenshot_stale() const
{
    return screenshot_waiting_ && screenshot_key_ != settings_key();
}

void Viewer::drop_screenshots(const char* why, bool as_error)
{
    as_error ? error(why) : note(why);
    screenshot_pending_ = 0;
    screenshot_waiting_ = false;
    screenshot_settled_ = false;
}

void Viewer::screenshot_now()
{
    if (!o_.screenshot.empty()) {
        take_screenshot(o_.screenshot);
        return;
    }
    // The next number whose file is not there: the count starts at 1 in every run, and a second
    // run's first P replaced the first run's picture (found by an exploratory session).
    std::string path;
    std::error_code ec;
    // (A name taken by a link too, dangling or not: `exists` follows links, and a dangling one
    // passed for free: P wrote nothing, the next P through the link; found by an exploratory
    // session, thirty-sixth.)
    do path = "prismrelief-view-" + std::to_string(++screenshot_counter_) + ".png";
    while (std::filesystem::exists(std::filesystem::symlink_status(path, ec)) && screenshot_counter_ < 1000000);
    // A number whose file could not be written is tried again by the next P (it was skipped: on
    // a full disk, the P after space was freed wrote -2 with -1 free; an exploratory session,
    // forty-ninth).
    if (!take_screenshot(path)) --screenshot_counter_;
}

void Viewer::reset_view()
{
    s_.camera = initial_camera_;
    fit_planes();
    dirty_ = true;
}

void Viewer::reload_shaders()
{
    // (Said first: a compositor that does not compile says so after it, not before "shaders
    // reloaded", which read as if the reload had mended it; found by an exploratory session.)
    note("shaders reloaded");
    s_.renderer->reload_shaders();
    frame_compiles_ = true; // (this frame's draw compiles them: not timed)
    // The compositor's too (compositor.frag): built once at the start, it kept its first program,
    // edits and errors alike (found by an exploratory session). A broken one keeps the last good
    // program and is reported as the renderer's are.
    try {
        compositor_->reload_program();
        compositor_error_.clear();
    } catch (const Error& e) {
        compositor_error_ = e.what();
        error(e.what());
    }
    blocked_key_.clear(); // retry the settings that failed to compile
    dirty_ = true;
}

// The window as shown (back buffer, before the swap): view, background, divider, panel.
RgbaImage Viewer::read_window() const
{
    RgbaImage img;
    img.width = compositor_->width();
    img.height = compositor_->height();
    img.pixels.resize(std::size_t(img.width) * img.height * 4);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, img.width, img.height, GL_RGBA, GL_UNSIGNED_BYTE, img.pixels.data());
    for (std::size_t i = 3; i < img.pixels.size(); i += 4) img.pixels[i] = 255;
    return img;
}

void Viewer::init_imgui()
{
    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr; // no imgui.ini in the working folder
    ImGui::StyleColorsDark();
    // High DPI: fonts and sizes follow the monitor's content scale (window coordinates are
    // logical; the GLFW backend sets DisplayFramebufferScale for the pixels).
    const float scale = std::clamp(window_.content_scale(), 1.0f, 4.0f);
    ImFontConfig font;
    font.SizePixels = std::round(13.0f * scale);
    io.Fonts->AddFontDefault(&font);
    ImGui::GetStyle().ScaleAllSizes(scale);
    ImGui_ImplGlfw_InitForOpenGL(window_.handle(), true);
    ImGui_ImplOpenGL3_Init("#version 450 core");
}

void Viewer::shutdown_imgui()
{
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void Viewer::handle_input()
{
    ImGuiIO& io = ImGui::GetIO();
    const float fb_scale = framebuffer_scale();
    const float w = float(compositor_->width());
    const float mouse_px = cursor_column();
    const bool near_divider = split_ && std::abs(mouse_px - divider_ * w) < 6.0f * fb_scale;

    if (!io.WantCaptureMouse) {
        if (ImGui::IsMouseClicked(ImGuiMouseButton_Left))
            drag_ = near_divider ? Drag::Divider : io.KeyCtrl ? Drag::Light : Drag::Orbit;
        else if (ImGui::IsMouseClicked(ImGuiMouseButton_Right) || ImGui::IsMouseClicked(ImGuiMouseButton_Middle))
            drag_ = Drag::Pan;
        if (io.MouseWheel != 0.0f) {
            zoom(s_.camera, io.MouseWheel, bounds_);
            fit_planes();
            dirty_ = true;
        }
        if (near_divider || drag_ == Drag::Divider) ImGui::SetMouseCursor(ImGuiMouseCursor_ResizeEW);
    }
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) && !ImGui::IsMouseDown(ImGuiMouseButton_Right) &&
        !ImGui::IsMouseDown(ImGuiMouseButton_Middle))
        drag_ = Drag::None;
    const ImVec2 d = io.MouseDelta;
    if (drag_ != Drag::None && (d.x != 0.0f || d.y != 0.0f)) {
        switch (drag_) {
        case Drag::Orbit:
            orbit(s_.camera, -d.x * 0.008f, d.y * 0.008f, s_.spec.camera.up); // (dragging down: the eye up)
            fit_planes();
            break;
        case Drag::Pan:
            pan(s_.camera, d.x * fb_scale, d.y * fb_scale, compositor_->height());
            fit_planes();
            break;
        case Drag::Light:
            light_azimuth_ -= d.x * 0.01f;
            light_elevation_ = std::clamp(light_elevation_ - d.y * 0.01f, -1.55f, 1.55f);
            s_.light = direction_from_angles(light_azimuth_, light_elevation_, s_.spec.camera.up);
            break;
        case Drag::Divider:
            divider_ = std::clamp(mouse_px / w, 0.0f, 1.0f);
            break;
        case Drag::None: break;
        }
        dirty_ = true;
    }
}

void Viewer::handle_keys()
{
    // Every key pressed since the last frame, in order (GlfwWindow queues them). Polled with
    // ImGui::IsKeyPressed, a press and release within one slow frame were lost: P, M or Q tapped
    // while a soft-shadowed reference or a first prism draw took seconds on llvmpipe did nothing
    // (found by an exploratory session, thirty-second). Called after the panel is drawn, so that a
    // field it opened in this frame (Ctrl + click on a slider) takes them, not the scene: "0.05"
    // typed into it during a slow frame turned the technique to the prism and then to pom.
    const ImGuiIO& io = ImGui::GetIO();
    const std::vector<GlfwWindow::KeyPress> keys = window_.take_key_presses();
    if (io.WantCaptureKeyboard || io.WantTextInput || ImGui::IsAnyItemActive()) return; // (the panel's)
    // A list of the panel's open (a combo's): its keys too, and Esc closes it. Dear ImGui 1.86 sets
    // WantCaptureKeyboard for an active item or keyboard navigation only, so with the shadows
    // list open Esc quit the viewer and a number key changed the technique behind the list
    // (found by an exploratory session, fifty-second; view.keys.popup).
    if (ImGui::IsPopupOpen("", ImGuiPopupFlags_AnyPopupId)) {
        const int esc = ImGui::GetKeyIndex(ImGuiKey_Escape);
        if (std::any_of(keys.begin(), keys.end(), [&](const GlfwWindow::KeyPress& k) { return k.key == esc; }))
            ImGui::ClosePopupsOverWindow(nullptr, true);
        return;
    }
    // The half drawn under the cursor: its renderer column against the right half's first
    // (divider_ * width unrounded gave the right half's first column to the left half where the
    // product's fraction was under a half; found by an exploratory session, thirty-fourth).
    const int cursor_renderer_column = int(std::floor(cursor_column() * float(s_.renderer->width()) /
                                                      float(std::max(compositor_->width(), 1))));
    const bool right_half = split_ && cursor_renderer_column >= divider_column();
    const auto& table = technique_table();
    const int tab = ImGui::GetKeyIndex(ImGuiKey_Tab), escape = ImGui::GetKeyIndex(ImGuiKey_Escape);
    for (const GlfwWindow::KeyPress& key : keys) {
        // 1..9, 0: the table's first ten techniques (Shift: the right half, which turns split on).
        for (int i = 0; i < 10 && i < int(table.size()); ++i) {
            if (key.key == '0' + (i + 1) % 10) {
                const int k = key.shift ? 1 : 0;
                if (k == 1) split_ = true;
                half_[k].technique = table[i].technique;
                dirty_ = true;
            }
        }
        // `[`, `]` and `M` act on the half under the cursor in split view (they acted on the left
        // half alone: in the default split, POM | prism, `M` changed nothing to be seen; found by
        // an exploratory session); `M` on the other half when that one is the prism and this one not.
        const int pointed = right_half ? 1 : 0;
        const auto cycle = [&](int step) {
            DrawSettings& d = half_[pointed];
            std::size_t at = 0;
            for (std::size_t i = 0; i < table.size(); ++i)
                if (table[i].technique == d.technique) at = i;
            const std::size_t n = table.size();
            d.technique = table[(at + (step > 0 ? 1 : n - 1)) % n].technique;
            dirty_ = true;
        };
        if (key.key == ']') cycle(1);
        if (key.key == '[') cycle(-1);
        if (key.key == 'M') {
            const int k = split_ && half_[pointed].technique != Technique::Prism &&
                                  half_[1 - pointed].technique == Technique::Prism
                              ? 1 - pointed
                              : pointed;
            const std::vector<Marcher>& all = all_marchers();
            const auto at = std::find(all.begin(), all.end(), half_[k].marcher);
            half_[k].marcher = at == all.end() || at + 1 == all.end() ? all.front() : *(at + 1);
            dirty_ = true;
        }
        if (key.key == 'S') split_ = !split_, dirty_ = true;
        if (key.key == 'W') overlay_ = WireOverlay((int(overlay_) + 1) % 3), dirty_ = true;
        if (key.key == 'D') reference_overlay_ = !reference_overlay_, dirty_ = true;
        if (key.key == 'R') reset_view();
        if (key.key == 'H' || key.key == tab) show_panel_ = !show_panel_;
        if (key.key == 'P') request_screenshot();
        if (key.key == 'Q' || key.key == escape) window_.request_close();
    }
}

void Viewer::technique_combo(int k)
{
    const auto& table = technique_table();
    DrawSettings& d = half_[k];
    const char* label = k == 0 ? (split_ ? "left" : "technique") : "right";
    if (ImGui::BeginCombo(label, technique_name(d.technique).c_str())) {
        for (const TechniqueInfo& t : table) {
            if (ImGui::Selectable(t.name, t.technique == d.technique)) {
                d.technique = t.technique;
                dirty_ = true;
            }
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", t.summary);
        }
        ImGui::EndCombo();
    }
    if (d.technique == Technique::Prism) {
        static const std::vector<PrismExit> exits = {PrismExit::Walk, PrismExit::Exact, PrismExit::Vertex};
        const std::string half = std::string("##") + char('0' + k);
        if (choice_combo("marcher" + half, d.marcher, all_marchers(), marcher_name)) dirty_ = true;
        if (choice_combo("exit" + half, d.prism_exit, exits, prism_exit_name)) dirty_ = true;
        if (d.prism_exit == PrismExit::Walk) {
            if (ImGui::Checkbox(("full shell" + half).c_str(), &d.full_shell)) dirty_ = true;
        }
    }
}

// ImGui's ScaleAllSizes factor (the panel's and the build box's sizes follow it).
float ui_scale()
{
    return ImGui::GetStyle().ScrollbarSize / 14.0f;
}

// A cone map's build, in a box of its own at the window's bottom right, shown with the panel
// hidden too: in the panel, its three lines pushed every control down while it ran.
void Viewer::draw_build_box()
{
    if (!cone_job_) return;
    const float scale = ui_scale();
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(display.x - 8.0f * scale, display.y - 8.0f * scale), ImGuiCond_Always,
                            ImVec2(1.0f, 1.0f));
    ImGui::SetNextWindowBgAlpha(0.85f);
    ImGui::Begin("##cone map build", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoInputs |
                     ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoFocusOnAppearing);
    // 300 wide with its lines wrapped to that where the window has room, else the bar alone,
    // as wide as the window allows (at 400 pixels the box ran off the window's left edge, and
    // wrapped lines ran off its foot in smaller ones; found by exploratory sessions, thirty-second).
    const float done = float(cone_job_->done->load());
    if (display.x >= 360.0f * scale && display.y >= 200.0f * scale) {
        const float width = 300.0f * scale;
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + width);
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.8f, 0.3f, 1.0f));
        ImGui::TextWrapped("building the %s", cone_job_->what.c_str());
        ImGui::PopStyleColor();
        ImGui::ProgressBar(done, ImVec2(width, 0.0f));
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        // (Not with --no-cache, or where there is no cache folder: it said so there too; found by
        // an exploratory session, thirty-sixth.)
        ImGui::TextWrapped(s_.renderer->cache_dir().empty() ? "relief drawn meanwhile; the map is kept in memory only"
                                                            : "relief drawn meanwhile; the map is cached for later runs");
        ImGui::PopStyleColor();
        ImGui::PopTextWrapPos();
    } else {
        char label[48];
        std::snprintf(label, sizeof label, "cone map %d%%", int(done * 100.0f));
        ImGui::ProgressBar(done, ImVec2(std::max(1.0f, display.x - 32.0f * scale), 0.0f), label);
    }
    ImGui::End();
}

void Viewer::draw_panel()
{
    const float scale = ui_scale();
    ImGui::SetNextWindowPos(ImVec2(8.0f * scale, 8.0f * scale), ImGuiCond_FirstUseEver);
    // The width the user gave it (330 at first), the height fitted to what it holds in every frame
    // (0 on an axis: fit it). Fitted only once, at the first frame, the log's lines and a shader
    // error below the controls were cut off.
    ImGui::SetNextWindowSize(ImVec2(panel_width_ > 0.0f ? panel_width_ : 330.0f * scale, 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.85f);
    panel_refit_ = false;
    if (!ImGui::Begin("prismrelief", &show_panel_)) {
        ImGui::End();
        return;
    }
    panel_width_ = ImGui::GetWindowWidth();
    ImGui::PushItemWidth(ImGui::GetWindowWidth() * 0.55f);
    // No field takes the focus by Tab, the key that shows and hides the panel: ImGui took the Tab
    // that showed it to focus the first slider's text field, which then held every key (Q did not
    // quit; digits went into `steps`) until a click or Enter (found by an exploratory session,
    // thirty-eighth).
    ImGui::PushAllowKeyboardFocus(false);
    ImGui::TextDisabled("%s", s_.context->description().c_str());

    // Frame time and counters.
    const auto fmt_half = [&](int k) {
        const HalfStats& st = stats_[k];
        const std::string name = display_name(half_[k]);
        if (half_meanwhile_[k]) {
            ImGui::Text("%-14s waits for its cone map", name.c_str());
            return;
        }
        char time[32]; // "n/a" before its first timed draw (the first draws compile and count)
        if (st.draw_ms > 0.0) std::snprintf(time, sizeof time, "%6.1f ms", st.draw_ms);
        else std::snprintf(time, sizeof time, "   n/a ms");
        if (st.samples_per_fragment >= 0.0) {
            ImGui::Text("%-14s %s %5.1f samples/frag", name.c_str(), time, st.samples_per_fragment);
            // (On a line of its own, under the samples: beside them it was cut at the panel's edge.)
            if (st.prisms_per_fragment >= 0.0) ImGui::Text("%25s%5.1f prisms/frag", "", st.prisms_per_fragment);
        } else
            ImGui::Text("%-14s %s", name.c_str(), time);
    };
    // (n/a before the first frame time, as a technique's time: it read "0.0 ms (0 fps)"; an
    // exploratory session, forty-ninth.)
    if (frame_ms_.empty() || !(frame_ms_.back() > 0.0f))
        ImGui::Text("frame n/a ms, %dx%d px", compositor_->width(), compositor_->height());
    else
        ImGui::Text("frame %.1f ms (%.0f fps), %dx%d px", frame_ms_.back(), 1000.0f / frame_ms_.back(),
                    compositor_->width(), compositor_->height());
    fmt_half(0);
    if (split_) fmt_half(1);
    // (Drawn before the first frame time too, empty: the panel's items below kept moving down
    // when the first one came.)
    {
        const std::vector<float> v(frame_ms_.begin(), frame_ms_.end());
        const float none = 0.0f;
        ImGui::PlotLines("##frames", v.empty() ? &none : v.data(), int(v.size()), 0, "frame ms", 0.0f, FLT_MAX,
                         ImVec2(0.0f, 36.0f * scale));
    }
    ImGui::Checkbox("count height samples", &count_samples_);
    ImGui::SameLine();
    ImGui::Checkbox("continuous", &continuous_);
    // The presets, and a --render-scale between them as a fifth entry (it showed as 100%).
    float scales[] = {1.0f, 0.75f, 0.5f, 0.25f, render_scale_};
    char other[16];
    std::snprintf(other, sizeof other, "%.0f%%", 100.0 * double(render_scale_));
    const char* scale_names[] = {"100%", "75%", "50%", "25%", other};
    int si = 4;
    for (int i = 3; i >= 0; --i)
        if (render_scale_ == scales[i]) si = i;
    if (ImGui::Combo("render scale", &si, scale_names, si == 4 ? 5 : 4)) render_scale_ = scales[si];
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("Pixels the renderer draws, upscaled to the window");

    if (ImGui::CollapsingHeader("Technique", ImGuiTreeNodeFlags_DefaultOpen)) {
        technique_combo(0);
        if (ImGui::Checkbox("split compare (S)", &split_)) dirty_ = true;
        if (split_) {
            technique_combo(1);
            if (ImGui::SliderFloat("divider", &divider_, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp)) dirty_ = true;
        }
        int steps = half_[0].steps, refine = half_[0].refine;
        // The command line's ranges (--steps 1000 showed past a 1-256 slider's end), kept to them
        // when a value is typed (Ctrl + click): steps 200000 froze the window, 0 steps and
        // negative depths were drawn (found by an exploratory session, thirty-sixth).
        constexpr ImGuiSliderFlags kClamp = ImGuiSliderFlags_AlwaysClamp;
        bool changed = ImGui::SliderInt("steps", &steps, 1, kMaxSteps, "%d", ImGuiSliderFlags_Logarithmic | kClamp);
        changed |= ImGui::SliderInt("refine", &refine, 0, kMaxRefine, "%d", kClamp);
        static const char* qualities[] = {"gather", "central", "sobel"};
        int q = int(half_[0].normal_quality);
        changed |= ImGui::Combo("normals", &q, qualities, 3);
        static const char* shadows[] = {"none", "hard", "soft"};
        int sh = int(half_[0].shadows);
        changed |= ImGui::Combo("shadows", &sh, shadows, 3);
        float light_size = half_[0].light_size;
        if (sh == int(Shadows::Soft)) {
            // (From 0.01 degrees: --light-size takes any size over 0, a typed 0.05 was made 0.1.)
            changed |= ImGui::SliderFloat("light size", &light_size, 0.01f, kMaxLightSize, "%.3g deg",
                                          ImGuiSliderFlags_Logarithmic | kClamp);
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("The light's angular diameter (--light-size; the sun: about 0.5)");
        }
        bool depth_write = half_[0].depth_write;
        changed |= ImGui::Checkbox("depth write", &depth_write);
        if (changed) {
            for (DrawSettings& d : half_) {
                d.steps = steps;
                d.refine = refine;
                d.normal_quality = parse_normal_quality(qualities[q]);
                d.shadows = parse_shadows(shadows[sh]);
                d.light_size = light_size;
                d.depth_write = depth_write;
            }
            dirty_ = true;
        }
    }
    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
        const float max_depth = std::max(4.0f * (base_depth_.empty() ? 0.0f : base_depth_[0]), float(0.1 * base_radius_));
        // (The depth may be typed past the slider's end, as --depth may be any finite number
        // from 0; not under it, nor as inf or nan.)
        const float depth_before = depth_;
        bool disp = ImGui::SliderFloat("depth", &depth_, 0.0f, max_depth, "%.4f");
        if (!std::isfinite(depth_) || depth_ > 1e30f) depth_ = depth_before;
        depth_ = std::max(depth_, 0.0f);
        disp |= ImGui::SliderFloat("midlevel", &midlevel_, 0.0f, 1.0f, "%.2f", ImGuiSliderFlags_AlwaysClamp);
        if (disp) apply_displacement();
        float az = glm::degrees(light_azimuth_), el = glm::degrees(light_elevation_);
        bool light = ImGui::SliderFloat("light azimuth", &az, -180.0f, 180.0f, "%.0f deg", ImGuiSliderFlags_AlwaysClamp);
        light |= ImGui::SliderFloat("light elevation", &el, -89.0f, 89.0f, "%.0f deg", ImGuiSliderFlags_AlwaysClamp);
        if (light) {
            light_azimuth_ = glm::radians(az);
            light_elevation_ = glm::radians(el);
            s_.light = direction_from_angles(light_azimuth_, light_elevation_, s_.spec.camera.up);
            dirty_ = true;
        }
        if (ImGui::Button("reset view (R)")) reset_view();
        ImGui::SameLine();
        if (ImGui::Button("screenshot (P)")) request_screenshot();
    }
    if (ImGui::CollapsingHeader("Overlays", ImGuiTreeNodeFlags_DefaultOpen)) {
        int ov = int(overlay_);
        bool changed = ImGui::RadioButton("none", &ov, 0);
        ImGui::SameLine();
        changed |= ImGui::RadioButton("base mesh", &ov, 1);
        ImGui::SameLine();
        changed |= ImGui::RadioButton("prism shell", &ov, 2);
        if (changed) overlay_ = WireOverlay(ov), dirty_ = true;
        if (ImGui::Checkbox("reference difference (D)", &reference_overlay_)) dirty_ = true;
        if (reference_overlay_) {
            ImGui::TextColored(ImVec4(0.0f, 1.0f, 1.0f, 1.0f), "missed");
            ImGui::SameLine();
            ImGui::TextColored(ImVec4(1.0f, 0.0f, 1.0f, 1.0f), "extra");
            ImGui::SameLine();
            if (ImGui::SmallButton("re-tessellate")) reference_ready_ = false, dirty_ = true;
        }
    }
    if (ImGui::CollapsingHeader("Shaders")) {
        if (watch_)
            ImGui::TextWrapped("hot reload: watching %s", watch_->dir().string().c_str());
        else
            ImGui::TextWrapped("embedded shaders (hot reload: --shader-dir DIR or PRISMRELIEF_SHADER_DIR)");
        if (ImGui::Button("reload now")) reload_shaders();
    }
    for (const std::string* shown : {&compositor_error_, &shader_error_}) {
        if (shown->empty()) continue;
        ImGui::Separator();
        ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1.0f, 0.45f, 0.4f, 1.0f));
        ImGui::TextWrapped("%s", shown->c_str());
        ImGui::PopStyleColor();
    }
    if (!log_.empty()) {
        ImGui::Separator();
        for (const std::string& line : log_) ImGui::TextWrapped("%s", line.c_str());
    }
    ImGui::TextDisabled("drop a mesh or a height image on the window");
    ImGui::PopAllowKeyboardFocus();
    ImGui::PopItemWidth();
    // The height it fits is what it held in the frame before (ImGui's auto-fit): where that
    // changed (a log line, an error, a section opened) the frame lays the panel out again
    // (run), or its last lines were cut for a frame or two.
    const float content = ImGui::GetCursorPosY();
    panel_refit_ = content != panel_content_y_;
    panel_content_y_ = content;
    ImGui::End();
}

int Viewer::run()
{
    window_.set_swap_interval(o_.frames > 0 ? 0 : 1);
    // A compositor.frag under --shader-dir that does not build ends a batch run (--frames), as any
    // shader that cannot draw does; interactively it is reported, as a hot reload's error is, and
    // the embedded one composes until a reload builds the folder's (it ended the viewer, exit 1,
    // right after "the window stays open"; found by an exploratory session, forty-ninth).
    try {
        compositor_.emplace();
    } catch (const ShaderError& e) {
        if (o_.frames > 0) throw;
        compositor_error_ = e.what();
        error(e.what());
        compositor_.emplace(Compositor::EmbeddedShaders{});
    }
    init_imgui();
    show_panel_ = o_.panel;
    bool previous_counted = false;
    try {
        while (!window_.should_close()) {
            const bool busy = dirty_ || continuous_ || o_.frames > 0 || drag_ != Drag::None;
            // A build's progress: 10 per s. With --frames too: the frames drawn meanwhile do not
            // count, and drawn as fast as they go they took the cores from the build.
            const bool building = cone_job_.has_value();
            // Keys tapped in the last frame were held down for it (below): up again before the
            // events, which hold them down anew where they are pressed again.
            ImGuiIO& keys_io = ImGui::GetIO();
            for (const int key : held_taps_) keys_io.KeysDown[key] = false; // (in range: held below)
            held_taps_.clear();
            window_.poll_events(busy && !(building && o_.frames > 0) ? 0.0 : building ? 0.1 : 0.25);
            poll_cone_job();
            for (const std::string& path : window_.take_dropped_files()) handle_drop(path);
            if (frame_ == (o_.frames == 1 ? 0 : 1)) { // after the first frame, as if dropped by hand (tests)
                for (const std::string& path : pending_drops_) handle_drop(path);
                pending_drops_.clear();
            }
            log_warnings();
            if (watch_ && seconds_since(last_watch_) > 0.5) {
                last_watch_ = Clock::now();
                if (watch_->changed()) {
                    reload_shaders();
                }
            }
            // The frame's own work from here (draw, copy, compositor, ImGui, swap): not the wait
            // for events, a drop's load, a screenshot's write (nor a frame that compiles
            // reloaded shaders: frame_compiles_), which the
            // panel's fps and --frames' median took in (a 2-frame run with --screenshot read
            // 53 ms for 22, one with a --drop 1520 for 69; found by an exploratory session,
            // thirty-fifth).
            const Clock::time_point work_start = Clock::now();
            const GlfwWindow::Size fb = window_.framebuffer_size();
            if (fb.width < 1 || fb.height < 1) { // minimized
                if (o_.frames > 0) throw Error("view", "the window has no pixels to draw (minimized?)");
                continue;
            }
            const int rw = std::max(1, int(std::lround(float(fb.width) * render_scale_)));
            const int rh = std::max(1, int(std::lround(float(fb.height) * render_scale_)));
            if (fb.width != compositor_->width() || fb.height != compositor_->height() ||
                rw != s_.renderer->width() || rh != s_.renderer->height()) {
                s_.renderer->resize(rw, rh);
                compositor_->resize(fb.width, fb.height);
                reference_ready_ = false; // its automatic level depends on the pixel size
                dirty_ = true;
                // The window's shape frames what is framed from now on: a dropped mesh and R's
                // view (they were framed for the starting --size: a cube dropped after a resize
                // from 200x100 to 60x200 was cut off at both sides; found by an exploratory
                // session, thirty-sixth).
                if (fb.width != s_.spec.width || fb.height != s_.spec.height) {
                    s_.spec.width = fb.width;
                    s_.spec.height = fb.height;
                    try {
                        initial_camera_ = scene_camera(s_.spec, s_.scene);
                    } catch (const Error&) {
                    } // (the old framing stays)
                }
            }

            ImGui_ImplOpenGL3_NewFrame();
            ImGui_ImplGlfw_NewFrame();
            // A key pressed and released since the last frame is held down for this one: Dear
            // ImGui 1.86 reads the keys' state once a frame, and a Return tapped in a panel's field
            // during a slow frame (relief at 200 ms a frame) was lost; the field stayed open and
            // took P and Q (found by an exploratory session, forty-fourth). (The viewer's own keys
            // come from GlfwWindow's queue: handle_keys.)
            for (const int key : window_.take_taps())
                if (key >= 0 && key < int(IM_ARRAYSIZE(keys_io.KeysDown))) {
                    keys_io.KeysDown[key] = true;
                    held_taps_.push_back(key);
                }
            ImGui::NewFrame();
            handle_input();
            if (show_panel_) draw_panel();
            draw_build_box(); // (with the panel hidden too)
            handle_keys();    // (after the panel: a field it opened this frame takes the keys)
            ImGui::Render();
            // The panel laid out again where what it holds changed since the frame before: its
            // height is fitted to that frame's (a --frames 3 run's --screenshot-ui after a --drop
            // cut the log's last line; found by an exploratory session, thirty-fifth). The input
            // was read by the first pass: a second sees the same buttons held, not pressed.
            for (int pass = 0; pass < 2 && show_panel_ && panel_refit_; ++pass) {
                ImGui::NewFrame();
                draw_panel();
                draw_build_box();
                ImGui::Render();
            }

            drew_meanwhile_ = false;
            scene_drawn_ = false;
            // The compositor's draw once before the scene's first: llvmpipe made the prism's code
            // again at the first draw after the compositor's first (a state of the pipeline's that
            // the compositor's draw leaves, found by trying), so its first timed draw compiled,
            // and `--frames 2` printed 258-532 ms for prism:cone without a colour map, 5 ms with
            // one, Mesa's shader cache off (found by an exploratory session, fifty-second). The
            // view it draws is overwritten in this frame.
            if (!presented_) compositor_->present(Compositor::Present{}), presented_ = true;
            if (dirty_ || continuous_ || o_.frames > 0) {
                dirty_ = false;
                render_scene();
            }
            Compositor::Present p;
            const float fb_scale = framebuffer_scale();
            // The line on the right half's first column (at the right edge, the last column). It
            // was drawn at divider * width: at odd widths a column left of where the halves meet.
            const int line = std::min(compositor_->view_column(divider_column(), s_.renderer->width()), fb.width - 1);
            p.divider_px = split_ ? float(line) + 0.5f : -1.0f;
            p.line_width = std::max(1.0f, fb_scale);
            p.tint_difference = reference_overlay_;
            compositor_->present(p);
            ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
            const double work_ms = seconds_since(work_start) * 1000.0;
            const bool counted = !drew_meanwhile_;
            const bool last_frame = o_.frames > 0 && counted && counted_ + 1 >= o_.frames;
            if (last_frame && !o_.screenshot.empty()) {
                take_screenshot(o_.screenshot);
                screenshot_pending_ = 0;
            } else if (screenshot_pending_ > 0 && image_meanwhile_ && cone_job_) {
                // The picture is relief's while the cone map builds: P saved it under the
                // technique's screenshot without a word (found by an exploratory session,
                // thirty-second). It waits for the technique's own picture.
                if (!screenshot_waiting_) {
                    note("P: the screenshot waits for the cone map (relief is drawn meanwhile)");
                    screenshot_key_ = settings_key();
                }
                screenshot_waiting_ = true;
            } else if (screenshot_pending_ > 0 && image_meanwhile_) {
                // Built, but the technique's draw failed (a shader error): the picture is still relief's.
                drop_screenshots("P: no screenshot: the picture shown is relief's (the technique could not be drawn)", true);
            } else if (screenshot_pending_ > 0 && !blocked_key_.empty() && blocked_key_ == settings_key()) {
                // What is set could not be drawn (a hot-reloaded shader's error): the picture
                // shown is the last one drawn, of other settings or the shaders before. P saved it
                // under the technique the panel names, without a word (found by an exploratory
                // session, forty-fourth).
                // (Nothing drawn yet since the scene was loaded: no earlier picture to speak of;
                // an exploratory session, forty-ninth.)
                drop_screenshots(rendered_ > 0 ? "P: no screenshot: what is set could not be drawn (the error above); "
                                                 "the picture shown is an earlier one"
                                               : "P: no screenshot: what is set could not be drawn (the error above), "
                                                 "and nothing has been drawn yet",
                                 true);
            } else if (screenshot_pending_ > 0 && screenshot_stale()) {
                // Turned to another technique (or settings) while P waited: what is drawn now is
                // not the picture P asked for (it saved flat's after a 1, without a word; found by
                // an exploratory session, thirty-sixth).
                drop_screenshots(kScreenshotSettingsChanged, false);
            } else if (screenshot_pending_ > 0 && screenshot_waiting_ && !screenshot_settled_) {
                // The technique's own picture is drawn in this frame, but the panel was laid out
                // before it (a --screenshot-ui said "waits for its cone map"): the next frame's.
                screenshot_settled_ = true;
                dirty_ = true;
            } else if (screenshot_pending_ > 0) {
                for (; screenshot_pending_ > 0; --screenshot_pending_) screenshot_now();
                screenshot_waiting_ = false;
                screenshot_settled_ = false;
            }
            const Clock::time_point swap_start = Clock::now();
            window_.swap_buffers();

            const double ms = work_ms + seconds_since(swap_start) * 1000.0;
            const bool timed = !frame_compiles_;
            frame_compiles_ = false;
            // (Only frames that draw the scene: on demand, the turns that only redraw the panel
            // read "3.0 ms (336 fps)" beside relief's 147 ms draw; found by an exploratory
            // session, forty-fourth.)
            if (frame_ > 0 && timed && scene_drawn_) {
                frame_ms_.push_back(float(ms));
                while (frame_ms_.size() > 120) frame_ms_.pop_front();
            }
            // (Not the first frame drawn with the techniques, nor the first after a build: it
            // compiles their shaders, and the frame before it waited for the build.)
            if (o_.frames > 0 && counted && previous_counted && timed) all_frame_ms_.push_back(ms);
            previous_counted = counted;
            ++frame_;
            counted_ += counted;
            if (o_.frames > 0 && counted_ >= o_.frames) break;
        }
        // A P that waited for a cone map when the window closed (only the panel's log had said so).
        if (screenshot_pending_ > 0) warn("P: no screenshot: the window closed while the cone map was built");
        // Closed (Q, the window's close button) before the frames asked for: a --screenshot was not
        // written, and the run fails, rather than exit 0 without its PNG (found by an exploratory
        // session).
        if (o_.frames > 0 && counted_ < o_.frames && !o_.screenshot.empty())
            throw Error("view", "the window was closed after " + std::to_string(counted_) + " of " +
                                    std::to_string(o_.frames) + " frames: --screenshot " + o_.screenshot +
                                    " not written");
        if (o_.frames > 0) {
            // Frame times for docs/viewer.md: the renderer's draw (to glFinish) per technique and
            // the whole frame (draw, copy, panel, swap).
            // (A frame that counts samples is not timed, nor is the first whole frame: with one
            // frame there is no time to print, "n/a" rather than 0.00.)
            const auto ms_text = [](const auto& samples) {
                char buf[32];
                if (samples.empty()) return std::string("n/a");
                std::snprintf(buf, sizeof buf, "%.2f ms median", median(samples));
                return std::string(buf);
            };
            std::printf("view: %d frame%s at %dx%d:", counted_, counted_ == 1 ? "" : "s", compositor_->width(), compositor_->height());
            for (int k = 0; k < (split_ ? 2 : 1); ++k) {
                const std::string name = display_name(half_[k]);
                // (With how many draws: the median of a technique switched to is of its own draws
                // only, which a test checks by the count, not by the times.)
                std::printf(" %s draw %s", name.c_str(), ms_text(stats_[k].draws).c_str());
                if (!stats_[k].draws.empty())
                    std::printf(" of %zu draw%s", stats_[k].draws.size(), stats_[k].draws.size() == 1 ? "" : "s");
                if (stats_[k].prisms_per_fragment >= 0.0)
                    std::printf(" (%.2f samples/fragment, %.2f prisms/fragment)", stats_[k].samples_per_fragment,
                                stats_[k].prisms_per_fragment);
                else if (stats_[k].samples_per_fragment >= 0.0)
                    std::printf(" (%.2f samples/fragment)", stats_[k].samples_per_fragment);
                std::printf(";");
            }
            std::printf(" frame %s\n", ms_text(all_frame_ms_).c_str());
        }
    } catch (...) {
        shutdown_imgui();
        throw;
    }
    shutdown_imgui();
    return kExitOk;
}

} // namespace

int run_viewer(Session& session, GlfwWindow& window, const ViewerOptions& options)
{
    Viewer viewer(session, window, options);
    return viewer.run();
}

} // namespace pr::view
