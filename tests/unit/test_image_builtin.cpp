// Built-in procedural maps: sizes, range, tiling, determinism, colours and errors.
#include "core/error.hpp"
#include "core/image.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

namespace {

std::string problem_of(const std::string& spec, bool colour = false, const pr::ImageLimits& limits = {})
{
    try {
        if (colour)
            pr::load_color(spec, limits);
        else
            pr::load_height(spec, limits);
    } catch (const pr::Error& e) {
        EXPECT_EQ(e.subject(), spec);
        return e.problem();
    }
    ADD_FAILURE() << spec << ": no error";
    return {};
}

// Height names with the const:V placeholder given a value.
std::vector<std::string> height_specs(const std::string& suffix)
{
    std::vector<std::string> specs;
    for (std::string n : pr::builtin_height_names()) {
        if (n == "const:V") n = "const:0.5";
        specs.push_back("builtin:" + n + suffix);
    }
    return specs;
}

} // namespace

TEST(BuiltinHeight, NamesIncludeTheDocumentedOnes)
{
    const auto names = pr::builtin_height_names();
    for (const char* n : {"bumps", "bricks", "noise", "pyramids", "boxes", "const:V"})
        EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
    const auto colours = pr::builtin_color_names();
    for (const char* n : {"checker", "bricks", "uv", "bumps", "noise"})
        EXPECT_NE(std::find(colours.begin(), colours.end(), n), colours.end()) << n;
}

TEST(BuiltinHeight, DefaultSizeAndSuffix)
{
    const pr::HeightField h = pr::load_height("builtin:bumps");
    EXPECT_EQ(h.width, 512);
    EXPECT_EQ(h.height, 512);
    EXPECT_EQ(h.name, "builtin:bumps");
    EXPECT_EQ(h.texels.size(), 512u * 512u);
    const pr::HeightField s = pr::load_height("builtin:noise@256");
    EXPECT_EQ(s.width, 256);
    EXPECT_EQ(s.height, 256);
    const pr::HeightField r = pr::load_height("builtin:bricks@64x32");
    EXPECT_EQ(r.width, 64);
    EXPECT_EQ(r.height, 32);
}

TEST(BuiltinHeight, ValuesInRangeAndNotFlat)
{
    for (const std::string& spec : height_specs("@128")) {
        const pr::HeightField h = pr::load_height(spec);
        ASSERT_EQ(h.texels.size(), 128u * 128u) << spec;
        EXPECT_GE(h.min_value(), 0.0f) << spec;
        EXPECT_LE(h.max_value(), 1.0f) << spec;
        for (float t : h.texels) ASSERT_TRUE(std::isfinite(t)) << spec;
        if (spec.find("const:") == std::string::npos) {
            EXPECT_GT(h.max_value() - h.min_value(), 0.5f) << spec;
        }
    }
    const pr::HeightField n = pr::load_height("builtin:noise@128");
    EXPECT_FLOAT_EQ(n.min_value(), 0.0f); // noise is stretched to the full range
    EXPECT_FLOAT_EQ(n.max_value(), 1.0f);
}

TEST(BuiltinHeight, Tiles)
{
    // The seam between the last and first column (row) must look like any other pair of
    // neighbours: no larger than the largest step inside, and as small on average.
    for (const std::string& spec : height_specs("@96")) {
        const pr::HeightField h = pr::load_height(spec);
        const int w = h.width, n = h.height;
        for (int axis = 0; axis < 2; ++axis) {
            const auto t = [&](int a, int b) { return axis == 0 ? h.at(a, b) : h.at(b, a); };
            const int along = axis == 0 ? w : n, across = axis == 0 ? n : w;
            double seam_max = 0, seam_sum = 0, inner_max = 0, inner_sum = 0;
            for (int b = 0; b < across; ++b) {
                const double s = std::abs(t(along - 1, b) - t(0, b));
                seam_max = std::max(seam_max, s);
                seam_sum += s;
                for (int a = 0; a + 1 < along; ++a) {
                    const double d = std::abs(t(a + 1, b) - t(a, b));
                    inner_max = std::max(inner_max, d);
                    inner_sum += d;
                }
            }
            const double seam_mean = seam_sum / across;
            const double inner_mean = inner_sum / (across * (along - 1));
            EXPECT_LE(seam_max, inner_max + 1e-6) << spec << " axis " << axis;
            EXPECT_LE(seam_mean, 3.0 * inner_mean + 1e-6) << spec << " axis " << axis;
        }
    }
}

