#include "eval/metrics.hpp"

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <fmt/format.h>

namespace pr {
namespace {

std::size_t pixel_count(const RgbaImage& image)
{
    return static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
}

// An RgbaImage is a plain struct: a caller could hand over one whose buffer disagrees with its
// size, and indexing it would then read out of bounds.
void check_image(const RgbaImage& image, const char* which)
{
    if (image.width < 0 || image.height < 0 || image.pixels.size() != 4 * pixel_count(image))
        throw Error("compare", fmt::format("the {} image is {}x{} but holds {} bytes", which,
                                           image.width, image.height, image.pixels.size()));
}

void check_depth(const FrameCapture& frame, const char* which)
{
    const std::size_t n = pixel_count(frame.color);
    if (!frame.depth.empty() && frame.depth.size() != n)
        throw Error("compare", fmt::format("the {} depth has {} values for {}x{} pixels", which,
                                           frame.depth.size(), frame.color.width,
                                           frame.color.height));
}

} // namespace

CompareMetrics compare_frames(const FrameCapture& technique, const FrameCapture& reference)
{
    const RgbaImage& a = technique.color;
    const RgbaImage& b = reference.color;
    check_image(a, "technique");
    check_image(b, "reference");
    if (a.width != b.width || a.height != b.height)
        throw Error("compare",
                    fmt::format("the technique image is {}x{} but the reference is {}x{}",
                                a.width, a.height, b.width, b.height));
    check_depth(technique, "technique");
    check_depth(reference, "reference");
    const bool have_depth = !technique.depth.empty() && !reference.depth.empty();

    CompareMetrics m;
    double squared_error = 0.0; // sum over RGB of both-covered pixels; exact in double up to 2^53
    double depth_sum = 0.0;
    double depth_max = 0.0;
    std::vector<double> depth_errors; // for the median
    for (int y = 0; y < a.height; ++y) {
        for (int x = 0; x < a.width; ++x) {
            const std::size_t i = static_cast<std::size_t>(y) * a.width + x;
            const std::uint8_t* pa = &a.pixels[4 * i];
            const std::uint8_t* pb = &b.pixels[4 * i];
            const bool in_a = covers(pa[3]);
            const bool in_b = covers(pb[3]);
            if (in_a && !in_b) ++m.only_in_technique;
            if (in_b && !in_a) ++m.only_in_reference;
            if (!(in_a && in_b)) continue;
            ++m.both;
            for (int c = 0; c < 3; ++c) {
                const double d = double(pa[c]) - double(pb[c]);
                squared_error += d * d;
            }
            if (have_depth) {
                const auto fx = static_cast<float>(x);
                const auto fy = static_cast<float>(y);
                const double da = depth_to_distance(technique.camera, a.width, a.height, fx, fy,
                                                    technique.depth[i]);
                const double db = depth_to_distance(reference.camera, b.width, b.height, fx, fy,
                                                    reference.depth[i]);
                const double e = std::abs(da - db);
                depth_sum += e;
                depth_errors.push_back(e);
                depth_max = std::max(depth_max, e);
            }
        }
    }

    m.silhouette_wrong_px = m.only_in_technique + m.only_in_reference;
    const std::size_t united = m.both + m.silhouette_wrong_px;
    m.iou = united == 0 ? 1.0 : double(m.both) / double(united);
    if (m.both > 0 && have_depth) {
        m.depth_error_mean = depth_sum / double(m.both);
        m.depth_error_max = depth_max;
        m.depth_error_median = median(std::move(depth_errors));
    }
    if (m.both > 0 && squared_error > 0.0) {
        const double mse = squared_error / (3.0 * double(m.both));
        m.psnr = 10.0 * std::log10(255.0 * 255.0 / mse);
    }
    m.identical = m.silhouette_wrong_px == 0 && squared_error == 0.0;
    return m;
}

std::string iou_text(double iou)
{
    return bounded_text(iou, 4, 0.0, 1.0);
}

} // namespace pr
