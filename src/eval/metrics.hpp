#pragma once
// Image comparison metrics for `compare` (contract, "Metrics and JSON"): silhouette IoU and
// xor count, depth error along the eye ray, PSNR. CPU only: the frames come in already read back,
// so this file needs no GL and unit tests can exercise it directly.
#include "core/camera.hpp"
#include "core/image.hpp"

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace pr {

// Coverage (contract): alpha >= 0.5. In 8 bits that is alpha >= 128 (128/255 = 0.502 is the first
// value at or above one half), shared by the metrics and the silhouette-difference tile.
inline constexpr std::uint8_t kCoverageAlpha = 128;
inline bool covers(std::uint8_t alpha) { return alpha >= kCoverageAlpha; }

// One rendered frame as read back from the GPU.
struct FrameCapture {
    RgbaImage color;          // straight alpha, bottom row first
    std::vector<float> depth; // window depth 0..1 (1 at the near plane, Camera::projection), width*height,
                              // bottom row first, 0 = nothing;
                              // empty when no depth was captured (the depth error is then absent)
    Camera camera;            // the camera the frame was drawn with (depth -> distance)
};

struct CompareMetrics {
    double iou = 1.0;                      // |A n B| / |A u B|, 1 when the union is empty
    std::size_t silhouette_wrong_px = 0;   // |A xor B|
    std::size_t only_in_technique = 0;     // |A \ B|
    std::size_t only_in_reference = 0;     // |B \ A|
    std::size_t both = 0;                  // |A n B|
    // Distance from the eye along each pixel's ray, |technique - reference|, scene units, over the
    // pixels both cover. Absent when no pixel is covered by both or a capture has no depth.
    std::optional<double> depth_error_mean;
    std::optional<double> depth_error_max;
    // Median of the same errors: robust to the few silhouette pixels where both cover but see
    // different surfaces (a bump's edge in one, the body behind it in the other).
    std::optional<double> depth_error_median;
    // 10 log10(255^2 / MSE) over the RGB channels of the pixels both cover. Absent when the MSE is
    // 0 (nothing to measure a ratio against) or no pixel is covered by both.
    std::optional<double> psnr;
    // The masks are equal and so is the RGB of every covered pixel: what the contract reports as
    // `"identical": true` (psnr is then absent too).
    bool identical = false;
};

// A is the technique's coverage, B the reference's. Both captures must have the same size (and
// depth, when present, width*height values); anything else throws pr::Error("compare", ...).
// Each capture's depth is turned into distance with its own camera; `compare` draws both with
// one camera, so this only matters to callers that do not.
CompareMetrics compare_frames(const FrameCapture& technique, const FrameCapture& reference);

// An IoU as compare's table and grid show it: 4 digits, more (up to 9) where 4 would round an
// IoU under 1 up to "1.0000" (a prism with 2 wrong pixels at 512² read as perfect; found by an
// exploratory session, thirty-third), or one over 0 down to "0.0000". Those are exact.
std::string iou_text(double iou);

} // namespace pr
