#pragma once
// Builds GL programs from the embedded shader files. Variants are chosen by #define lines placed
// after `#version` (never by editing shader text); `#include "path"` (relative to shaders/) is
// resolved once per file with `#line` directives, so compile errors name the real file and line.
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "gl/objects.hpp"

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace pr {

struct ShaderStage {
    GLenum stage;        // GL_VERTEX_SHADER, GL_GEOMETRY_SHADER, GL_FRAGMENT_SHADER, GL_COMPUTE_SHADER
    std::string file;    // relative to shaders/, e.g. "surface.frag"
};

using ShaderDefines = std::vector<std::pair<std::string, std::string>>; // name, value

// The text of shaders/<path>: embedded at build time, or read from the folder named by the
// environment variable PRISMRELIEF_SHADER_DIR when it is set (development override for hot
// reload). Throws ShaderError("shaders/<path>", …) when there is no such embedded file, and one
// named by the override (name_shader_dir) when its folder or the file in it is missing or
// cannot be read.
std::string shader_file(const std::string& path);

// What the errors call the override folder: "PRISMRELIEF_SHADER_DIR", or the flag that set it
// (the viewer's --shader-dir).
void name_shader_dir(const std::string& name);

// How messages name shaders/<path>: so, or the file in the override folder where one is set.
std::string shader_path_shown(const std::string& path);

// What shader_file, preprocess_shader and build_program throw: a shader that cannot be read or
// built (the viewer shows these in its panel; it told them by "shaders/" in the text, which a
// folder named otherwise lacks and another input's path may hold).
class ShaderError : public Error {
public:
    using Error::Error;
};

// The full source handed to the compiler for one stage, and the files it was made of (the
// index is the source-string number used in #line directives).
struct PreprocessedShader {
    std::string text;
    std::vector<std::string> files;
};
PreprocessedShader preprocess_shader(const std::string& file, const ShaderDefines& defines);

// Compiles and links. Throws ShaderError(shader_path_shown(file), "<log with file:line>") on failure.
gl::Program build_program(const std::vector<ShaderStage>& stages, const ShaderDefines& defines);
// The same from the embedded copies alone, whatever PRISMRELIEF_SHADER_DIR says: for a program
// that must exist, where the folder's copy does not build and there is no earlier one to keep
// (the viewer's compositor at its start).
gl::Program build_embedded_program(const std::vector<ShaderStage>& stages, const ShaderDefines& defines);

// Every shader file the program table knows, for the test that compiles every variant.
std::vector<std::string> shader_file_list();

// The files a run reads under PRISMRELIEF_SHADER_DIR (none without it), as inputs for
// check_distinct_outputs() named by the variable: its outputs must not replace them (`render --out
// shaders/surface.frag` with the variable set broke every later run).
std::vector<NamedPath> shader_override_inputs();

} // namespace pr