TEST(BuiltinHeight, Deterministic)
{
    for (const std::string& spec : height_specs("@64"))
        EXPECT_EQ(pr::load_height(spec).texels, pr::load_height(spec).texels) << spec;
}

TEST(BuiltinHeight, SixteenBitQuantized)
{
    // Heights are exact 16-bit values, so an R16 texture holds precisely what the CPU samples.
    const pr::HeightField h = pr::load_height("builtin:noise@64");
    EXPECT_EQ(h.bits, 16);
    for (float t : h.texels) ASSERT_FLOAT_EQ(std::round(t * 65535.0f) / 65535.0f, t);
}

TEST(BuiltinHeight, SizeIndependentLayout)
{
    // Patterns live in UV space: a bump centre (cell 0 of an 8x8 grid) is high at any size.
    for (int size : {64, 100, 512}) {
        const pr::HeightField h = pr::load_height("builtin:bumps@" + std::to_string(size));
        EXPECT_GT(h.sample({1.0f / 16, 1.0f / 16}), 0.85f) << size;
        EXPECT_LT(h.sample({0.0f, 0.0f}), 0.05f) << size;
    }
}

TEST(BuiltinHeight, Constants)
{
    const pr::HeightField one = pr::load_height("builtin:const:1@16");
    EXPECT_EQ(one.width, 16);
    for (float t : one.texels) EXPECT_EQ(t, 1.0f);
    const pr::HeightField zero = pr::load_height("builtin:const:0");
    EXPECT_EQ(zero.width, 512);
    EXPECT_EQ(zero.max_value(), 0.0f);
    const pr::HeightField half = pr::load_height("builtin:const:0.5@8");
    EXPECT_NEAR(half.min_value(), 0.5f, 1e-4);
    EXPECT_NEAR(half.max_value(), 0.5f, 1e-4);
    EXPECT_NEAR(pr::load_height("builtin:const:0.25@4").sample({0.3f, 0.9f}), 0.25f, 1e-4);
}

TEST(BuiltinHeight, Errors)
{
    const std::string unknown = problem_of("builtin:nope");
    for (const std::string& n : pr::builtin_height_names())
        EXPECT_NE(unknown.find(n), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("nope"), std::string::npos) << unknown;
    EXPECT_FALSE(problem_of("builtin:").empty());
    for (const char* bad : {"builtin:const:2", "builtin:const:-0.1", "builtin:const:x",
                            "builtin:const:", "builtin:const:nan"})
        EXPECT_NE(problem_of(bad).find("[0,1]"), std::string::npos) << bad;
    for (const char* bad : {"builtin:bumps@0", "builtin:bumps@abc", "builtin:bumps@100000",
                            "builtin:bumps@", "builtin:bumps@64x", "builtin:bumps@-4"})
        EXPECT_NE(problem_of(bad).find("size"), std::string::npos) << bad;
    pr::ImageLimits small;
    small.max_pixels = 1000;
    EXPECT_THROW(pr::load_height("builtin:bumps@64", small), pr::Error);
}

// --max-image-size applies to a built-in map named without @N (its default size, 512) as to one
// with @N; the message says which (the default size, or the size after '@').
TEST(BuiltinHeight, DefaultSizeObeysTheLimits)
{
    pr::ImageLimits small;
    small.max_dimension = 16;
    small.max_pixels = 16 * 16;
    const std::string after_at = "size after '@' must be N or WxH with each side between 1 and 16";
    const std::string by_default = "its default size, 512x512, is over the limit of 16 per side";
    for (bool colour : {false, true}) {
        for (const char* spec : {"builtin:bumps", "builtin:noise", "builtin:const:0.5"})
            EXPECT_NE(problem_of(spec, colour, small).find(by_default), std::string::npos) << spec;
        EXPECT_NE(problem_of("builtin:bumps@64", colour, small).find(after_at), std::string::npos);
    }
    EXPECT_NE(problem_of("builtin:checker", true, small).find(by_default), std::string::npos);
    EXPECT_EQ(pr::load_height("builtin:bumps@16", small).width, 16);
    pr::ImageLimits fits;
    fits.max_dimension = 512;
    fits.max_pixels = 512 * 512;
    EXPECT_EQ(pr::load_height("builtin:bumps", fits).width, 512);
    fits.max_pixels = 512 * 512 - 1; // the area limit too
    EXPECT_NE(problem_of("builtin:bumps", false, fits).find("more than the limit"), std::string::npos);
}

