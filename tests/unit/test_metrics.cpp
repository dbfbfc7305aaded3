// Compare metrics (eval/metrics): IoU and xor count, PSNR over both-covered pixels, depth error
// along the eye ray. Images are built here pixel by pixel, so each expected value can be worked
// out by hand.
#include "core/camera.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "eval/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

using pr::FrameCapture;

// A w x h frame of one colour, uncovered (alpha 0) everywhere, depth 1 (nothing drawn).
FrameCapture blank(int w, int h, glm::u8vec4 colour = {100, 150, 200, 0})
{
    FrameCapture f;
    f.color.width = w;
    f.color.height = h;
    f.color.pixels.resize(4 * std::size_t(w) * h);
    for (std::size_t i = 0; i < f.color.pixels.size(); i += 4)
        for (int c = 0; c < 4; ++c) f.color.pixels[i + c] = colour[c];
    f.depth.assign(std::size_t(w) * h, 0.0f); // the far plane (reversed depth)
    f.camera.near_plane = 1.0f;
    f.camera.far_plane = 10.0f;
    return f;
}

std::uint8_t* px(FrameCapture& f, int x, int y)
{
    return &f.color.pixels[4 * (std::size_t(y) * f.color.width + x)];
}

// Covers the rectangle [x0, x1) x [y0, y1) with alpha 255 and the given window depth.
void cover(FrameCapture& f, int x0, int y0, int x1, int y1, float depth = 0.5f)
{
    for (int y = y0; y < y1; ++y) {
        for (int x = x0; x < x1; ++x) {
            px(f, x, y)[3] = 255;
            f.depth[std::size_t(y) * f.color.width + x] = depth;
        }
    }
}

TEST(Metrics, IdenticalMasksHaveIouOneAndIdenticalImagesHaveNoPsnr)
{
    FrameCapture a = blank(8, 6);
    cover(a, 1, 1, 5, 4);
    const FrameCapture b = a;
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_DOUBLE_EQ(m.iou, 1.0);
    EXPECT_EQ(m.silhouette_wrong_px, 0u);
    EXPECT_EQ(m.both, 12u);
    EXPECT_FALSE(m.psnr.has_value());
    EXPECT_TRUE(m.identical);
    ASSERT_TRUE(m.depth_error_mean.has_value());
    EXPECT_DOUBLE_EQ(*m.depth_error_mean, 0.0);
    EXPECT_DOUBLE_EQ(*m.depth_error_max, 0.0);
}

TEST(Metrics, DisjointMasksHaveIouZeroAndNoSharedMeasures)
{
    FrameCapture a = blank(8, 4);
    FrameCapture b = blank(8, 4);
    cover(a, 0, 0, 3, 4);
    cover(b, 5, 0, 8, 4);
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_DOUBLE_EQ(m.iou, 0.0);
    EXPECT_EQ(m.silhouette_wrong_px, 24u);
    EXPECT_EQ(m.only_in_technique, 12u);
    EXPECT_EQ(m.only_in_reference, 12u);
    EXPECT_EQ(m.both, 0u);
    // Nothing covered by both: no depth error and no PSNR, and the masks differ.
    EXPECT_FALSE(m.depth_error_mean.has_value());
    EXPECT_FALSE(m.depth_error_max.has_value());
    EXPECT_FALSE(m.psnr.has_value());
    EXPECT_FALSE(m.identical);
}

TEST(Metrics, EmptyUnionHasIouOne)
{
    const pr::CompareMetrics m = pr::compare_frames(blank(5, 5), blank(5, 5));
    EXPECT_DOUBLE_EQ(m.iou, 1.0);
    EXPECT_EQ(m.silhouette_wrong_px, 0u);
    EXPECT_TRUE(m.identical);
    EXPECT_FALSE(m.psnr.has_value());
    EXPECT_FALSE(m.depth_error_mean.has_value());
}

