#pragma once
// Technique names (contract, fixed) and the settings that choose a shader variant.
#include <cstddef>
#include <string>
#include <vector>

#include <glm/vec2.hpp>

namespace pr {

// Order is the shader ids' (PR_TECH_* in shaders/common/shared.h); the listing order is technique_table()'s.
enum class Technique { Flat, Normal, Offset, Steep, Pom, Relief, Reference, Prism, Cone, RelaxedCone };
// Ray marchers inside the prism. Cone and RelaxedCone step through the cone map of that kind
// (src/maps/conemap.hpp) and finish with a binary search.
// MaxMip traverses a pyramid of height maxima (quadtree displacement mapping) and intersects the
// bilinear patch exactly.
enum class Marcher { Linear, Relief, Cone, RelaxedCone, MaxMip };
// Self-shadowing: march from the hit towards the light through the height field.
enum class Shadows { None, Hard, Soft };
// How the prism finds where the ray leaves it: exactly per fragment, or from per-vertex distances
// to the texture-space prism's planes, interpolated (the seed's draft); or exactly, and then the
// ray walks on into the prism across that face until it hits or leaves the shell (only the
// shell's outer faces are rasterized; docs/prism.md).
enum class PrismExit { Exact, Vertex, Walk };
enum class NormalQuality { Gather, Central, Sobel };

struct TechniqueInfo {
    Technique technique;
    const char* name;
    const char* summary;
};
const std::vector<TechniqueInfo>& technique_table();

Technique parse_technique(const std::string& name, const std::string& option = "--technique");
std::string technique_name(Technique t);
std::string technique_names(); // "flat|normal|…" for help texts

NormalQuality parse_normal_quality(const std::string& name);
Marcher parse_marcher(const std::string& name, const std::string& option = "--marcher");
std::string marcher_name(Marcher m);
std::string marcher_names(); // "linear|relief|cone|relaxed-cone|max-mip"
const std::vector<Marcher>& all_marchers(); // in that order (the viewer's combo and M key)
Shadows parse_shadows(const std::string& name, const std::string& option = "--shadows");
std::string shadows_name(Shadows s);
PrismExit parse_prism_exit(const std::string& name, const std::string& option = "--prism-exit");
std::string prism_exit_name(PrismExit e);
// "tight" or "full": returns DrawSettings::full_shell.
bool parse_prism_shell(const std::string& name, const std::string& option = "--prism-shell");

std::string normal_quality_name(NormalQuality q);

// The derived map a draw needs besides the height map, bound to PR_TEX_CONE: a cone map of either
// kind (techniques cone/relaxed-cone, prism with those marchers) or the max pyramid (max-mip).
enum class AuxMap { None, Cone, Relaxed, MaxMip };

// How one technique draws: quality knobs shared by every marcher (contract: equal --steps means
// equal step length in any comparison).
// The ranges of DrawSettings::steps and ::refine the command line takes and the viewer's panel
// offers.
constexpr int kMaxSteps = 1024;
constexpr int kMaxRefine = 32;
// Soft shadows' light: its angular diameter in degrees (--light-size), the default and the range
// the command line and the viewer's panel take (more than 0, at most kMaxLightSize).
constexpr float kDefaultLightSize = 2.0f;
constexpr float kMaxLightSize = 30.0f;

struct DrawSettings {
    Technique technique = Technique::Relief;
    int steps = 32;  // linear steps over the full height range, 1..kMaxSteps
    int refine = 6;  // binary refinement steps (relief), 0..kMaxRefine
    Marcher marcher = Marcher::Relief; // prism only
    PrismExit prism_exit = PrismExit::Walk; // prism only
    bool full_shell = false; // walk: top caps at height 1, not at the field's local maximum (shell_bounds.hpp)
    NormalQuality normal_quality = NormalQuality::Sobel;
    Shadows shadows = Shadows::None;
    float light_size = kDefaultLightSize; // soft shadows: the light's angular diameter, degrees
    bool depth_write = false; // base-surface techniques: write the depth of what they show
    bool count_samples = false; // instrumented variant (bench)
    // Where each pixel samples the scene, from its centre (pixels, x right, y up): one pass of
    // multisampling (render --msaa, render/multisample.hpp). (0, 0) samples pixel centres; the
    // image moves by the opposite offset.
    glm::vec2 pixel_offset{0.0f};

    AuxMap aux_map() const;
    // The prism with the walk: its shaders, buffers (Renderer::ensure_walk_data) and overlay.
    bool prism_walk() const { return technique == Technique::Prism && prism_exit == PrismExit::Walk; }
};

// Ground truth (technique `reference`): how finely to tessellate.
struct ReferenceOptions {
    int level = 0; // 0: automatic (edges about one texel or one pixel, whichever is coarser)
    std::size_t max_triangles = 8'000'000; // automatic levels are lowered to stay within this
};

// The technique as a list names it in full: "pom", "prism:cone:walk:tight", "prism:relief:exact".
std::string configuration_name(const DrawSettings& s);

// Whether a draw with these settings reads each quality setting at all, as the shaders do
// (shaders/surface.frag, prism.frag, march/, common/shadow.glsl); a setting a draw does not read
// leaves its image and depth as they are (gl test TechniqueUse). The command line refuses a flag
// that nothing it draws reads (app/options.cpp, check_quality_flags_apply).
// Linear steps: the searches of steep, pom, relief, the cone marchers (their shortest step) and
// the prism's marchers; the light's march with shadows (every technique but flat and reference,
// whose shadows come from a shadow map).
// Max-mip traverses its pyramid without steps, but the walk marches linearly under a torn or
// open surface.
bool reads_steps(const DrawSettings& s);
// Binary refinement: relief, as a technique or as the prism's marcher, the prism's cone
// marchers, and the walk's linear march under a torn surface with max-mip. Not pom or the linear
// marcher (interpolation), steep, max-mip's exact patch intersection, nor the base-surface cone
// and relaxed-cone, which meet each sample's patch exactly (marches_patches).
bool reads_refine(const DrawSettings& s);
// The base-surface cone and relaxed-cone: they march the cone map's patch texture
// (Renderer, make_patch_texture; shaders/march/cone.glsl, PR_CONE_PATCHES).
bool marches_patches(const DrawSettings& s);
// The normal from the heights: every technique but flat (the mesh's normal).
bool reads_normal_quality(const DrawSettings& s);
// Self-shadowing: every technique but flat (the reference's from shadow maps of its geometry:
// Renderer::ensure_shadow_map).
bool reads_shadows(const DrawSettings& s);
// The shadows a draw draws: its setting where it reads it, else none (the shaders' PR_SHADOWS,
// the reference's shadow map, the reports).
Shadows drawn_shadows(const DrawSettings& s);
// The light's size: soft shadows only (of the techniques that shade any).
bool reads_light_size(const DrawSettings& s);
// --depth-write: the base-surface techniques that show a point off the polygon (steep, pom,
// relief, cone, relaxed-cone). Flat, normal and offset show the polygon's own point (its depth
// is the one written anyway), the reference its own geometry, and the prism always writes the
// depth of what it shows.
bool reads_depth_write(const DrawSettings& s);

} // namespace pr
