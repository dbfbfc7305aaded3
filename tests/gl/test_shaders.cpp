// Every shader variant compiles and links; the C++ and GLSL views of the uniform blocks agree.
#include "gl_fixture.hpp"

#include "core/error.hpp"
#include "render/shader_program.hpp"

#include "common/shared.h"

#include <cstddef>
#include <cstdlib>
#include <filesystem>
#include <fstream>

using namespace pr;

TEST(ShaderVariants, EveryTechniqueQualityAndInstrumentationCompiles)
{
    prtest::context();
    Renderer r(8, 8);
    for (const TechniqueInfo& t : technique_table())
        for (NormalQuality q : {NormalQuality::Gather, NormalQuality::Central, NormalQuality::Sobel})
            for (bool depth_write : {false, true})
                for (bool count : {false, true}) {
                    DrawSettings s;
                    s.technique = t.technique;
                    s.normal_quality = q;
                    s.depth_write = depth_write;
                    s.count_samples = count;
                    for (Marcher m : {Marcher::Linear, Marcher::Relief})
                        for (PrismExit e : {PrismExit::Walk, PrismExit::Exact, PrismExit::Vertex})
                            for (bool full_shell : {false, true}) {
                                s.marcher = m;
                                s.prism_exit = e;
                                s.full_shell = full_shell;
                                EXPECT_NO_THROW(r.program_for(s)) << t.name << " " << normal_quality_name(q);
                                if (t.technique != Technique::Prism) break;
                            }
                }
}

// Self-shadowing in every technique that takes it, and in the prism's exact and per-vertex exits
// with every marcher (the thin-shell change in prism.frag left the shadows reading a variable
// those exits no longer declared: "'below' undeclared", found by a review).
TEST(ShaderVariants, ShadowsCompileWithEveryTechniqueAndExit)
{
    prtest::context();
    Renderer r(8, 8);
    for (const TechniqueInfo& t : technique_table())
        for (Shadows shadows : {Shadows::Hard, Shadows::Soft}) {
            DrawSettings s;
            s.technique = t.technique;
            s.shadows = shadows;
            if (t.technique != Technique::Prism) {
                EXPECT_NO_THROW(r.program_for(s)) << t.name << " " << shadows_name(shadows);
                continue;
            }
            for (Marcher m : {Marcher::Linear, Marcher::Relief, Marcher::Cone, Marcher::RelaxedCone, Marcher::MaxMip})
                for (PrismExit e : {PrismExit::Exact, PrismExit::Vertex}) {
                    s.marcher = m;
                    s.prism_exit = e;
                    EXPECT_NO_THROW(r.program_for(s)) << marcher_name(m) << " " << prism_exit_name(e) << " "
                                                      << shadows_name(shadows);
                }
        }
}

// The colour texture's variant (PR_COLOR_TEXTURE, chosen per object) in every technique, with and
// without shadows, and in every program of the prism walk's passes that draw() builds (with the
// relief and relaxed-cone marchers).
TEST(ShaderVariants, ColourTextureVariantsCompile)
{
    prtest::context();
    Renderer r(8, 8);
    using Pass = Renderer::WalkVariant;
    using Draw = Renderer::ShellDraw;
    for (Shadows shadows : {Shadows::None, Shadows::Hard})
        for (const TechniqueInfo& t : technique_table()) {
            DrawSettings s;
            s.technique = t.technique;
            s.shadows = shadows;
            EXPECT_NO_THROW(r.program_for(s, Pass::Plain, Draw::Faces, true)) << t.name;
            if (t.technique != Technique::Prism) continue;
            for (Marcher m : {Marcher::Relief, Marcher::RelaxedCone}) {
                s.marcher = m;
                for (const auto& [pass, draw] : {std::pair{Pass::Seamless, Draw::Tops}, std::pair{Pass::Through, Draw::Tops},
                                                 std::pair{Pass::Through, Draw::Listed}, std::pair{Pass::Through, Draw::FromEye},
                                                 std::pair{Pass::Inside, Draw::Listed}, std::pair{Pass::UnderSurface, Draw::Bottoms},
                                                 std::pair{Pass::UnderSurface, Draw::FromEye}, std::pair{Pass::OpenEntry, Draw::Listed}})
                    EXPECT_NO_THROW(r.program_for(s, pass, draw, true)) << t.name << " " << marcher_name(m);
            }
        }
}

// The prism walk's variants by UV seams (none at all; torn: through the tears, and the second
// pass from inside), with every marcher, self-shadowing and instrumentation, in the programs
// draw() builds: the caps by the vertex shader (bottoms: open meshes) and the listed prisms by
// the geometry shader (the second pass only listed).
TEST(ShaderVariants, PrismWalkVariantsCompileWithEveryMarcher)
{
    prtest::context();
    Renderer r(8, 8);
    for (Marcher m : {Marcher::Linear, Marcher::Relief, Marcher::Cone, Marcher::RelaxedCone, Marcher::MaxMip})
        for (Renderer::WalkVariant pass :
             {Renderer::WalkVariant::Seamless, Renderer::WalkVariant::Through, Renderer::WalkVariant::Inside})
            for (Shadows shadows : {Shadows::None, Shadows::Soft})
                for (bool count : {false, true}) {
                    DrawSettings s;
                    s.technique = Technique::Prism;
                    s.marcher = m;
                    s.shadows = shadows;
                    s.count_samples = count;
                    using Draw = Renderer::ShellDraw;
                    for (Draw draw : {Draw::Tops, Draw::Bottoms, Draw::Listed})
                        if (pass != Renderer::WalkVariant::Inside || draw == Draw::Listed)
                            EXPECT_NO_THROW(r.program_for(s, pass, draw)) << marcher_name(m);
                }
}