TEST(Metrics, OverlappingRectanglesGiveTheExactIouAndXor)
{
    // A = [0,6)x[0,4) (24 px), B = [3,9)x[2,6) (24 px); overlap [3,6)x[2,4) = 6 px.
    // Union 42, IoU 6/42 = 1/7, xor 36.
    FrameCapture a = blank(10, 8);
    FrameCapture b = blank(10, 8);
    cover(a, 0, 0, 6, 4);
    cover(b, 3, 2, 9, 6);
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_EQ(m.both, 6u);
    EXPECT_EQ(m.only_in_technique, 18u);
    EXPECT_EQ(m.only_in_reference, 18u);
    EXPECT_EQ(m.silhouette_wrong_px, 36u);
    EXPECT_DOUBLE_EQ(m.iou, 1.0 / 7.0);
}

TEST(Metrics, CoverageStartsAtAlphaOneHalf)
{
    FrameCapture a = blank(2, 1);
    FrameCapture b = blank(2, 1);
    px(a, 0, 0)[3] = 128; // 0.502: covered
    px(b, 0, 0)[3] = 255;
    px(a, 1, 0)[3] = 127; // 0.498: not covered
    px(b, 1, 0)[3] = 255;
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_EQ(m.both, 1u);
    EXPECT_EQ(m.only_in_reference, 1u);
    EXPECT_EQ(m.only_in_technique, 0u);
}

TEST(Metrics, PsnrOfAConstantOffsetInOneChannel)
{
    // Red off by 10 on every both-covered pixel: MSE over RGB = 10^2 / 3, so
    // PSNR = 10 log10(255^2 * 3 / 100).
    FrameCapture a = blank(6, 5);
    FrameCapture b = blank(6, 5);
    cover(a, 0, 0, 4, 5);
    cover(b, 0, 0, 4, 5);
    for (int y = 0; y < 5; ++y)
        for (int x = 0; x < 4; ++x) px(a, x, y)[0] = static_cast<std::uint8_t>(px(b, x, y)[0] + 10);
    // A pixel only one side covers, with a wildly different colour, must not count.
    cover(a, 5, 0, 6, 1);
    px(a, 5, 0)[1] = 0;
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    ASSERT_TRUE(m.psnr.has_value());
    EXPECT_NEAR(*m.psnr, 10.0 * std::log10(255.0 * 255.0 * 3.0 / 100.0), 1e-9);
    EXPECT_NEAR(*m.psnr, 32.90202, 1e-5); // the same, as a number
    EXPECT_FALSE(m.identical);
}

TEST(Metrics, DifferentImagesHaveAFinitePsnr)
{
    FrameCapture a = blank(4, 4);
    cover(a, 0, 0, 4, 4);
    FrameCapture b = a;
    px(b, 2, 3)[2] = 0; // one channel of one pixel, off by 200
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    ASSERT_TRUE(m.psnr.has_value());
    EXPECT_TRUE(std::isfinite(*m.psnr));
    EXPECT_GT(*m.psnr, 0.0);
    EXPECT_FALSE(m.identical);
}

TEST(Metrics, EqualColoursButDifferentMasksAreNotIdentical)
{
    FrameCapture a = blank(4, 4);
    FrameCapture b = blank(4, 4);
    cover(a, 0, 0, 4, 4);
    cover(b, 0, 0, 4, 3);
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_FALSE(m.psnr.has_value()); // MSE 0 over the 12 shared pixels
    EXPECT_FALSE(m.identical);
}

TEST(Metrics, AlphaAndUncoveredColourDoNotAffectPsnr)
{
    FrameCapture a = blank(3, 3, {10, 20, 30, 0});
    FrameCapture b = blank(3, 3, {200, 100, 0, 0});
    cover(a, 0, 0, 1, 1);
    cover(b, 0, 0, 1, 1);
    for (int c = 0; c < 3; ++c) px(b, 0, 0)[c] = px(a, 0, 0)[c];
    px(b, 0, 0)[3] = 200; // covered on both sides, other alpha: colour still equal
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_TRUE(m.identical);
    EXPECT_FALSE(m.psnr.has_value());
}

