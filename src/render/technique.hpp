#pragma once
// Technique names (contract, fixed) and the settings that choose a shader variant.
#include <string>
#include <vector>

namespace pr {

enum class Technique { Flat, Normal, Offset, Steep, Pom, Relief };
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
std::string normal_quality_name(NormalQuality q);

// How one technique draws: quality knobs shared by every marcher (contract: equal --steps means
// equal step length in any comparison).
struct DrawSettings {
    Technique technique = Technique::Relief;
    int steps = 32;  // linear steps over the full height range
    int refine = 6;  // binary refinement steps (relief)
    NormalQuality normal_quality = NormalQuality::Sobel;
    bool depth_write = false; // base-surface techniques: write the depth of what they show
    bool count_samples = false; // instrumented variant (bench)
};

} // namespace pr