// The patterns laid out on an 8x8 grid of cells per UV unit came out constant where every texel
// centre sits at the same place in its cell (bumps@8, @16: one or two texels per cell): those
// sizes take fewer, larger cells (4, 2 or 1 per UV unit), the most that show the pattern. Sizes
// that showed it keep their 8x8 layout bit for bit (SizeIndependentLayout, and every size the
// tests and docs use); sizes too small for any layout are refused.
TEST(BuiltinHeight, SmallSizesShowTheirPattern)
{
    for (const char* name : {"bumps", "pyramids", "boxes"})
        for (const char* size : {"3", "4", "5", "6", "8", "12", "16", "24", "32", "2x64", "64x2", "1x40", "3x2"}) {
            const std::string spec = std::string("builtin:") + name + "@" + size;
            const pr::HeightField h = pr::load_height(spec);
            EXPECT_GT(h.max_value() - h.min_value(), 0.15f) << spec; // (pyramids@3x2: one pyramid, 0.167)
            const pr::RgbaImage c = pr::load_color(spec); // the tint follows the heights
            bool varies = false;
            for (int y = 0; y < c.height; ++y)
                for (int x = 0; x < c.width; ++x) varies = varies || c.at(x, y) != c.at(0, 0);
            EXPECT_TRUE(varies) << spec;
        }
    // A cell has 3 texels or more along the longer side: boxes give every cell a height of its
    // own, so with a texel a cell boxes@8 were 64 random heights (found by a review, thirty-third).
    // A box shows as texels of one height: far fewer heights than texels.
    for (const char* spec : {"builtin:boxes@4", "builtin:boxes@8", "builtin:boxes@16", "builtin:boxes@3x2"}) {
        const pr::HeightField h = pr::load_height(spec);
        std::vector<float> heights = h.texels;
        std::sort(heights.begin(), heights.end());
        const auto distinct = std::unique(heights.begin(), heights.end()) - heights.begin();
        EXPECT_LE(distinct * 3, std::ptrdiff_t(h.texels.size())) << spec;
    }
    // With 4 texels per cell, as at 32: bumps@16 and @8 are corners of bumps@32, bit for bit.
    for (const char* name : {"bumps", "pyramids"}) {
        const pr::HeightField big = pr::load_height(std::string("builtin:") + name + "@32");
        for (int size : {8, 16}) {
            const pr::HeightField h = pr::load_height(std::string("builtin:") + name + "@" + std::to_string(size));
            for (int y = 0; y < size; ++y)
                for (int x = 0; x < size; ++x) ASSERT_EQ(h.at(x, y), big.at(x, y)) << name << "@" << size;
        }
    }
    // Bricks and noise, which have no cells to enlarge, came out constant at these sizes (all
    // mortar, or noise normalized to 0.5) and were accepted until the sixteenth session.
    for (const char* spec : {"builtin:bumps@2", "builtin:pyramids@1", "builtin:bumps@2x1", "builtin:boxes@2",
                             "builtin:pyramids@2x1", "builtin:bricks@2",
                             "builtin:bricks@1", "builtin:noise@1", "builtin:noise@2"}) {
        EXPECT_NE(problem_of(spec).find("too small for its pattern"), std::string::npos) << spec;
        EXPECT_NE(problem_of(spec, true).find("too small for its pattern"), std::string::npos) << spec;
    }
    // The colour maps of their own too, where every texel centre takes one colour (the checker's
    // one square, the bricks' mortar: accepted until the fifty-third session, found by an
    // exploratory session); where two colours show, they are kept.
    for (const char* spec : {"builtin:checker@4", "builtin:checker@2x1", "builtin:bricks@4", "builtin:uv@1"})
        EXPECT_NE(problem_of(spec, true).find("too small for its pattern: every texel centre takes the same colour"),
                  std::string::npos)
            << spec;
    for (const char* spec : {"builtin:checker@8", "builtin:bricks@3", "builtin:uv@2"})
        EXPECT_EQ(pr::load_color(spec).width, spec[std::strlen(spec) - 1] - '0') << spec;
    // A constant map has no pattern to show: any size.
    EXPECT_EQ(pr::load_height("builtin:const:0.5@1").width, 1);
}