// Eye distance of window depth d on the optical axis: -z_eye from the inverse of the reversed
// depth mapping (Camera::projection: d = n (f - D) / ((f - n) D), 1 at D = n, 0 at D = f),
// D = nf / (n + d (f - n)).
double axis_distance(double n, double f, double d)
{
    return n * f / (n + d * (f - n));
}

TEST(Metrics, DepthErrorOnTheAxisMatchesTheClosedForm)
{
    // A 1x1 image: its pixel centre is the centre of the view, so its ray is the optical axis
    // and the distance is the linear eye depth.
    FrameCapture a = blank(1, 1);
    FrameCapture b = blank(1, 1);
    cover(a, 0, 0, 1, 1, 0.9f);
    cover(b, 0, 0, 1, 1, 0.8f);
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    const double expected = axis_distance(1.0, 10.0, 0.8) - axis_distance(1.0, 10.0, 0.9); // b lies behind a
    ASSERT_TRUE(m.depth_error_mean.has_value());
    EXPECT_GT(expected, 0.0);
    EXPECT_NEAR(*m.depth_error_mean, expected, 1e-4 * expected);
    EXPECT_NEAR(*m.depth_error_max, expected, 1e-4 * expected);
}

TEST(Metrics, DepthErrorOfAConstantWindowOffsetIsMeasuredAlongEachRay)
{
    const int w = 7;
    const int h = 5;
    FrameCapture a = blank(w, h);
    FrameCapture b = blank(w, h);
    a.camera = pr::Camera{};
    a.camera.near_plane = 0.5f;
    a.camera.far_plane = 20.0f;
    b.camera = a.camera;
    cover(a, 0, 0, w, h, 0.95f);
    cover(b, 0, 0, w, h, 0.90f);
    double sum = 0.0;
    double max = 0.0;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const double e = pr::depth_to_distance(a.camera, w, h, float(x), float(y), 0.90f) -
                             pr::depth_to_distance(a.camera, w, h, float(x), float(y), 0.95f);
            sum += e;
            max = std::max(max, e);
        }
    }
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    ASSERT_TRUE(m.depth_error_mean.has_value());
    EXPECT_NEAR(*m.depth_error_mean, sum / (w * h), 1e-9);
    EXPECT_NEAR(*m.depth_error_max, max, 1e-9);
    // Off-axis rays are longer than the axis for the same window depth: the corners give the max.
    const double axis = axis_distance(0.5, 20.0, 0.90) - axis_distance(0.5, 20.0, 0.95);
    EXPECT_GT(*m.depth_error_max, axis);
    EXPECT_GT(*m.depth_error_mean, 0.0);
}

// The median of an even count is the mean of the two middle errors (it was the upper one; found
// by an exploratory session recomputing compare's numbers).
TEST(Metrics, DepthErrorMedianOfAnEvenCountIsTheMeanOfTheMiddleTwo)
{
    FrameCapture a = blank(4, 1);
    FrameCapture b = blank(4, 1);
    cover(a, 0, 0, 4, 1, 0.9f);
    const float behind[4] = {0.9f, 0.85f, 0.8f, 0.5f};
    for (int x = 0; x < 4; ++x) cover(b, x, 0, x + 1, 1, behind[x]);
    std::vector<double> e;
    for (int x = 0; x < 4; ++x)
        e.push_back(pr::depth_to_distance(a.camera, 4, 1, float(x), 0.0f, behind[x]) -
                    pr::depth_to_distance(a.camera, 4, 1, float(x), 0.0f, 0.9f));
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    ASSERT_TRUE(m.depth_error_median.has_value());
    EXPECT_LT(e[1], e[2]);
    EXPECT_NEAR(*m.depth_error_median, 0.5 * (e[1] + e[2]), 1e-9);
}

