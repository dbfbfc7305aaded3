#include "render/technique.hpp"

#include "core/error.hpp"

namespace pr {

const std::vector<TechniqueInfo>& technique_table()
{
    static const std::vector<TechniqueInfo> table = {
        {Technique::Flat, "flat", "colour and the mesh's smooth normal; no height"},
        {Technique::Normal, "normal", "normal mapping with normals computed from the height map"},
        {Technique::Offset, "offset", "parallax mapping with offset limiting (one height sample)"},
        {Technique::Steep, "steep", "steep parallax: linear search, first sample below the surface"},
        {Technique::Pom, "pom", "parallax occlusion mapping: linear search + linear interpolation"},
        {Technique::Relief, "relief", "relief mapping: linear search + binary refinement"},
        {Technique::Cone, "cone", "cone step mapping (conservative cone map), each sample's bilinear patch met exactly"},
        {Technique::RelaxedCone, "relaxed-cone", "relaxed cone stepping (relaxed cone map), each sample's bilinear patch met exactly"},
        {Technique::Reference, "reference", "true displaced geometry, finely tessellated: the ground truth"},
        {Technique::Prism, "prism", "shell prisms from a geometry shader, marched ray: true silhouettes and depth"},
    };
    return table;
}

Technique parse_technique(const std::string& name, const std::string& option)
{
    for (const TechniqueInfo& t : technique_table())
        if (name == t.name) return t.technique;
    throw Error(option, "unknown technique '" + name + "' (expected " + technique_names() + ")");
}

std::string technique_name(Technique t)
{
    for (const TechniqueInfo& i : technique_table())
        if (i.technique == t) return i.name;
    return "?";
}

std::string technique_names()
{
    std::string s;
    for (const TechniqueInfo& t : technique_table()) {
        if (!s.empty()) s += '|';
        s += t.name;
    }
    return s;
}

NormalQuality parse_normal_quality(const std::string& name)
{
    if (name == "gather") return NormalQuality::Gather;
    if (name == "central") return NormalQuality::Central;
    if (name == "sobel") return NormalQuality::Sobel;
    throw Error("--normal-quality", "unknown quality '" + name + "' (expected gather|central|sobel)");
}

std::string normal_quality_name(NormalQuality q)
{
    switch (q) {
    case NormalQuality::Gather: return "gather";
    case NormalQuality::Central: return "central";
    case NormalQuality::Sobel: return "sobel";
    }
    return "?";
}

namespace {
struct MarcherInfo {
    Marcher marcher;
    const char* name;
};
constexpr MarcherInfo kMarchers[] = {{Marcher::Linear, "linear"},
                                     {Marcher::Relief, "relief"},
                                     {Marcher::Cone, "cone"},
                                     {Marcher::RelaxedCone, "relaxed-cone"},
                                     {Marcher::MaxMip, "max-mip"}};
} // namespace

Marcher parse_marcher(const std::string& name, const std::string& option)
{
    for (const MarcherInfo& m : kMarchers)
        if (name == m.name) return m.marcher;
    throw Error(option, "unknown marcher '" + name + "' (expected " + marcher_names() + ")");
}

std::string marcher_name(Marcher m)
{
    for (const MarcherInfo& i : kMarchers)
        if (i.marcher == m) return i.name;
    return "?";
}

const std::vector<Marcher>& all_marchers()
{
    static const std::vector<Marcher> all = [] {
        std::vector<Marcher> v;
        for (const MarcherInfo& m : kMarchers) v.push_back(m.marcher);
        return v;
    }();
    return all;
}

std::string marcher_names()
{
    std::string s;
    for (const MarcherInfo& m : kMarchers) {
        if (!s.empty()) s += '|';
        s += m.name;
    }
    return s;
}

Shadows parse_shadows(const std::string& name, const std::string& option)
{
    if (name == "none") return Shadows::None;
    if (name == "hard") return Shadows::Hard;
    if (name == "soft") return Shadows::Soft;
    throw Error(option, "unknown shadow mode '" + name + "' (expected none|hard|soft)");
}

std::string shadows_name(Shadows s)
{
    return s == Shadows::Hard ? "hard" : s == Shadows::Soft ? "soft" : "none";
}

AuxMap DrawSettings::aux_map() const
{
    if (technique == Technique::Cone) return AuxMap::Cone;
    if (technique == Technique::RelaxedCone) return AuxMap::Relaxed;
    if (technique != Technique::Prism) return AuxMap::None;
    switch (marcher) {
    case Marcher::Cone: return AuxMap::Cone;
    case Marcher::RelaxedCone: return AuxMap::Relaxed;
    case Marcher::MaxMip: return AuxMap::MaxMip;
    default: return AuxMap::None;
    }
}

PrismExit parse_prism_exit(const std::string& name, const std::string& option)
{
    if (name == "exact") return PrismExit::Exact;
    if (name == "vertex") return PrismExit::Vertex;
    if (name == "walk") return PrismExit::Walk;
    throw Error(option, "unknown prism exit '" + name + "' (expected walk|exact|vertex)");
}

std::string prism_exit_name(PrismExit e)
{
    switch (e) {
    case PrismExit::Exact: return "exact";
    case PrismExit::Vertex: return "vertex";
    default: return "walk";
    }
}

bool parse_prism_shell(const std::string& name, const std::string& option)
{
    if (name == "tight") return false;
    if (name == "full") return true;
    throw Error(option, "unknown prism shell '" + name + "' (expected tight|full)");
}

std::string configuration_name(const DrawSettings& s)
{
    if (s.technique != Technique::Prism) return technique_name(s.technique);
    std::string name = "prism:" + marcher_name(s.marcher) + ":" + prism_exit_name(s.prism_exit);
    if (s.prism_walk()) name += s.full_shell ? ":full" : ":tight";
    return name;
}

namespace {

bool base_surface_search(Technique t)
{
    return t == Technique::Steep || t == Technique::Pom || t == Technique::Relief || t == Technique::Cone ||
           t == Technique::RelaxedCone;
}

} // namespace

bool reads_steps(const DrawSettings& s)
{
    if (s.technique == Technique::Flat || s.technique == Technique::Reference) return false; // (they march nothing)
    if (s.shadows != Shadows::None) return true; // the light's march (common/shadow.glsl)
    if (s.technique == Technique::Prism) return s.marcher != Marcher::MaxMip || s.prism_walk();
    return base_surface_search(s.technique);
}

bool reads_refine(const DrawSettings& s)
{
    if (s.technique == Technique::Prism)
        return s.marcher == Marcher::Relief || s.marcher == Marcher::Cone || s.marcher == Marcher::RelaxedCone ||
               (s.marcher == Marcher::MaxMip && s.prism_walk());
    return s.technique == Technique::Relief; // (not marches_patches: exact in each sample's patch)
}

bool marches_patches(const DrawSettings& s)
{
    return s.technique == Technique::Cone || s.technique == Technique::RelaxedCone;
}

bool reads_normal_quality(const DrawSettings& s)
{
    return s.technique != Technique::Flat;
}

bool reads_shadows(const DrawSettings& s)
{
    // (The reference's come from shadow maps of its geometry: Renderer::ensure_shadow_map.)
    return s.technique != Technique::Flat;
}

Shadows drawn_shadows(const DrawSettings& s)
{
    return reads_shadows(s) ? s.shadows : Shadows::None;
}

bool reads_light_size(const DrawSettings& s)
{
    return reads_shadows(s) && s.shadows == Shadows::Soft;
}

bool reads_depth_write(const DrawSettings& s)
{
    return base_surface_search(s.technique);
}

} // namespace pr
