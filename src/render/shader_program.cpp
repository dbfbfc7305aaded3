#include "render/shader_program.hpp"

#include "core/error.hpp"
#include "core/input_file.hpp"
#include "render/shader_sources.hpp"

#include <cstdlib>
#include <filesystem>
#include <regex>
#include <set>
#include <sstream>

namespace pr {

namespace {

std::string& shader_dir_name()
{
    static std::string name = "PRISMRELIEF_SHADER_DIR";
    return name;
}

// Set while build_embedded_program() builds: the override folder is passed over.
thread_local bool embedded_only = false;

// The override folder (PRISMRELIEF_SHADER_DIR), or null where none is set.
const char* shader_dir()
{
    if (embedded_only) return nullptr;
    const char* dir = std::getenv("PRISMRELIEF_SHADER_DIR");
    return dir && *dir ? dir : nullptr;
}

} // namespace

void name_shader_dir(const std::string& name)
{
    shader_dir_name() = name;
}

std::string shader_path_shown(const std::string& path)
{
    if (const char* dir = shader_dir()) return (std::filesystem::path(dir) / path).string();
    return "shaders/" + path;
}

std::string shader_file(const std::string& path)
{
    if (const char* dir = shader_dir()) {
        const std::string file = shader_path_shown(path); // (as messages name it: "sd/" gave "sd//x")
        std::error_code ec;
        // Named by what gave the folder: the headless commands have no --shader-dir (the message
        // offered it, and named shaders/<path>, a file the user had not given; found by a docs
        // audit, thirty-eighth session).
        if (!std::filesystem::is_directory(dir, ec)) throw ShaderError(shader_dir_name(), std::string(dir) + " is not a folder");
        if (!std::filesystem::exists(file, ec))
            throw ShaderError(shader_dir_name(), std::string(dir) + " has no " + path +
                                                     " (the folder stands in for the source's shaders/)");
        // (The input reader: a FIFO there without a writer is refused after 1 s, not waited on.)
        try {
            return read_input_text(file, InputLimit{16u << 20, "a shader", "not a shader"});
        } catch (const ShaderError&) {
            throw;
        } catch (const Error& e) {
            throw ShaderError(e.subject(), e.problem(), e.detail());
        }
    }
    for (const EmbeddedShader& e : embedded_shaders())
        if (path == e.path) return e.source;
    throw ShaderError(shader_path_shown(path), "no such embedded shader");
}

std::vector<std::string> shader_file_list()
{
    std::vector<std::string> out;
    for (const EmbeddedShader& e : embedded_shaders()) out.emplace_back(e.path);
    return out;
}

std::vector<NamedPath> shader_override_inputs()
{
    std::vector<NamedPath> out;
    if (const char* dir = shader_dir())
        for (const EmbeddedShader& e : embedded_shaders())
            out.emplace_back("PRISMRELIEF_SHADER_DIR", std::filesystem::path(dir) / e.path);
    return out;
}

namespace {

void append_file(const std::string& path, PreprocessedShader& out, std::set<std::string>& seen,
                 int depth)
{
    if (depth > 16) throw ShaderError(shader_path_shown(path), "#include nested too deeply");
    if (!seen.insert(path).second) return; // every file is included once (like #pragma once)
    const int id = static_cast<int>(out.files.size());
    out.files.push_back(path);
    std::istringstream in(shader_file(path));
    std::string line;
    int number = 0;
    out.text += "#line 1 " + std::to_string(id) + "\n";
    static const std::regex include_re(R"(^\s*#\s*include\s+\"([^\"]+)\"\s*$)");
    static const std::regex pragma_once_re(R"(^\s*#\s*pragma\s+once\s*$)");
    while (std::getline(in, line)) {
        ++number;
        std::smatch m;
        if (std::regex_match(line, m, include_re)) {
            append_file(m[1].str(), out, seen, depth + 1);
            out.text += "#line " + std::to_string(number + 1) + " " + std::to_string(id) + "\n";
        } else if (std::regex_match(line, pragma_once_re)) {
            out.text += "\n"; // GLSL has no #pragma once; C++ uses it in shared headers
        } else {
            out.text += line + "\n";
        }
    }
}

// Rewrites "0:12(5): error: …" (Mesa) and "0(12) : error …" (NVIDIA) to "surface.frag:12: …".
std::string map_log(const std::string& log, const std::vector<std::string>& files)
{
    static const std::regex mesa(R"((\d+):(\d+)\((\d+)\))");
    static const std::regex nvidia(R"((\d+)\((\d+)\) ?)");
    std::string out;
    std::istringstream in(log);
    std::string line;
    while (std::getline(in, line)) {
        std::smatch m;
        const auto name = [&](const std::string& id) {
            const auto i = static_cast<std::size_t>(std::stoul(id));
            return i < files.size() ? shader_path_shown(files[i]) : "source " + id;
        };
        if (std::regex_search(line, m, mesa) && m.position(0) == 0)
            line = name(m[1]) + ":" + m[2].str() + ":" + m[3].str() + m.suffix().str();
        else if (std::regex_search(line, m, nvidia) && m.position(0) == 0)
            line = name(m[1]) + ":" + m[2].str() + m.suffix().str();
        out += line + "\n";
    }
    while (!out.empty() && out.back() == '\n') out.pop_back();
    return out;
}

} // namespace

PreprocessedShader preprocess_shader(const std::string& file, const ShaderDefines& defines)
{
    PreprocessedShader out;
    out.text = "#version 450 core\n";
    for (const auto& [name, value] : defines) out.text += "#define " + name + " " + value + "\n";
    std::set<std::string> seen;
    append_file(file, out, seen, 0);
    return out;
}

gl::Program build_embedded_program(const std::vector<ShaderStage>& stages, const ShaderDefines& defines)
{
    struct Embedded {
        Embedded() { embedded_only = true; }
        ~Embedded() { embedded_only = false; }
    } embedded;
    return build_program(stages, defines);
}

gl::Program build_program(const std::vector<ShaderStage>& stages, const ShaderDefines& defines)
{
    gl::Program program = gl::Program::create();
    std::vector<gl::Shader> shaders;
    for (const ShaderStage& s : stages) {
        const PreprocessedShader pre = preprocess_shader(s.file, defines);
        gl::Shader shader = gl::Shader::create(s.stage);
        const char* text = pre.text.c_str();
        glShaderSource(shader.id(), 1, &text, nullptr);
        glCompileShader(shader.id());
        GLint ok = 0;
        glGetShaderiv(shader.id(), GL_COMPILE_STATUS, &ok);
        if (!ok) {
            GLint len = 0;
            glGetShaderiv(shader.id(), GL_INFO_LOG_LENGTH, &len);
            std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
            glGetShaderInfoLog(shader.id(), len, nullptr, log.data());
            std::string variant;
            for (const auto& [name, value] : defines) variant += " " + name + "=" + value;
            // (Named where the file was read: the folder of --shader-dir or PRISMRELIEF_SHADER_DIR
            // was said as shaders/; and no "(variant:)" for a program without defines.)
            throw ShaderError(shader_path_shown(s.file), "compile error" + (variant.empty() ? "" : " (variant:" + variant + ")"),
                        map_log(log.c_str(), pre.files));
        }
        glAttachShader(program.id(), shader.id());
        shaders.push_back(std::move(shader));
    }
    glLinkProgram(program.id());
    GLint ok = 0;
    glGetProgramiv(program.id(), GL_LINK_STATUS, &ok);
    for (const gl::Shader& s : shaders) glDetachShader(program.id(), s.id());
    if (!ok) {
        GLint len = 0;
        glGetProgramiv(program.id(), GL_INFO_LOG_LENGTH, &len);
        std::string log(static_cast<std::size_t>(std::max(len, 1)), '\0');
        glGetProgramInfoLog(program.id(), len, nullptr, log.data());
        throw ShaderError(shader_path_shown(stages.front().file), "link error", std::string(log.c_str()));
    }
    return program;
}

} // namespace pr
