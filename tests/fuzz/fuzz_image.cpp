// libFuzzer harness: bytes -> an image file -> pr::load_height and pr::load_color (our header
// sniffing and limits, then stb_image, compiled into pr_core and so instrumented too).
// pr::Error is the expected outcome for bad input; anything else is a finding.
#include "core/error.hpp"
#include "core/image.hpp"
#include "fuzz_common.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
    const auto path = pr::fuzz::scratch_file(".img");
    pr::fuzz::write_bytes(path, data, size);
    // Smaller limits than the defaults (16384 per side, 64 Mpixel) keep each decode within
    // -rss_limit_mb; the checks are the same code.
    pr::ImageLimits limits;
    limits.max_dimension = 4096;
    limits.max_pixels = 1 << 22;
    try {
        const pr::HeightField h = pr::load_height(path.string(), limits);
        if (h.width < 1 || h.height < 1 || h.texels.size() != std::size_t(h.width) * h.height) {
            std::fprintf(stderr, "inconsistent height field %dx%d\n", h.width, h.height);
            std::abort();
        }
        for (float t : h.texels)
            if (!(t >= 0.0f && t <= 1.0f)) {
                std::fprintf(stderr, "height %g outside [0,1]\n", double(t));
                std::abort();
            }
    } catch (const pr::Error&) {
    }
    try {
        const pr::RgbaImage c = pr::load_color(path.string(), limits);
        if (c.width < 1 || c.height < 1 || c.pixels.size() != std::size_t(c.width) * c.height * 4) {
            std::fprintf(stderr, "inconsistent colour image %dx%d\n", c.width, c.height);
            std::abort();
        }
    } catch (const pr::Error&) {
    }
    return 0;
}
