// Which quality settings a draw reads (reads_steps and the others, render/technique.hpp): the
// command line refuses a flag that nothing it draws reads as having no effect
// (check_quality_flags_apply), so a setting said to be unread must leave the image and the depth
// as they are. Were a shader to start reading one, the flag would be refused where it matters.
#include "gl_fixture.hpp"

#include "core/camera.hpp"
#include "mesh/mesh.hpp"

#include <cmath>
#include <functional>
#include <string>

using namespace pr;

namespace {

struct Frame {
    RgbaImage color;
    std::vector<float> depth;
};

Frame draw(Renderer& r, const Camera& c, const DrawSettings& s)
{
    r.draw(c, glm::normalize(glm::vec3(-0.6f, 0.5f, 0.4f)), s);
    return {r.read_color(), r.read_depth()};
}

// The same picture: colours to the bit; depths within float rounding (a depth written from the
// shader, --depth-write, is computed otherwise than the rasterizer's: up to 8e-6 of it on the
// rock, where a point carved below the polygon lies a percent or more further).
bool same(const Frame& a, const Frame& b)
{
    if (a.color.pixels != b.color.pixels || a.depth.size() != b.depth.size()) return false;
    for (std::size_t i = 0; i < a.depth.size(); ++i)
        if (std::abs(a.depth[i] - b.depth[i]) > 1e-4f * std::max(std::abs(a.depth[i]), 1e-3f)) return false;
    return true;
}

DrawSettings prism(Marcher m, PrismExit e)
{
    DrawSettings s;
    s.technique = Technique::Prism;
    s.marcher = m;
    s.prism_exit = e;
    return s;
}

DrawSettings technique(Technique t, Shadows shadows = Shadows::None)
{
    DrawSettings s;
    s.technique = t;
    s.shadows = shadows;
    return s;
}

} // namespace

TEST(TechniqueUse, ASettingADrawDoesNotReadChangesNothing)
{
    prtest::context();
    // The rock: a mesh with UV seams and creases, where the prism's walk marches under torn
    // surfaces (with max-mip too), with bricks' steep walls.
    SceneSpec spec;
    ObjectSpec o;
    o.mesh = std::string(PR_SOURCE_DIR) + "/meshes/rock.obj";
    o.height = "builtin:bricks@128";
    spec.objects.push_back(o);
    spec.width = spec.height = 96;
    const Scene scene = load_scene(spec);
    const Camera c = scene_camera(spec, scene);
    Renderer r(spec.width, spec.height);
    r.set_cache_dir(prtest::cache_dir());
    r.upload(scene);
    r.prepare_reference(scene, c, ReferenceOptions{});

    std::vector<DrawSettings> configurations;
    for (Technique t : {Technique::Flat, Technique::Normal, Technique::Offset, Technique::Steep, Technique::Pom,
                        Technique::Relief, Technique::Cone, Technique::RelaxedCone, Technique::Reference})
        configurations.push_back(technique(t));
    for (Marcher m : all_marchers()) configurations.push_back(prism(m, PrismExit::Walk));
    for (Marcher m : {Marcher::Linear, Marcher::MaxMip}) configurations.push_back(prism(m, PrismExit::Exact));
    configurations.push_back(prism(Marcher::MaxMip, PrismExit::Vertex));
    // With self-shadowing the light's march takes steps (not refinement).
    for (Technique t : {Technique::Flat, Technique::Normal, Technique::Offset, Technique::Pom})
        configurations.push_back(technique(t, Shadows::Hard));
    for (DrawSettings s : {prism(Marcher::Linear, PrismExit::Walk), prism(Marcher::MaxMip, PrismExit::Exact)}) {
        s.shadows = Shadows::Hard;
        configurations.push_back(s);
    }
    // The reference's hard shadows (a shadow map) take no steps and no light size.
    configurations.push_back(technique(Technique::Reference, Shadows::Hard));
    // Soft shadows read the light's size, the reference's too (shadow maps over its disc).
    configurations.push_back(technique(Technique::Relief, Shadows::Soft));
    configurations.push_back(technique(Technique::Reference, Shadows::Soft));
    for (DrawSettings s : {prism(Marcher::RelaxedCone, PrismExit::Walk)}) {
        s.shadows = Shadows::Soft;
        configurations.push_back(s);
    }

    struct Setting {
        const char* name;
        bool (*reads)(const DrawSettings&);
        std::function<void(DrawSettings&)> change;
    };
    const Setting settings[] = {
        {"steps", reads_steps, [](DrawSettings& s) { s.steps = 3; }},
        {"refine", reads_refine, [](DrawSettings& s) { s.refine = 0; }},
        {"normal_quality", reads_normal_quality, [](DrawSettings& s) { s.normal_quality = NormalQuality::Gather; }},
        {"depth_write", reads_depth_write, [](DrawSettings& s) { s.depth_write = true; }},
        {"light_size", reads_light_size, [](DrawSettings& s) { s.light_size = 10.0f; }},
    };
    for (const DrawSettings& base : configurations) {
        const std::string name = configuration_name(base) + (base.shadows != Shadows::None ? " with shadows" : "");
        const Frame plain = draw(r, c, base);
        ASSERT_GT(prtest::coverage(plain.color), 500u) << name;
        for (const Setting& setting : settings) {
            DrawSettings changed = base;
            setting.change(changed);
            const bool unchanged = same(plain, draw(r, c, changed));
            if (!setting.reads(base))
                EXPECT_TRUE(unchanged) << name << " does not read " << setting.name << ", but drew otherwise with it";
            else // (this scene shows every change where it is read: the test can tell both ways)
                EXPECT_FALSE(unchanged) << name << " reads " << setting.name
                                        << ", but drew the same with it changed here";
        }
    }
}

