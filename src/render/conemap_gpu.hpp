#pragma once
// Cone-map generation on the GPU (shaders/conemap.comp): the CPU generator's algorithm
// (maps/conemap.cpp) in a compute shader, one invocation per texel, so the maps are the same (see
// docs/cone-maps.md for the tolerance). Needs a current OpenGL 4.5 context, or `make_current`.
#include "maps/conemap.hpp"

namespace pr {

// What a GPU build did besides the map (prismrelief conemap --json reports it).
struct ConeGpuReport {
    double search_ms = 0.0;     // the seeds, the dispatches, the read-back and the CPU's share
                                // below, without creating the context, uploading and compiling
    double cpu_ms = 0.0;        // of that, the CPU's threads finishing searches that ran out of nodes
    std::size_t resumed = 0;    // searches the CPU went on with from the GPU's state
    std::size_t restarted = 0;  // texels the CPU searched again from the start (no room for a state)
    double seed_ms = 0.0;       // of search_ms, finding the seeds (maps::ConeSeeds); on the CPU,
                                // the wait for those begun before the context (make_current)
    bool seeds_on_cpu = false;  // found by the CPU's threads (ConeBuildOptions::gpu_seed_pass)
};

// Splits the work into dispatches of a few thousand texels, each finished before the next, so a
// software rasterizer (llvmpipe) never runs one long dispatch; options.progress is called
// between them. Where a texel's search ran out of nodes (ConeBuildOptions::node_budget), the GPU
// saves its state and the CPU's threads go on from there after the dispatch, best first as the
// CPU's own search does, so the map is the CPU generator's (where more searches ran out than
// ConeBuildOptions::gpu_resume_capacity holds, those texels are searched again from the start).
// Throws pr::Error("conemap", …) on GL failure. With `make_current`, the context is made by
// that call, after the CPU's share of the work (the max pyramid) and before the first GL call:
// `prismrelief conemap` loads Mesa on another thread meanwhile (preload_backend). Unless
// ConeBuildOptions::gpu_seed_pass says Gpu, the CPU's threads begin on the seeds before that
// call, and are stopped where the renderer turns out to be a GPU's.
ConeMap build_cone_map_gpu(const HeightField& field, ConeKind kind, const ConeBuildOptions& options = {},
                           ConeGpuReport* report = nullptr, const std::function<void()>& make_current = {});

} // namespace pr
