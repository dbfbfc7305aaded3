// Wireframe overlays: placeholder until the viewer issue lands.
#include "render/renderer.hpp"

namespace pr {

void Renderer::draw_overlay(const Camera&, Overlay, glm::vec4, const DrawSettings&) {}

} // namespace pr
