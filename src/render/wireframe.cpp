// Wireframe overlays (viewer, docs figures): the base mesh's edges or the prism shells' edges,
// drawn over what the last draw() left in the renderer's target, depth-tested against it, alpha
// untouched (it stays the coverage). Shaders: shaders/prism.vert and wireframe.{geom,frag}, which
// build the shell with prism/shell.glsl like the prism technique.
#include "render/renderer.hpp"

#include "core/error.hpp"
#include "render/shader_program.hpp"

#include "common/shared.h"

#include <glm/gtc/type_ptr.hpp>

namespace pr {

void Renderer::draw_overlay(const Camera& camera, Overlay overlay, glm::vec4 color, const DrawSettings& settings)
{
    const bool shell = overlay == Overlay::PrismShell;
    // The walk's shell (tight tops, from its per-vertex buffer) when that is what the prism draws.
    const bool walk = shell && settings.prism_walk();
    const bool full = walk && settings.full_shell;
    // Keys cannot collide with the technique variants' ("NAME=VALUE;…"); reload_shaders() drops
    // these programs too.
    const std::string key = !shell ? "overlay:base" : !walk ? "overlay:shell" : full ? "overlay:walk-full" : "overlay:walk";
    auto it = programs_.find(key);
    if (it == programs_.end()) {
        ShaderDefines defines;
        if (shell) defines.emplace_back("PR_OVERLAY_SHELL", "1");
        if (walk) defines.emplace_back("PR_PRISM_WALK", "1");
        if (full) defines.emplace_back("PR_PRISM_FULL_SHELL", "1");
        gl::Program p = build_program({{GL_VERTEX_SHADER, "prism.vert"}, // the prism's own shell vertices
                                       {GL_GEOMETRY_SHADER, "wireframe.geom"},
                                       {GL_FRAGMENT_SHADER, "wireframe.frag"}},
                                      defines);
        it = programs_.emplace(key, std::move(p)).first;
    }
    const GLuint program = it->second.id();
    if (walk) ensure_prism_data(true);

    upload_frame(camera, glm::vec3(0.0f, 1.0f, 0.0f)); // the frame block of draw(); no lighting

    glBindFramebuffer(GL_FRAMEBUFFER, fbo_.id());
    glViewport(0, 0, width_, height_);
    use_reversed_depth();
    glDepthFunc(GL_GEQUAL);
    glDepthMask(GL_FALSE);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_FALSE);
    glDisable(GL_CULL_FACE);
    glDisable(GL_BLEND);
    glUseProgram(program);
    glProgramUniform4fv(program, 0, 1, glm::value_ptr(color));

    // Which shell: the prism's (contract: t in [-midlevel, 1 - midlevel]) for prism, reference
    // and flat; base-surface techniques carve inward by depth from the polygon (contract), so
    // their volume is the shell with midlevel 1.
    const Technique t = settings.technique;
    const bool inward = t != Technique::Prism && t != Technique::Reference && t != Technique::Flat;
    for (const GpuObject& o : objects_) {
        upload_object(o, settings, inward ? 1.0f : o.midlevel);
        // The walk's prisms are those of its own triangles (flat stretches merged).
        if (walk) bind_prism_data(o, true);
        const Geometry& g = walk ? walk_geometry(o) : o.base;
        glBindVertexArray(g.vao.id());
        glDrawElements(GL_TRIANGLES, g.index_count, GL_UNSIGNED_INT, nullptr);
    }
    glBindVertexArray(0);
    glUseProgram(0);
    glColorMaski(0, GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_GREATER);
    if (const GLenum err = glGetError(); err != GL_NO_ERROR)
        throw Error("overlay", "OpenGL error " + std::to_string(err));
}

} // namespace pr
