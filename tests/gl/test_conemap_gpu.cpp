// The GPU cone-map generator (render/conemap_gpu, shaders/conemap.comp) against the CPU one.
// Tolerance: none. Both run the same double-precision arithmetic with no fused multiply-add and
// a pruning that never changes the rounded result, so the integer steps must be identical; the
// test reports the largest difference if they are not.
#include "gl_fixture.hpp"

#include "core/error.hpp"
#include "maps/conemap.hpp"
#include "render/conemap_gpu.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

using namespace pr;

namespace {

HeightField field_of(int w, int h, unsigned seed, bool smooth)
{
    HeightField f;
    f.width = w;
    f.height = h;
    f.bits = 16;
    f.name = "test";
    std::mt19937 rng(seed);
    std::uniform_int_distribution<int> d(0, 65535);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            double v = d(rng) / 65535.0;
            if (smooth)
                v = 0.5 + 0.25 * std::sin(6.2831853 * 3 * x / w) * std::cos(6.2831853 * 2 * y / h) +
                    0.2 * ((x / 8 + y / 8) % 2) + 0.02 * v;
            f.texels.push_back(float(std::round(std::clamp(v, 0.0, 1.0) * 65535.0) / 65535.0));
        }
    return f;
}

void expect_same(const ConeMap& gpu, const ConeMap& cpu, ConeFormat format, const char* what)
{
    ASSERT_EQ(gpu.ratios.size(), cpu.ratios.size());
    const int steps = cone_format_steps(format);
    int differ = 0, worst = 0;
    for (std::size_t i = 0; i < cpu.ratios.size(); ++i) {
        const int d = int(std::lround(std::abs(double(gpu.ratios[i]) - double(cpu.ratios[i])) * steps));
        if (d != 0 && differ < 5)
            ADD_FAILURE() << what << ": texel " << i << " gpu " << gpu.ratios[i] << " cpu " << cpu.ratios[i];
        differ += d != 0;
        worst = std::max(worst, d);
    }
    EXPECT_EQ(differ, 0) << what << ": " << differ << " texels differ, by up to " << worst << " steps";
    EXPECT_EQ(gpu.heights, cpu.heights);
}

} // namespace

TEST(ConeMapGpu, EqualsCpuCone)
{
    prtest::context();
    // The seeds (maps::ConeSeeds) from the shader's seed passes and from the CPU's threads (what
    // llvmpipe gets by itself).
    for (bool smooth : {false, true})
        for (ConeFormat format : {ConeFormat::Rg8, ConeFormat::Rg16})
            for (auto seeds : {ConeBuildOptions::SeedPass::Gpu, ConeBuildOptions::SeedPass::Auto}) {
                const HeightField f = field_of(64, 40, smooth ? 3u : 4u, smooth);
                ConeBuildOptions o;
                o.format = format;
                o.gpu_seed_pass = seeds;
                ConeGpuReport report;
                expect_same(build_cone_map_gpu(f, ConeKind::Cone, o, &report), build_cone_map_cpu(f, ConeKind::Cone, o),
                            format, smooth ? "cone smooth" : "cone random");
                EXPECT_EQ(report.seeds_on_cpu, seeds == ConeBuildOptions::SeedPass::Auto); // (llvmpipe)
            }
}

TEST(ConeMapGpu, EqualsCpuRelaxed)
{
    prtest::context();
    for (bool smooth : {false, true}) {
        const HeightField f = field_of(48, 48, smooth ? 5u : 6u, smooth);
        for (int budget : {0, ConeBuildOptions{}.relaxed_budget, 24}) { // exact, the default, one that binds often
            ConeBuildOptions o;
            o.relaxed_budget = budget;
            o.gpu_seed_pass = budget == 24 ? ConeBuildOptions::SeedPass::Gpu : ConeBuildOptions::SeedPass::Cpu;
            int calls = 0;
            o.progress = [&](double) { ++calls; };
            ConeBuildOptions cpu = o;
            cpu.progress = nullptr;
            expect_same(build_cone_map_gpu(f, ConeKind::Relaxed, o), build_cone_map_cpu(f, ConeKind::Relaxed, cpu),
                        ConeFormat::Rg16, smooth ? "relaxed smooth" : "relaxed random");
            EXPECT_GE(calls, 1);
        }
    }
    // Odd sizes: the march's bilinear samples come four at a time from a repeating 2D texture
    // (conemap.comp, bilinear), whose wrap at the edges must be the CPU's.
    for (const auto& [w, h] : {std::pair{37, 23}, std::pair{5, 61}}) {
        const HeightField f = field_of(w, h, 9u, false);
        expect_same(build_cone_map_gpu(f, ConeKind::Relaxed, {}), build_cone_map_cpu(f, ConeKind::Relaxed, {}),
                    ConeFormat::Rg16, ("relaxed " + std::to_string(w) + "x" + std::to_string(h)).c_str());
    }
}