TEST(BuiltinColor, CheckerAndUv)
{
    const pr::RgbaImage c = pr::load_color("builtin:checker@64");
    ASSERT_EQ(c.width, 64);
    ASSERT_EQ(c.pixels.size(), 64u * 64u * 4u);
    EXPECT_NE(c.at(0, 0), c.at(8, 0)); // 8 tiles per UV unit: 8 texels each at 64
    EXPECT_EQ(c.at(0, 0), c.at(8, 8));
    EXPECT_EQ(c.at(0, 0), c.at(7, 7));
    EXPECT_EQ(c.at(0, 0).a, 255);

    const pr::RgbaImage uv = pr::load_color("builtin:uv@256");
    EXPECT_EQ(uv.at(0, 0), glm::u8vec4(0, 0, 0, 255));
    EXPECT_EQ(uv.at(255, 0).r, 255);
    EXPECT_EQ(uv.at(0, 255).g, 255); // row 0 is v = 0: green grows upwards
    EXPECT_EQ(uv.at(128, 64).r, 128);
    EXPECT_EQ(uv.at(128, 64).g, 64);
}

TEST(BuiltinColor, BricksMatchTheHeightLayout)
{
    const pr::HeightField h = pr::load_height("builtin:bricks@128");
    const pr::RgbaImage c = pr::load_color("builtin:bricks@128");
    int mortar = 0, brick = 0;
    for (int y = 0; y < 128; ++y)
        for (int x = 0; x < 128; ++x) {
            const glm::ivec4 p = c.at(x, y);
            const bool grey = std::abs(p.r - p.g) < 16 && std::abs(p.g - p.b) < 16;
            const bool red = p.r > p.g + 40 && p.r > p.b + 40;
            EXPECT_EQ(p.a, 255);
            if (h.at(x, y) < 0.15f) {
                EXPECT_TRUE(grey) << x << "," << y; // low: mortar
                ++mortar;
            } else if (h.at(x, y) > 0.6f) {
                EXPECT_TRUE(red) << x << "," << y; // high: brick face
                ++brick;
            }
        }
    EXPECT_GT(mortar, 128 * 128 / 20);
    EXPECT_GT(brick, 128 * 128 / 2);
}

TEST(BuiltinColor, HeightNamesGetATint)
{
    for (std::string spec : height_specs("@32")) {
        const pr::RgbaImage c = pr::load_color(spec);
        EXPECT_EQ(c.width, 32) << spec;
        EXPECT_EQ(c.pixels.size(), 32u * 32u * 4u) << spec;
        EXPECT_EQ(c.at(5, 7).a, 255) << spec;
    }
    // Tinted: brighter where higher.
    const pr::HeightField h = pr::load_height("builtin:pyramids@64");
    const pr::RgbaImage c = pr::load_color("builtin:pyramids@64");
    EXPECT_GT(h.at(4, 4), h.at(0, 0));
    EXPECT_GT(c.at(4, 4).r, c.at(0, 0).r);
    EXPECT_EQ(pr::load_color("builtin:noise@32").pixels, pr::load_color("builtin:noise@32").pixels);

    const std::string unknown = problem_of("builtin:nope", true);
    for (const char* n : {"checker", "uv", "bricks", "bumps"})
        EXPECT_NE(unknown.find(n), std::string::npos) << unknown;
}
