#pragma once
// Shader text embedded at build time (cmake/EmbedShaders.cmake), with an optional development
// override that reads shaders/ from disk for hot reload.
#include <optional>
#include <string>
#include <vector>

namespace pr {

struct EmbeddedShader {
    const char* path;   // relative to shaders/, e.g. "surface.frag", "march/linear.glsl"
    const char* source;
};

// Every file under shaders/, sorted by path.
const std::vector<EmbeddedShader>& embedded_shaders();

} // namespace pr
