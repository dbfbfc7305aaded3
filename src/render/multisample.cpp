#include "render/multisample.hpp"

#include "core/error.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pr {

namespace {

// Direct3D's standard patterns, in sixteenths of a pixel (y down there: turned for y up here).
constexpr std::array<glm::vec2, 1> kOne{{{0, 0}}};
constexpr std::array<glm::vec2, 2> kTwo{{{4, 4}, {-4, -4}}};
constexpr std::array<glm::vec2, 4> kFour{{{-2, -6}, {6, -2}, {-6, 2}, {2, 6}}};
constexpr std::array<glm::vec2, 8> kEight{{{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}}};
constexpr std::array<glm::vec2, 16> kSixteen{{{1, 1}, {-1, -3}, {-3, 2}, {4, -1}, {-5, -2}, {2, 5}, {5, 3}, {3, -5},
                                               {-2, 6}, {0, -7}, {-4, -6}, {-6, 4}, {-8, 0}, {7, -4}, {6, 7}, {-7, -8}}};

template <std::size_t N>
std::span<const glm::vec2> in_pixels(const std::array<glm::vec2, N>& sixteenths)
{
    static const std::array<glm::vec2, N> pixels = [&] {
        std::array<glm::vec2, N> p{};
        for (std::size_t i = 0; i < N; ++i) p[i] = glm::vec2(sixteenths[i].x, -sixteenths[i].y) / 16.0f;
        return p;
    }();
    return pixels;
}

} // namespace

std::span<const glm::vec2> sample_offsets(int samples, const std::string& typed)
{
    switch (samples) {
    case 1: return in_pixels(kOne);
    case 2: return in_pixels(kTwo);
    case 4: return in_pixels(kFour);
    case 8: return in_pixels(kEight);
    case 16: return in_pixels(kSixteen);
    default: throw Error("--msaa", "must be 1, 2, 4, 8 or 16, got " + (typed.empty() ? std::to_string(samples) : typed));
    }
}

void SampleResolve::add(const RgbaImage& image)
{
    if (count_ == 0) {
        width_ = image.width;
        height_ = image.height;
        sums_.assign(std::size_t(width_) * std::size_t(height_) * 4, 0u);
    }
    const std::size_t n = std::size_t(width_) * std::size_t(height_);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t a = image.pixels[4 * i + 3];
        for (int c = 0; c < 3; ++c) sums_[4 * i + c] += a * image.pixels[4 * i + c];
        sums_[4 * i + 3] += a;
    }
    ++count_;
}

RgbaImage SampleResolve::result() const
{
    RgbaImage out;
    out.width = width_;
    out.height = height_;
    out.pixels.assign(std::size_t(width_) * std::size_t(height_) * 4, 0);
    // Rounded to nearest, halves up: (2 x + d) / 2d.
    const auto rounded = [](std::uint64_t x, std::uint64_t d) { return std::uint8_t(std::min<std::uint64_t>((2 * x + d) / (2 * d), 255)); };
    for (std::size_t i = 0; i < out.pixels.size() / 4; ++i) {
        const std::uint32_t a = sums_[4 * i + 3];
        if (a == 0) continue;
        for (int c = 0; c < 3; ++c) out.pixels[4 * i + c] = rounded(sums_[4 * i + c], a);
        out.pixels[4 * i + 3] = rounded(a, std::uint64_t(count_));
    }
    return out;
}

} // namespace pr
