#pragma once
// What the viewer shows: the renderer's image(s) copied into its own RGBA8 target (one
// technique, or the two halves of the split view), then drawn to the window over a background
// with the divider and the reference's silhouette difference tinted on top. The target keeps
// alpha = coverage, so a screenshot of it is a rendered PNG in the contract's sense.
#include "core/image.hpp"
#include "gl/objects.hpp"

namespace pr::view {

class Compositor {
public:
    Compositor();
    // From the embedded shaders, whatever the override folder holds (the viewer's start, where
    // the folder's compositor does not build: a later reload takes the folder's again).
    struct EmbeddedShaders {};
    explicit Compositor(EmbeddedShaders);
    void resize(int width, int height); // framebuffer pixels; clears both targets
    int width() const { return width_; }
    int height() const { return height_; }

    // Copies columns [x0, x1) of `source_fbo`'s colour (src_w x src_h pixels) into the matching
    // columns of the view image, scaled (nearest) when the sizes differ (render scale < 1): the
    // whole image's scale, whichever columns are copied.
    void copy_view(GLuint source_fbo, int x0, int x1, int src_w, int src_h);
    // The first view column that shows renderer column `x` or one right of it (`width()` past
    // the last), for a renderer `src_w` wide: where the halves of the split view meet.
    int view_column(int x, int src_w) const;
    // Copies all of `source_fbo`'s colour into the reference image (for the difference tint),
    // scaled as the view is.
    void copy_reference(GLuint source_fbo, int src_w, int src_h);
    void clear_view();

    struct Present {
        float divider_px = -1.0f;  // the divider line's centre, pixels from the left; < 0: none
        float line_width = 1.0f;   // divider, pixels
        bool tint_difference = false; // reference covers, view does not: cyan; the reverse: magenta
    };
    // Draws to the default framebuffer (the window), `width` x `height` pixels.
    void present(const Present& p);

    RgbaImage read_view() const; // RGBA8, alpha = coverage, bottom row first
    // Builds the program again from its sources (the viewer's shader reload); on a compile or
    // link error throws pr::Error and keeps the program it had.
    void reload_program();

private:
    int width_ = 0;
    int height_ = 0;
    gl::Texture view_tex_, ref_tex_;
    gl::Framebuffer view_fbo_, ref_fbo_;
    gl::Program program_;
    gl::VertexArray vao_;
};

} // namespace pr::view