TEST(Metrics, DepthErrorIgnoresPixelsOnlyOneSideCovers)
{
    FrameCapture a = blank(4, 1);
    FrameCapture b = blank(4, 1);
    cover(a, 0, 0, 2, 1, 0.5f);
    cover(b, 0, 0, 1, 1, 0.5f);
    a.depth[1] = 0.1f; // covered only in the technique: no partner to compare with
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    ASSERT_TRUE(m.depth_error_max.has_value());
    EXPECT_DOUBLE_EQ(*m.depth_error_max, 0.0);
}

TEST(Metrics, MissingDepthLeavesDepthErrorAbsent)
{
    FrameCapture a = blank(2, 2);
    cover(a, 0, 0, 2, 2);
    FrameCapture b = a;
    b.depth.clear();
    const pr::CompareMetrics m = pr::compare_frames(a, b);
    EXPECT_FALSE(m.depth_error_mean.has_value());
    EXPECT_DOUBLE_EQ(m.iou, 1.0);
}

TEST(Metrics, SizeMismatchThrows)
{
    EXPECT_THROW(pr::compare_frames(blank(4, 4), blank(4, 5)), pr::Error);
    EXPECT_THROW(pr::compare_frames(blank(5, 4), blank(4, 4)), pr::Error);
    FrameCapture bad_depth = blank(4, 4);
    bad_depth.depth.resize(3);
    EXPECT_THROW(pr::compare_frames(bad_depth, blank(4, 4)), pr::Error);
    FrameCapture bad_buffer = blank(4, 4);
    bad_buffer.color.pixels.resize(10);
    EXPECT_THROW(pr::compare_frames(blank(4, 4), bad_buffer), pr::Error);
    try {
        pr::compare_frames(blank(4, 4), blank(4, 5));
    } catch (const pr::Error& e) {
        EXPECT_EQ(e.subject(), "compare");
    }
}

} // namespace

// compare's table and grid: an IoU under 1 never reads 1.0000 (2 wrong pixels at 512² did).
TEST(Metrics, IouTextNeverRoundsUpToOne)
{
    EXPECT_EQ(pr::iou_text(1.0), "1.0000");
    EXPECT_EQ(pr::iou_text(0.5), "0.5000");
    EXPECT_EQ(pr::iou_text(0.99994), "0.9999");
    EXPECT_EQ(pr::iou_text(0.99996), "0.99996");
    EXPECT_EQ(pr::iou_text(0.9999962), "0.999996");
    EXPECT_EQ(pr::iou_text(1.0 - 1.0 / 268435456.0), "0.999999996"); // one pixel of 16384²
    EXPECT_EQ(pr::iou_text(0.0), "0.0000");
    EXPECT_EQ(pr::iou_text(0.00004), "0.00004"); // not an empty intersection
    EXPECT_EQ(pr::bounded_text(99.99695, 1, 0.0, 100.0), "99.997"); // 65534 of 65536 pixels: not 100.0 %
    EXPECT_EQ(pr::bounded_text(2.3865e-05, 4, 0.0, 100.0), "0.00002");
    EXPECT_EQ(pr::bounded_text(100.0, 1, 0.0, 100.0), "100.0");
    EXPECT_EQ(pr::bounded_text(42.04, 1, 0.0, 100.0), "42.0");
}

// Reports give a float as the shortest decimal that reads back as it (render --json's camera:
// --fovy 178.9 read 178.89999389648438).
TEST(Metrics, FloatsAreReportedAsTheirShortestDecimal)
{
    EXPECT_EQ(pr::shortest_decimal(178.9f), 178.9);
    EXPECT_EQ(pr::shortest_decimal(40.0f), 40.0);
    EXPECT_EQ(pr::shortest_decimal(0.1f), 0.1);
    EXPECT_EQ(float(pr::shortest_decimal(1.0f / 3.0f)), 1.0f / 3.0f); // reads back as the same float
    EXPECT_EQ(pr::shortest_decimal(-2.5e-30f), -2.5e-30);
}
