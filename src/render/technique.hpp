#pragma once
// Technique names (contract, fixed) and the settings that choose a shader variant.
#include <cstddef>
#include <string>
#include <vector>

namespace pr {

enum class Technique { Flat, Normal, Offset, Steep, Pom, Relief, Reference, Prism };
// Ray marchers inside the prism (more arrive with cone maps).
enum class Marcher { Linear, Relief };
// How the prism finds where the ray leaves it: exactly per fragment, or from per-vertex distances
// to the texture-space prism's planes, interpolated (the seed's draft).
enum class PrismExit { Exact, Vertex };
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
std::string marcher_names(); // "linear|relief"
PrismExit parse_prism_exit(const std::string& name, const std::string& option = "--prism-exit");

std::string normal_quality_name(NormalQuality q);

// How one technique draws: quality knobs shared by every marcher (contract: equal --steps means
// equal step length in any comparison).
struct DrawSettings {
    Technique technique = Technique::Relief;
    int steps = 32;  // linear steps over the full height range
    int refine = 6;  // binary refinement steps (relief)
    Marcher marcher = Marcher::Relief; // prism only
    PrismExit prism_exit = PrismExit::Exact; // prism only
    NormalQuality normal_quality = NormalQuality::Sobel;
    bool depth_write = false; // base-surface techniques: write the depth of what they show
    bool count_samples = false; // instrumented variant (bench)
};

// Ground truth (technique `reference`): how finely to tessellate.
struct ReferenceOptions {
    int level = 0; // 0: automatic (edges about one texel or one pixel, whichever is coarser)
    std::size_t max_triangles = 8'000'000; // automatic levels are lowered to stay within this
};

} // namespace pr
