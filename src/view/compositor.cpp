#include "view/compositor.hpp"

#include "core/error.hpp"
#include "render/renderer.hpp"
#include "render/shader_program.hpp"

#include <algorithm>
#include <string>

namespace pr::view {

namespace {

void make_target(int w, int h, gl::Texture& tex, gl::Framebuffer& fbo)
{
    tex = gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(tex.id(), 1, GL_RGBA8, w, h);
    glTextureParameteri(tex.id(), GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(tex.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    fbo = gl::Framebuffer::create();
    glNamedFramebufferTexture(fbo.id(), GL_COLOR_ATTACHMENT0, tex.id(), 0);
    if (glCheckNamedFramebufferStatus(fbo.id(), GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        throw Error("view", "could not create a " + std::to_string(w) + "x" + std::to_string(h) + " view target");
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(fbo.id(), GL_COLOR, 0, zero);
}

const std::vector<ShaderStage> kCompositorStages = {{GL_VERTEX_SHADER, "compositor.vert"},
                                                     {GL_FRAGMENT_SHADER, "compositor.frag"}};

gl::Program compositor_program()
{
    return build_program(kCompositorStages, {});
}

} // namespace

Compositor::Compositor() : program_(compositor_program()), vao_(gl::VertexArray::create()) {}

Compositor::Compositor(EmbeddedShaders)
    : program_(build_embedded_program(kCompositorStages, {})), vao_(gl::VertexArray::create())
{
}

void Compositor::reload_program()
{
    program_ = compositor_program();
}

void Compositor::resize(int width, int height)
{
    if (width == width_ && height == height_) return;
    width_ = width;
    height_ = height;
    make_target(width, height, view_tex_, view_fbo_);
    make_target(width, height, ref_tex_, ref_fbo_);
}

int Compositor::view_column(int x, int src_w) const
{
    if (src_w == width_) return x;
    // The first view column X whose centre maps to x or beyond: (X + 0.5) * src_w / width_ >= x,
    // X >= (2 x width_ - src_w) / (2 src_w), rounded up (the numerator may be negative). (Where a
    // centre falls on x exactly, a driver may round it to x - 1; the right half's copy shows that
    // column then, from a renderer image that by then holds both halves, so the view is right.)
    const long long num = 2LL * x * width_ - src_w, den = 2LL * src_w;
    const long long column = num >= 0 ? (num + den - 1) / den : -((-num) / den);
    return int(std::clamp<long long>(column, 0, width_));
}

void Compositor::copy_view(GLuint source_fbo, int x0, int x1, int src_w, int src_h)
{
    // The whole image is scaled by one ratio, and only the view columns that show renderer columns
    // [x0, x1) are written (the blit honours the scissor). Each half of the split view was
    // stretched by its own ratio (41 columns to 81 for 81 to 161), so at --render-scale below 1
    // the halves were out of line by up to a renderer pixel.
    const int v0 = view_column(x0, src_w), v1 = view_column(x1, src_w);
    if (v1 <= v0) return;
    glEnable(GL_SCISSOR_TEST);
    glScissor(v0, 0, v1 - v0, height_);
    // Nearest, also when scaling (--render-scale): the view target is what screenshots save, and its
    // alpha must stay coverage (0 or 1), with no colour bled in from the empty background.
    glBlitNamedFramebuffer(source_fbo, view_fbo_.id(), 0, 0, src_w, src_h, 0, 0, width_, height_,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
    glDisable(GL_SCISSOR_TEST);
}

void Compositor::copy_reference(GLuint source_fbo, int src_w, int src_h)
{
    glDisable(GL_SCISSOR_TEST);
    // Nearest, as the view is scaled, so that the two coverages are compared pixel for pixel. With
    // linear filtering here, at render scales other than 0.5 silhouette pixels where the two agree
    // were tinted (the reference over itself showed 26 tinted pixels at 0.75).
    glBlitNamedFramebuffer(source_fbo, ref_fbo_.id(), 0, 0, src_w, src_h, 0, 0, width_, height_,
                           GL_COLOR_BUFFER_BIT, GL_NEAREST);
}

void Compositor::clear_view()
{
    const GLfloat zero[4] = {0.0f, 0.0f, 0.0f, 0.0f};
    glClearNamedFramebufferfv(view_fbo_.id(), GL_COLOR, 0, zero);
}

void Compositor::present(const Present& p)
{
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, width_, height_);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_BLEND);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_CULL_FACE);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glUseProgram(program_.id());
    glProgramUniform4f(program_.id(), 0, p.divider_px, p.tint_difference ? 1.0f : 0.0f, float(height_),
                       p.line_width);
    glBindTextureUnit(0, view_tex_.id());
    glBindTextureUnit(1, ref_tex_.id());
    glBindVertexArray(vao_.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    glUseProgram(0);
}

RgbaImage Compositor::read_view() const
{
    return read_texture_rgba8(view_tex_.id(), width_, height_);
}

} // namespace pr::view