TEST(ConeMapGpu, EqualsCpuWithABindingNodeBudget)
{
    prtest::context();
    HeightField f = field_of(64, 48, 8, true);
    for (int y = 0; y < f.height; ++y) // a ramp: the search runs out of nodes on most texels
        for (int x = 0; x < f.width; ++x) f.texels[std::size_t(y * f.width + x)] = float(x + 0.3 * y) / 80.0f;
    // The GPU searches depth first; where its nodes run out the CPU goes on best first, from the
    // state the GPU saved: with that part off, running out, and finishing; and with room for the
    // state of one search per dispatch, so that the CPU searches those texels again from the start.
    // The seeds' searches run out of nodes too (they keep the best found by then): found by the
    // shader and by the CPU's threads.
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed})
        for (int best_first : {0, 24, 1024})
            for (int capacity : {0, 1}) {
                ConeBuildOptions o;
                o.node_budget = 24;
                o.best_first_budget = best_first;
                o.gpu_resume_capacity = capacity;
                o.gpu_seed_pass = best_first == 24 ? ConeBuildOptions::SeedPass::Cpu : ConeBuildOptions::SeedPass::Gpu;
                const std::string what = std::string(kind == ConeKind::Cone ? "cone" : "relaxed") +
                                         " ramp budget, best first " + std::to_string(best_first) +
                                         (capacity == 1 ? ", no room" : "") +
                                         (best_first == 24 ? ", seeds on the CPU" : ", seeds on the GPU");
                ConeGpuReport report;
                expect_same(build_cone_map_gpu(f, kind, o, &report), build_cone_map_cpu(f, kind, o), ConeFormat::Rg16,
                            what.c_str());
                // Most texels of a ramp run out of 24 nodes (kind relaxed: in both its searches).
                if (capacity == 0) {
                    EXPECT_GT(report.resumed, f.texels.size() / 2) << what;
                    EXPECT_EQ(report.restarted, 0u) << what;
                } else {
                    EXPECT_GT(report.restarted, f.texels.size() / 2) << what;
                }
            }
}