// A broken shader (through the PRISMRELIEF_SHADER_DIR override) fails with the file and the
// line of the mistake, also inside an included file, each named in the folder it was read from
// (they were named shaders/..., which is not the file the user edits: found by an exploratory
// session, thirty-eighth).
TEST(ShaderVariants, CompileErrorNamesFileAndLine)
{
    prtest::context();
    const std::filesystem::path dir = std::filesystem::temp_directory_path() / "pr_broken_shaders";
    for (const std::string& f : shader_file_list()) {
        std::filesystem::create_directories((dir / f).parent_path());
        std::string text = shader_file(f);
        if (f == "march/linear.glsl") {
            // Break line 3 of the included marcher.
            std::size_t pos = 0;
            for (int i = 0; i < 2; ++i) pos = text.find('\n', pos) + 1;
            text.insert(pos, "this is not glsl;\n");
        }
        std::ofstream(dir / f) << text;
    }
    setenv("PRISMRELIEF_SHADER_DIR", dir.c_str(), 1);
    std::string what;
    try {
        build_program({{GL_FRAGMENT_SHADER, "surface.frag"}},
                      {{"PR_TECHNIQUE", "PR_TECH_POM"}, {"PR_NORMAL_QUALITY", "PR_NORMAL_SOBEL"}});
    } catch (const Error& e) {
        what = e.what();
    }
    unsetenv("PRISMRELIEF_SHADER_DIR");
    std::filesystem::remove_all(dir);
    EXPECT_EQ(what.rfind((dir / "surface.frag").string() + ": compile error (variant: PR_TECHNIQUE=", 0), 0u) << what;
    EXPECT_NE(what.find("\n" + (dir / "march/linear.glsl").string() + ":3:"), std::string::npos) << what;
}

TEST(SharedLayout, UniformBlockOffsetsMatchCpp)
{
    prtest::context();
    Renderer r(8, 8);
    DrawSettings s;
    s.technique = Technique::Relief;
    const GLuint program = r.program_for(s);
    const auto offset_of = [program](const char* name) {
        GLuint index = GL_INVALID_INDEX;
        glGetUniformIndices(program, 1, &name, &index);
        EXPECT_NE(index, GL_INVALID_INDEX) << name;
        GLint offset = -1;
        glGetActiveUniformsiv(program, 1, &index, GL_UNIFORM_OFFSET, &offset);
        return offset;
    };
    const auto block_size = [program](const char* name) {
        const GLuint b = glGetUniformBlockIndex(program, name);
        GLint size = 0;
        glGetActiveUniformBlockiv(program, b, GL_UNIFORM_BLOCK_DATA_SIZE, &size);
        return size;
    };
    EXPECT_EQ(block_size("FrameBlock"), GLint(sizeof(shader::FrameBlock)));
    EXPECT_EQ(block_size("ObjectBlock"), GLint(sizeof(shader::ObjectBlock)));
    EXPECT_EQ(offset_of("u_view_proj"), GLint(offsetof(shader::FrameBlock, u_view_proj)));
    EXPECT_EQ(offset_of("u_eye"), GLint(offsetof(shader::FrameBlock, u_eye)));
    EXPECT_EQ(offset_of("u_light_dir"), GLint(offsetof(shader::FrameBlock, u_light_dir)));
    EXPECT_EQ(offset_of("u_normal_matrix"), GLint(offsetof(shader::ObjectBlock, u_normal_matrix)));
    EXPECT_EQ(offset_of("u_displace"), GLint(offsetof(shader::ObjectBlock, u_displace)));
    EXPECT_EQ(offset_of("u_march"), GLint(offsetof(shader::ObjectBlock, u_march)));
    EXPECT_EQ(offset_of("u_material"), GLint(offsetof(shader::ObjectBlock, u_material)));
    EXPECT_EQ(offset_of("u_base_color"), GLint(offsetof(shader::ObjectBlock, u_base_color)));
    EXPECT_EQ(offset_of("u_eye_tex"), GLint(offsetof(shader::ObjectBlock, u_eye_tex)));
}

TEST(Context, IsOpenGL45Core)
{
    const std::string d = prtest::context().description();
    EXPECT_NE(d.find("OpenGL 4."), std::string::npos) << d;
    GLint major = 0, minor = 0, mask = 0;
    glGetIntegerv(GL_MAJOR_VERSION, &major);
    glGetIntegerv(GL_MINOR_VERSION, &minor);
    glGetIntegerv(GL_CONTEXT_PROFILE_MASK, &mask);
    EXPECT_GE(major * 10 + minor, 45);
    EXPECT_TRUE(mask & GL_CONTEXT_CORE_PROFILE_BIT);
}
