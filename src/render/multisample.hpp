#pragma once
// Multisampling for `render --msaa N`: N passes of the whole frame, each sampling every pixel at
// one of the standard N-sample positions within it (the image shifted the opposite way: Renderer,
// DrawSettings::pixel_offset), resolved into one image whose alpha is
// the fraction of samples covered. Passes rather than a multisampled framebuffer: the prism's
// silhouette is where its fragments discard, which a multisampled target resolves only with
// per-sample shading (the same N shadings a pixel), and the walk's per-pixel marks (the tears'
// second pass, prism.frag) would need a mark per sample.
#include "core/image.hpp"

#include <glm/vec2.hpp>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace pr {

// The standard sample positions of N-sample multisampling (Direct3D's fixed patterns, as GPUs
// use them), in pixels from the pixel's centre, x right, y up; N = 1 (the centre), 2, 4, 8 or 16.
// Throws pr::Error naming --msaa for another N, echoing `typed` where given (the flag's text, when
// it was past an int and read as its limit).
std::span<const glm::vec2> sample_offsets(int samples, const std::string& typed = {});

// Averages straight-alpha RGBA8 images of one size: alpha is the mean coverage, colour the mean
// of the covering samples' colours (weighted by their alpha), so edges blend with the background
// only through alpha.
class SampleResolve {
public:
    void add(const RgbaImage& image);
    RgbaImage result() const;

private:
    int width_ = 0, height_ = 0, count_ = 0;
    // Per pixel: r*a, g*a, b*a, a, in whole numbers (at most 16 samples of 255 * 255): 16 bytes a
    // pixel. In doubles they took 32, half a gigabyte more at 4096² (found by an exploratory
    // session); the mean is now rounded exactly (doubles put a few exact halves one level down).
    std::vector<std::uint32_t> sums_;
};

} // namespace pr