// The CPU's threads find the seeds while the context is made (make_current; render/conemap_gpu.cpp,
// EarlySeeds): a context that fails, or a build cancelled meanwhile, stops them (a thread left
// running would end the process), and the progress of a build goes from the seeds' share to 1
// without going back.
TEST(ConeMapGpu, SeedsFoundWhileTheContextIsMadeStopWithTheBuild)
{
    prtest::context();
    const HeightField f = field_of(96, 64, 11u, true);
    EXPECT_THROW(build_cone_map_gpu(f, ConeKind::Relaxed, {}, nullptr, [] { throw Error("--backend", "no context"); }),
                 Error);
    std::atomic<bool> cancel{false};
    ConeBuildOptions o;
    o.cancel = &cancel;
    EXPECT_THROW(build_cone_map_gpu(f, ConeKind::Relaxed, o, nullptr, [&] { cancel = true; }), ConeBuildCancelled);
    std::vector<double> seen;
    ConeBuildOptions p;
    p.progress = [&](double v) { seen.push_back(v); };
    ConeGpuReport report;
    expect_same(build_cone_map_gpu(f, ConeKind::Relaxed, p, &report, [] {}), build_cone_map_cpu(f, ConeKind::Relaxed, {}),
                ConeFormat::Rg16, "relaxed, seeds while the context is made");
    EXPECT_TRUE(report.seeds_on_cpu); // (llvmpipe)
    ASSERT_FALSE(seen.empty());
    EXPECT_TRUE(std::is_sorted(seen.begin(), seen.end()));
    EXPECT_GE(seen.front(), 0.0);
    EXPECT_DOUBLE_EQ(seen.back(), 1.0);
    EXPECT_NE(std::find(seen.begin(), seen.end(), kConeSeedProgress), seen.end());
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

// A cancelled build (the viewer's, when the scene changes) throws and leaves nothing of its own
// bound in the caller's context.
TEST(ConeMapGpu, ACancelledBuildLeavesTheContextAsItWas)
{
    prtest::context();
    const std::atomic<bool> cancel{true};
    ConeBuildOptions o;
    o.cancel = &cancel;
    EXPECT_THROW(build_cone_map_gpu(field_of(32, 32, 3, true), ConeKind::Relaxed, o), ConeBuildCancelled);
    GLint program = -1, texture = -1;
    glGetIntegerv(GL_CURRENT_PROGRAM, &program);
    EXPECT_EQ(program, 0);
    for (GLuint binding : {0u, 1u, 2u, 3u, 4u}) {
        GLint storage = -1;
        glGetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, binding, &storage);
        EXPECT_EQ(storage, 0) << binding;
    }
    glActiveTexture(GL_TEXTURE0);
    glGetIntegerv(GL_TEXTURE_BINDING_BUFFER, &texture);
    EXPECT_EQ(texture, 0);
    EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST(ConeMapGpu, SpikeAndLargerThanOneChunk)
{
    prtest::context();
    HeightField f = field_of(160, 130, 7, false); // 20800 texels: two dispatches
    for (float& t : f.texels) t = 0.0f;
    f.texels[1234] = 1.0f;
    expect_same(build_cone_map_gpu(f, ConeKind::Cone, {}), build_cone_map_cpu(f, ConeKind::Cone, {}),
                ConeFormat::Rg16, "spike");
}

// An rg8 map stores 8-bit heights, so both generators build it from those (the 16-bit field
// rounded as the PNG's R channel rounds it): the same map, conservative against its own heights
// (brute force), cone and relaxed.
TEST(ConeMapGpu, Rg8MapsAreBuiltFromTheirStoredHeights)
{
    prtest::context();
    const HeightField f = field_of(48, 40, 10u, true);
    ConeBuildOptions o;
    o.format = ConeFormat::Rg8;
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed}) {
        const ConeMap gpu = build_cone_map_gpu(f, kind, o);
        expect_same(gpu, build_cone_map_cpu(f, kind, o), ConeFormat::Rg8,
                    kind == ConeKind::Cone ? "cone rg8" : "relaxed rg8");
        ASSERT_EQ(gpu.heights.size(), f.texels.size());
        for (std::size_t i = 0; i < f.texels.size(); ++i)
            ASSERT_EQ(gpu.heights[i], float(std::lround(std::clamp(f.texels[i], 0.0f, 1.0f) * 255.0f)) / 255.0f) << i;
        if (kind == ConeKind::Relaxed) continue; // not conservative by design
        int inside = 0;
        for (int py = 0; py < f.height; ++py)
            for (int px = 0; px < f.width; ++px) {
                const double r = gpu.ratios[std::size_t(py * f.width + px)];
                const double hp = gpu.heights[std::size_t(py * f.width + px)];
                for (int qy = 0; qy < f.height; ++qy)
                    for (int qx = 0; qx < f.width; ++qx) {
                        const double dh = double(gpu.heights[std::size_t(qy * f.width + qx)]) - hp;
                        int dx = std::abs(qx - px), dy = std::abs(qy - py);
                        dx = std::min(dx, f.width - dx);
                        dy = std::min(dy, f.height - dy);
                        const double d = std::sqrt(double(dx * dx) / double(f.width * f.width) +
                                                   double(dy * dy) / double(f.height * f.height));
                        inside += dh > 0 && d < r * r * dh;
                    }
            }
        EXPECT_EQ(inside, 0);
    }
}

// Maps with more pyramid texels than GL_MAX_TEXTURE_BUFFER_SIZE are read from storage buffers
// (conemap.comp, PR_CONE_BUFFERS): the same maps as the CPU's, both kinds.
TEST(ConeMapGpu, StorageBufferPathEqualsCpu)
{
    prtest::context();
    const HeightField f = field_of(40, 36, 9u, true);
    ConeBuildOptions o;
    o.gpu_storage_buffers = true;
    for (ConeKind kind : {ConeKind::Cone, ConeKind::Relaxed})
        expect_same(build_cone_map_gpu(f, kind, o), build_cone_map_cpu(f, kind, {}), ConeFormat::Rg16,
                    kind == ConeKind::Cone ? "cone, storage buffers" : "relaxed, storage buffers");
}
