#pragma once
// prismrelief view: the interactive viewer. It draws with the one Renderer that render, compare
// and bench use (into the renderer's FBO, copied to the window), so techniques added to
// technique_table() and marchers to marcher_names() appear without changes here.
#include "app/session.hpp"
#include "render/technique.hpp"

#include <optional>
#include <string>
#include <vector>

namespace pr {
class GlfwWindow;
}

namespace pr::view {

enum class WireOverlay { None, Base, Shell };
WireOverlay parse_wire_overlay(const std::string& name, const std::string& option = "--overlay");

struct ViewerOptions {
    DrawSettings left;                   // the technique (the left half when split)
    std::optional<DrawSettings> right;   // split compare: the right half
    float divider = 0.5f;                // split position, fraction of the width from the left
    WireOverlay overlay = WireOverlay::None;
    bool reference_overlay = false;      // tint where the silhouette differs from the reference's
    ReferenceOptions reference;
    std::string screenshot;              // PNG written after --frames, and by the P key
    bool screenshot_ui = false;          // the screenshot shows the whole window (panel, background; alpha 1)
    int frames = 0;                      // > 0: draw this many frames, then exit
    float render_scale = 1.0f;           // renderer pixels per window pixel (0.25 .. 1)
    bool panel = true;
    std::string shader_dir;              // watched for hot reload; empty: none
    std::vector<std::string> drops;      // handled as if dropped on the window (tests)
};

// Runs until the window closes (or `frames` frames). `session.context` must be `window`.
// Returns the exit code.
int run_viewer(Session& session, GlfwWindow& window, const ViewerOptions& options);

} // namespace pr::view