// The list behind the command line's messages (check_quality_flags_apply).
TEST(TechniqueUse, WhatEachTechniqueReads)
{
    EXPECT_FALSE(reads_steps(technique(Technique::Flat, Shadows::Soft)));
    EXPECT_FALSE(reads_steps(technique(Technique::Reference, Shadows::Hard)));
    EXPECT_FALSE(reads_steps(technique(Technique::Offset)));
    EXPECT_TRUE(reads_steps(technique(Technique::Offset, Shadows::Soft)));
    EXPECT_TRUE(reads_steps(technique(Technique::Pom)));
    EXPECT_TRUE(reads_steps(prism(Marcher::Cone, PrismExit::Exact)));
    EXPECT_TRUE(reads_steps(prism(Marcher::MaxMip, PrismExit::Walk)));
    EXPECT_FALSE(reads_steps(prism(Marcher::MaxMip, PrismExit::Vertex)));

    EXPECT_FALSE(reads_refine(technique(Technique::Pom)));
    EXPECT_FALSE(reads_refine(technique(Technique::Steep)));
    EXPECT_FALSE(reads_refine(technique(Technique::RelaxedCone))); // exact in each sample's patch
    EXPECT_FALSE(reads_refine(technique(Technique::Cone)));
    EXPECT_TRUE(reads_refine(technique(Technique::Relief)));
    EXPECT_TRUE(reads_refine(prism(Marcher::RelaxedCone, PrismExit::Walk)));
    EXPECT_FALSE(reads_refine(prism(Marcher::Linear, PrismExit::Walk)));
    EXPECT_TRUE(reads_refine(prism(Marcher::MaxMip, PrismExit::Walk)));
    EXPECT_FALSE(reads_refine(prism(Marcher::MaxMip, PrismExit::Exact)));

    EXPECT_FALSE(reads_normal_quality(technique(Technique::Flat)));
    EXPECT_TRUE(reads_normal_quality(technique(Technique::Reference)));

    EXPECT_FALSE(reads_depth_write(technique(Technique::Offset)));
    EXPECT_FALSE(reads_depth_write(technique(Technique::Reference)));
    EXPECT_FALSE(reads_depth_write(prism(Marcher::Relief, PrismExit::Walk)));
    EXPECT_TRUE(reads_depth_write(technique(Technique::Steep)));

    EXPECT_FALSE(reads_light_size(technique(Technique::Pom, Shadows::Hard)));
    EXPECT_FALSE(reads_light_size(technique(Technique::Flat, Shadows::Soft)));
    EXPECT_TRUE(reads_light_size(technique(Technique::Offset, Shadows::Soft)));
    EXPECT_TRUE(reads_light_size(technique(Technique::Reference, Shadows::Soft)));
    EXPECT_FALSE(reads_steps(technique(Technique::Reference, Shadows::Soft)));
}
