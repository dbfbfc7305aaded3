#pragma once
// Cone-map generation on the GPU (shaders/conemap.comp): the CPU generator's algorithm
// (maps/conemap.cpp) in a compute shader, one invocation per texel, so the maps are the same (see
// docs/cone-maps.md for the tolerance). Needs a current OpenGL 4.5 context, or `make_current`.
#include "maps/conemap.hpp"

namespace pr {

// Splits the work into dispatches of a few thousand texels, each finished before the next, so a
// software rasterizer (llvmpipe) never runs one long dispatch; options.progress is called
// between them. The texels whose search ran out of nodes (ConeBuildOptions::node_budget) are
// searched again on options.threads CPU threads after their dispatch (the CPU goes on best first
// there). Throws pr::Error("conemap", …) on GL failure. With `search_ms`, the time of the
// dispatches, the read-back and those CPU searches, without uploading and compiling
// (prismrelief conemap --json reports both). With `make_current`, the context is made
// by that call, after the CPU's share of the work (the max pyramid) and before the first GL call:
// `prismrelief conemap` loads Mesa on another thread meanwhile (preload_backend).
ConeMap build_cone_map_gpu(const HeightField& field, ConeKind kind, const ConeBuildOptions& options = {},
                           double* search_ms = nullptr, const std::function<void()>& make_current = {});

} // namespace pr
