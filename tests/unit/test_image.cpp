// Image loading, PNG output and height sampling (core/image). Test images are made here, byte by
// byte, so each test says exactly what the file holds.
// GCC 12 at -O3 reports a false -Wstringop-overflow inside std::string concatenation when an
// Error is copied out of a lambda (GCC bug 105651); nothing in this file writes out of bounds.
#pragma GCC diagnostic ignored "-Wstringop-overflow"
#include "error_of.hpp"
#include "core/error.hpp"
#include "core/image.hpp"

#include <stb_image_write.h>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <unistd.h>
#include <vector>

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

namespace {

// A folder of its own per test (ctest may run tests in parallel), removed afterwards.
class ImageFiles : public ::testing::Test {
protected:
    void SetUp() override
    {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("pr_image_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    std::string put(const std::string& name, const Bytes& bytes) const
    {
        const fs::path p = dir_ / name;
        std::ofstream out(p, std::ios::binary);
        out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
        return p.string();
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    // `bytes` written as `name` is refused as a height map and as a colour image, naming the file,
    // with a message that holds `why`.
    void refused_both_ways(const std::string& name, const Bytes& bytes, const std::string& why) const
    {
        const std::string p = put(name, bytes);
        for (const bool colour : {false, true}) {
            const pr::Error e = prtest::error_of([&] { colour ? (void)pr::load_color(p) : (void)pr::load_height(p); });
            EXPECT_EQ(e.subject(), p);
            EXPECT_NE(e.problem().find(why), std::string::npos) << name << ": " << e.problem();
        }
    }

    fs::path dir_;
};

// ---- a minimal PNG encoder: stored (uncompressed) deflate blocks, filter 0, valid CRCs ----

void put_be32(Bytes& b, std::uint32_t v)
{
    for (int s = 24; s >= 0; s -= 8) b.push_back(std::uint8_t(v >> s));
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n)
{
    std::uint32_t c = 0xFFFFFFFFU;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320U & (0U - (c & 1U)));
    }
    return c ^ 0xFFFFFFFFU;
}

void chunk(Bytes& png, const char* type, const Bytes& data)
{
    put_be32(png, std::uint32_t(data.size()));
    Bytes body(type, type + 4);
    body.insert(body.end(), data.begin(), data.end());
    png.insert(png.end(), body.begin(), body.end());
    put_be32(png, crc32(body.data(), body.size()));
}

Bytes png_header(std::uint32_t w, std::uint32_t h, int depth, int colour_type)
{
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    Bytes ihdr;
    put_be32(ihdr, w);
    put_be32(ihdr, h);
    ihdr.insert(ihdr.end(), {std::uint8_t(depth), std::uint8_t(colour_type), 0, 0, 0});
    chunk(png, "IHDR", ihdr);
    return png;
}

// `rows` are the file's rows, top first, each already packed (big-endian for 16 bit).
Bytes make_png(int w, int depth, int colour_type, const std::vector<Bytes>& rows,
               const Bytes& palette = {})
{
    Bytes png = png_header(std::uint32_t(w), std::uint32_t(rows.size()), depth, colour_type);
    if (!palette.empty()) chunk(png, "PLTE", palette);
    Bytes raw;
    for (const Bytes& r : rows) {
        raw.push_back(0); // filter: none
        raw.insert(raw.end(), r.begin(), r.end());
    }
    Bytes z = {0x78, 0x01};
    for (std::size_t off = 0; off < raw.size() || off == 0; off += 65535) {
        const std::size_t n = std::min<std::size_t>(65535, raw.size() - off);
        const bool last = off + n >= raw.size();
        z.insert(z.end(), {std::uint8_t(last), std::uint8_t(n), std::uint8_t(n >> 8),
                           std::uint8_t(~n), std::uint8_t(~n >> 8)});
        z.insert(z.end(), raw.begin() + std::ptrdiff_t(off), raw.begin() + std::ptrdiff_t(off + n));
        if (last) break;
    }
    std::uint32_t a = 1, b = 0;
    for (std::uint8_t c : raw) {
        a = (a + c) % 65521;
        b = (b + a) % 65521;
    }
    put_be32(z, (b << 16) | a);
    chunk(png, "IDAT", z);
    chunk(png, "IEND", {});
    return png;
}

Bytes be16(std::initializer_list<int> values)
{
    Bytes b;
    for (int v : values) b.insert(b.end(), {std::uint8_t(v >> 8), std::uint8_t(v)});
    return b;
}

Bytes bmp_header(std::int32_t w, std::int32_t h)
{
    Bytes b = {'B', 'M'};
    const auto le32 = [&b](std::uint32_t v) {
        for (int s = 0; s < 32; s += 8) b.push_back(std::uint8_t(v >> s));
    };
    const auto le16 = [&b](std::uint16_t v) {
        b.insert(b.end(), {std::uint8_t(v), std::uint8_t(v >> 8)});
    };
    le32(54 + 16); // file size (a few bytes of pixels follow)
    le32(0);       // reserved
    le32(54);      // pixel data offset
    le32(40);      // BITMAPINFOHEADER
    le32(std::uint32_t(w));
    le32(std::uint32_t(h));
    le16(1);  // planes
    le16(24); // bits per pixel
    for (int i = 0; i < 6; ++i) le32(0);
    b.resize(b.size() + 16, 0x80);
    return b;
}

pr::RgbaImage sample_image(int w, int h)
{
    pr::RgbaImage img;
    img.width = w;
    img.height = h;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            img.pixels.insert(img.pixels.end(),
                              {std::uint8_t(x * 37 + y * 11), std::uint8_t(y * 53 + 7),
                               std::uint8_t((x * y * 29) ^ 0x5A), std::uint8_t(255 - x * 13 - y)});
    return img;
}

using prtest::contains;
using prtest::error_of;

pr::HeightField field(int w, int h, std::vector<float> texels)
{
    pr::HeightField f;
    f.width = w;
    f.height = h;
    f.texels = std::move(texels);
    return f;
}

} // namespace

// ---- PNG output and colour loading ----

TEST_F(ImageFiles, ImagePngRoundTrip8Bit)
{
    const pr::RgbaImage img = sample_image(7, 5);
    const std::string p = path("round.png");
    pr::write_png(p, img);
    const pr::RgbaImage back = pr::read_rgba(p);
    EXPECT_EQ(back.width, 7);
    EXPECT_EQ(back.height, 5);
    EXPECT_EQ(back.pixels, img.pixels);
    EXPECT_EQ(pr::load_color(p).pixels, img.pixels);
    for (const auto& e : fs::directory_iterator(dir_)) EXPECT_EQ(e.path().filename(), "round.png");
}

TEST(ImageEncode, PngSignatureAndBadImages)
{
    const Bytes png = pr::encode_png(sample_image(3, 2));
    ASSERT_GE(png.size(), 8u);
    EXPECT_EQ(png[1], 'P');
    EXPECT_EQ(png[2], 'N');
    EXPECT_EQ(png[3], 'G');
    EXPECT_THROW(pr::encode_png(pr::RgbaImage{}), pr::Error);
    pr::RgbaImage short_data = sample_image(3, 2);
    short_data.pixels.pop_back();
    EXPECT_THROW(pr::encode_png(short_data), pr::Error);
}

TEST(ImageEncode, WritePngErrorNamesThePath)
{
    const pr::Error e =
        error_of([] { pr::write_png("/nonexistent-dir-pr/x.png", sample_image(2, 2)); });
    EXPECT_EQ(e.subject(), "/nonexistent-dir-pr/x.png");
    const pr::Error empty = error_of([] { pr::write_png("/tmp/pr-empty.png", pr::RgbaImage{}); });
    EXPECT_EQ(empty.subject(), "/tmp/pr-empty.png");
    EXPECT_FALSE(fs::exists("/tmp/pr-empty.png"));
}

TEST_F(ImageFiles, ImageRowsFlipOnLoad)
{
    // File rows, top first: (10, 20) over (30, 40). Row 0 in memory is the bottom (v = 0).
    const std::string p = put("flip.png", make_png(2, 8, 0, {{10, 20}, {30, 40}}));
    const pr::HeightField h = pr::load_height(p);
    ASSERT_EQ(h.width, 2);
    ASSERT_EQ(h.height, 2);
    EXPECT_EQ(h.bits, 8);
    EXPECT_EQ(h.name, p);
    EXPECT_FLOAT_EQ(h.at(0, 1), 10 / 255.0f); // the file's top-left pixel: row 1, column 0
    EXPECT_FLOAT_EQ(h.at(1, 1), 20 / 255.0f);
    EXPECT_FLOAT_EQ(h.at(0, 0), 30 / 255.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 40 / 255.0f);

    const pr::RgbaImage c = pr::load_color(p);
    EXPECT_EQ(c.at(0, 1), glm::u8vec4(10, 10, 10, 255)); // grey replicated, opaque
    EXPECT_EQ(c.at(1, 0), glm::u8vec4(40, 40, 40, 255));
}

TEST_F(ImageFiles, ImageColorKeepsAlphaAndChannels)
{
    const std::string ga = put("ga.png", make_png(2, 8, 4, {{10, 200, 20, 100}}));
    const pr::RgbaImage c = pr::load_color(ga);
    EXPECT_EQ(c.at(0, 0), glm::u8vec4(10, 10, 10, 200));
    EXPECT_EQ(c.at(1, 0), glm::u8vec4(20, 20, 20, 100));

    const std::string rgba = put("rgba.png", make_png(1, 8, 6, {{1, 2, 3, 4}, {5, 6, 7, 8}}));
    const pr::RgbaImage d = pr::load_color(rgba);
    EXPECT_EQ(d.at(0, 0), glm::u8vec4(5, 6, 7, 8));
    EXPECT_EQ(d.at(0, 1), glm::u8vec4(1, 2, 3, 4));
}

// An Apple CgBI PNG (Xcode's form: a CgBI chunk first, BGRA colour premultiplied by alpha, raw
// deflate without zlib's header): stb left its bytes as stored, so a red map read blue and its
// height was the blue channel (found by an exploratory session, fiftieth). Read as the colour it
// stands for, as a PNG of that colour is.
TEST_F(ImageFiles, AppleCgbiPngReadsAsItsColour)
{
    Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
    chunk(png, "CgBI", {0x50, 0x00, 0x20, 0x06});
    Bytes ihdr;
    put_be32(ihdr, 2);
    put_be32(ihdr, 1);
    ihdr.insert(ihdr.end(), {8, 6, 0, 0, 0});
    chunk(png, "IHDR", ihdr);
    // One row: red 200 opaque, then red 128 at alpha 128 (stored premultiplied: 64), as B G R A.
    const Bytes raw = {0, 0, 0, 200, 255, 0, 0, 64, 128};
    Bytes deflated = {1, std::uint8_t(raw.size()), 0, std::uint8_t(~raw.size()), 0xFF}; // one stored block
    deflated.insert(deflated.end(), raw.begin(), raw.end());
    chunk(png, "IDAT", deflated);
    chunk(png, "IEND", {});
    const std::string p = put("cgbi.png", png);
    const pr::RgbaImage c = pr::load_color(p);
    EXPECT_EQ(c.at(0, 0), glm::u8vec4(200, 0, 0, 255));
    EXPECT_EQ(c.at(1, 0), glm::u8vec4(128, 0, 0, 128));
    EXPECT_FLOAT_EQ(pr::load_height(p).at(0, 0), 200 / 255.0f);
}

// ---- heights from files ----

TEST_F(ImageFiles, HeightFirstChannelOnly)
{
    // Grey + alpha: the grey. RGB(A): red. Paletted: the palette entry's red.
    EXPECT_FLOAT_EQ(pr::load_height(put("ga.png", make_png(1, 8, 4, {{51, 7}}))).at(0, 0), 0.2f);
    EXPECT_FLOAT_EQ(pr::load_height(put("rgb.png", make_png(1, 8, 2, {{102, 0, 255}}))).at(0, 0),
                    0.4f);
    EXPECT_FLOAT_EQ(pr::load_height(put("rgba.png", make_png(1, 8, 6, {{153, 1, 2, 3}}))).at(0, 0),
                    0.6f);
    const Bytes palette = {0, 9, 9, 204, 9, 9};
    const pr::HeightField pal =
        pr::load_height(put("pal.png", make_png(2, 8, 3, {{1, 0}}, palette)));
    EXPECT_FLOAT_EQ(pal.at(0, 0), 0.8f);
    EXPECT_FLOAT_EQ(pal.at(1, 0), 0.0f);
}

TEST_F(ImageFiles, Height16BitPngKeepsPrecision)
{
    // 1000 and 1001 are one 8-bit step apart from nothing: only 16 bits tell them apart.
    const std::string p = put("h16.png", make_png(4, 16, 0, {be16({0, 1000, 1001, 65535}),
                                                           be16({0x1234, 0xABCD, 32768, 1})}));
    const pr::HeightField h = pr::load_height(p);
    ASSERT_EQ(h.width, 4);
    ASSERT_EQ(h.height, 2);
    EXPECT_EQ(h.bits, 16);
    EXPECT_FLOAT_EQ(h.at(0, 1), 0.0f);
    EXPECT_FLOAT_EQ(h.at(1, 1), 1000 / 65535.0f);
    EXPECT_FLOAT_EQ(h.at(2, 1), 1001 / 65535.0f);
    EXPECT_FLOAT_EQ(h.at(3, 1), 1.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 0xABCD / 65535.0f);
    EXPECT_NE(h.at(1, 1), h.at(2, 1));

    // Colour 16-bit RGB: still the first channel at 16 bits.
    const std::string rgb = put("rgb16.png", make_png(1, 16, 2, {be16({40000, 1, 2})}));
    const pr::HeightField c = pr::load_height(rgb);
    EXPECT_EQ(c.bits, 16);
    EXPECT_FLOAT_EQ(c.at(0, 0), 40000 / 65535.0f);
    EXPECT_EQ(pr::load_color(rgb).at(0, 0), glm::u8vec4(40000 >> 8, 0, 0, 255));
}

TEST_F(ImageFiles, Height16BitPgm)
{
    Bytes pgm = {'P', '5', '\n', '2', ' ', '1', '\n', '6', '5', '5', '3', '5', '\n'};
    const Bytes samples = be16({300, 65000});
    pgm.insert(pgm.end(), samples.begin(), samples.end());
    const pr::HeightField h = pr::load_height(put("h.pgm", pgm));
    EXPECT_EQ(h.bits, 16);
    EXPECT_FLOAT_EQ(h.at(0, 0), 300 / 65535.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 65000 / 65535.0f);
    // As colour, 16 bits reduce to their high byte: 300 = 0x012C → 1, 65000 = 0xFDE8 → 253.
    const pr::RgbaImage c = pr::load_color(path("h.pgm"));
    EXPECT_EQ(c.at(0, 0), glm::u8vec4(1, 1, 1, 255));
    EXPECT_EQ(c.at(1, 0), glm::u8vec4(253, 253, 253, 255));
}

TEST_F(ImageFiles, HeightFromHdrIsClampedTo16Bits)
{
    // Radiance RGBE, flat scanlines (width < 8): 128·2^(e−136) gives 0.5 for e = 128, 2 for 130.
    const std::string header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
    Bytes hdr(header.begin(), header.end());
    hdr.insert(hdr.end(), {128, 0, 0, 128, 128, 128, 128, 130});
    const pr::HeightField h = pr::load_height(put("h.hdr", hdr));
    EXPECT_EQ(h.bits, 16);
    EXPECT_NEAR(h.at(0, 0), 0.5f, 1e-4);
    EXPECT_FLOAT_EQ(h.at(1, 0), 1.0f);
}

TEST_F(ImageFiles, HeightFrom8BitBmp)
{
    // 8-bit formats other than PNG, through stb: a 2x1 24-bit BMP (rows bottom first, BGR).
    Bytes bmp = bmp_header(2, 1);
    bmp.resize(54);
    bmp.insert(bmp.end(), {51, 51, 51, 102, 102, 102, 0, 0}); // two BGR pixels, padding
    const pr::HeightField h = pr::load_height(put("x.bmp", bmp));
    EXPECT_FLOAT_EQ(h.at(0, 0), 0.2f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 0.4f);
}

// ---- sampling ----

TEST(HeightSample, TexelCentresReturnTexels)
{
    const pr::HeightField f = field(3, 2, {0.0f, 0.25f, 0.5f, 0.75f, 1.0f, 0.125f});
    for (int j = 0; j < 2; ++j)
        for (int i = 0; i < 3; ++i)
            EXPECT_NEAR(f.sample({(i + 0.5f) / 3.0f, (j + 0.5f) / 2.0f}), f.at(i, j), 1e-6)
                << i << "," << j;
}

TEST(HeightSample, WrapsAtTheBoundary)
{
    const pr::HeightField f = field(4, 2, {0.0f, 0.2f, 0.4f, 1.0f, 0.5f, 0.5f, 0.5f, 0.5f});
    const float v = 0.25f; // centre of row 0
    // u = 0 lies halfway between the last column's centre and the first one's.
    EXPECT_FLOAT_EQ(f.sample({0.0f, v}), 0.5f * (f.at(3, 0) + f.at(0, 0)));
    EXPECT_FLOAT_EQ(f.sample({1.0f, v}), 0.5f * (f.at(3, 0) + f.at(0, 0)));
    // Along v: v = 0 averages the top row and the bottom row.
    EXPECT_FLOAT_EQ(f.sample({0.125f, 0.0f}), 0.5f * (f.at(0, 0) + f.at(0, 1)));
    // Periodic in both directions, negative coordinates included.
    for (const glm::vec2 uv : {glm::vec2(0.1f, 0.3f), glm::vec2(0.93f, 0.61f)}) {
        EXPECT_NEAR(f.sample(uv), f.sample(uv + glm::vec2(1.0f, 0.0f)), 1e-6);
        EXPECT_NEAR(f.sample(uv), f.sample(uv + glm::vec2(-2.0f, 3.0f)), 1e-6);
    }
}

TEST(HeightSample, MatchesTheGlLinearRepeatFormula)
{
    const int w = 5, h = 3;
    std::vector<float> t(w * h);
    for (int k = 0; k < w * h; ++k) t[k] = float((k * 7) % 11) / 10.0f;
    const pr::HeightField f = field(w, h, t);
    const auto gl = [&](double s, double r) {
        // GL 4.6 §8.14.2 written out: u' = s·w − ½, i0 = ⌊u'⌋ mod w, i1 = (i0 + 1) mod w.
        const double x = s * w - 0.5, y = r * h - 0.5;
        const int i0 = int(std::floor(x)), j0 = int(std::floor(y));
        const double a = x - i0, b = y - j0;
        const auto T = [&](int i, int j) { return double(f.at(i, j)); };
        return (1 - a) * (1 - b) * T(i0, j0) + a * (1 - b) * T(i0 + 1, j0) +
               (1 - a) * b * T(i0, j0 + 1) + a * b * T(i0 + 1, j0 + 1);
    };
    std::uint32_t seed = 12345;
    const auto rnd = [&seed] {
        seed = seed * 1664525U + 1013904223U;
        return double(seed >> 8) / double(1 << 24) * 3.0 - 1.0; // [-1, 2)
    };
    for (int k = 0; k < 500; ++k) {
        const double s = rnd(), r = rnd();
        EXPECT_NEAR(f.sample({float(s), float(r)}), gl(float(s), float(r)), 1e-5) << s << "," << r;
    }
}

TEST(HeightSample, AtWrapsAndMinMax)
{
    const pr::HeightField f = field(2, 2, {0.1f, 0.2f, 0.3f, 0.9f});
    EXPECT_FLOAT_EQ(f.at(-1, 0), 0.2f);
    EXPECT_FLOAT_EQ(f.at(2, 3), 0.3f);
    EXPECT_FLOAT_EQ(f.at(-3, -1), 0.9f);
    EXPECT_FLOAT_EQ(f.min_value(), 0.1f);
    EXPECT_FLOAT_EQ(f.max_value(), 0.9f);
}

// ---- errors: each names the file ----

TEST_F(ImageFiles, ImageErrorMissingFile)
{
    const std::string p = path("missing.png");
    const pr::Error e = error_of([&] { pr::load_height(p); });
    EXPECT_EQ(e.subject(), p);
    EXPECT_TRUE(contains(e.problem(), "cannot open")) << e.problem();
    EXPECT_EQ(error_of([&] { pr::load_color(p); }).subject(), p);
    EXPECT_EQ(error_of([&] { pr::read_rgba(p); }).subject(), p);
    const pr::Error folder = error_of([&] { pr::load_height(dir_.string()); });
    EXPECT_TRUE(contains(folder.problem(), "folder")) << folder.problem();
}

TEST_F(ImageFiles, ImageErrorNotAnImage)
{
    const std::string p = put("text.png", Bytes{'h', 'e', 'l', 'l', 'o', ',', ' ', 'I', ' ', 'a',
                                                'm', ' ', 't', 'e', 'x', 't', '\n'});
    const pr::Error e = error_of([&] { pr::load_height(p); });
    EXPECT_EQ(e.subject(), p);
    EXPECT_TRUE(contains(e.problem(), "not a supported image")) << e.problem();
    EXPECT_TRUE(contains(e.problem(), "PNG")) << e.problem(); // says what would be readable
    EXPECT_EQ(error_of([&] { pr::load_color(p); }).subject(), p);

    const std::string empty = put("empty.png", {});
    EXPECT_TRUE(contains(error_of([&] { pr::load_height(empty); }).problem(), "empty"));

    const std::string bad = std::string(PR_SOURCE_DIR) + "/tests/bad/not_an_image.png";
    if (fs::exists(bad)) {
        EXPECT_EQ(error_of([&] { pr::load_height(bad); }).subject(), bad);
    }
}

TEST_F(ImageFiles, ImageErrorTruncatedPng)
{
    pr::RgbaImage img = sample_image(32, 32);
    const Bytes full = pr::encode_png(img);
    ASSERT_GT(full.size(), 200u);
    const std::string p = put("cut.png", Bytes(full.begin(), full.begin() + 100));
    const pr::Error e = error_of([&] { pr::load_height(p); });
    EXPECT_EQ(e.subject(), p);
    EXPECT_TRUE(contains(e.problem(), "not a supported image")) << e.problem();
    EXPECT_EQ(error_of([&] { pr::load_color(p); }).subject(), p);
}

TEST_F(ImageFiles, ImageErrorHugeHeaderFailsBeforeDecoding)
{
    // Headers alone, claiming 100000x100000: decoding would try to allocate tens of GB. The
    // message quoting the size shows the header check, not the decoder, refused the file.
    const std::string png = put("huge.png", png_header(100000, 100000, 8, 0));
    const pr::Error e = error_of([&] { pr::load_height(png); });
    EXPECT_EQ(e.subject(), png);
    EXPECT_TRUE(contains(e.problem(), "100000x100000")) << e.problem();
    EXPECT_TRUE(contains(error_of([&] { pr::load_color(png); }).problem(), "100000x100000"));

    const std::string bmp = put("huge.bmp", bmp_header(100000, 100000));
    const pr::Error b = error_of([&] { pr::load_height(bmp); });
    EXPECT_EQ(b.subject(), bmp);
    EXPECT_TRUE(contains(b.problem(), "100000x100000")) << b.problem();
}

TEST_F(ImageFiles, ImageErrorZeroSize)
{
    const std::string png = put("zero.png", make_png(0, 8, 0, {}));
    const pr::Error e = error_of([&] { pr::load_height(png); });
    EXPECT_EQ(e.subject(), png);
    EXPECT_TRUE(contains(e.problem(), "0x0")) << e.problem();

    const std::string bmp = put("zero.bmp", bmp_header(0, 0));
    const pr::Error b = error_of([&] { pr::load_height(bmp); });
    EXPECT_EQ(b.subject(), bmp);
    EXPECT_TRUE(contains(b.problem(), "0x0") || contains(b.problem(), "not a supported image"))
        << b.problem();
}

TEST_F(ImageFiles, ImageErrorOverCallerLimits)
{
    const std::string p = put("8x4.png", make_png(8, 8, 0, std::vector<Bytes>(4, Bytes(8, 1))));
    EXPECT_NO_THROW(pr::load_height(p));
    pr::ImageLimits side;
    side.max_dimension = 6;
    const pr::Error e = error_of([&] { pr::load_height(p, side); });
    EXPECT_EQ(e.subject(), p);
    EXPECT_TRUE(contains(e.problem(), "8x4")) << e.problem();
    EXPECT_TRUE(contains(e.problem(), "6")) << e.problem();
    pr::ImageLimits pixels;
    pixels.max_pixels = 31;
    EXPECT_TRUE(contains(error_of([&] { pr::load_color(p, pixels); }).problem(), "31"));
}

// A top-down BMP (negative height in its header) was refused: stb 2.27's header probe reports the
// height negative ("the image is 2x-2 pixels: nothing to use"). Its top row stays on top.
TEST_F(ImageFiles, TopDownBmpLoadsTheRightWayUp)
{
    Bytes b = {'B', 'M'};
    const auto u32 = [&b](std::uint32_t v) {
        for (int i = 0; i < 4; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
    };
    const auto u16 = [&b](std::uint16_t v) {
        b.push_back(static_cast<std::uint8_t>(v));
        b.push_back(static_cast<std::uint8_t>(v >> 8));
    };
    u32(54 + 16); u32(0); u32(54);                                  // file size, reserved, pixel offset
    u32(40); u32(2); u32(static_cast<std::uint32_t>(-2));            // DIB header size, width, height (top-down)
    u16(1); u16(24); u32(0); u32(16); u32(2835); u32(2835); u32(0); u32(0);
    // Rows top first, BGR, padded to 4 bytes: red, green over blue, white.
    for (const std::uint8_t v : {0, 0, 255, 0, 255, 0, 0, 0, 255, 0, 0, 255, 255, 255, 0, 0}) b.push_back(v);
    const pr::RgbaImage c = pr::load_color(put("top_down.bmp", b));
    ASSERT_EQ(c.width, 2);
    ASSERT_EQ(c.height, 2);
    EXPECT_EQ(c.at(0, 1), glm::u8vec4(255, 0, 0, 255)); // the file's top-left: row 1 (top), column 0
    EXPECT_EQ(c.at(1, 1), glm::u8vec4(0, 255, 0, 255));
    EXPECT_EQ(c.at(0, 0), glm::u8vec4(0, 0, 255, 255));
    EXPECT_EQ(pr::load_height(put("top_down_h.bmp", b)).height, 2);
}

// A TGA's descriptor (byte 17) says where its first stored pixel goes: bit 5 top (else bottom),
// bit 4 right (else left). stb 2.27 reads bit 5 and ignores bit 4, so right-to-left files came
// out mirrored; each of the four origins now loads the same picture.
TEST_F(ImageFiles, TgaOriginsAllLoadTheSamePicture)
{
    // The picture, bottom row first: (10, 20) under (30, 40), grey; and in colour (BGR in the
    // file) red, green under blue, white.
    const int grey[2][2] = {{10, 20}, {30, 40}};
    const glm::u8vec4 colour[2][2] = {{{255, 0, 0, 255}, {0, 255, 0, 255}},
                                      {{0, 0, 255, 255}, {255, 255, 255, 255}}};
    for (const int origin : {0x00, 0x10, 0x20, 0x30}) {
        const bool right = origin & 0x10, top = origin & 0x20;
        Bytes g = {0, 0, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 8, std::uint8_t(origin)};
        Bytes c = {0, 0, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0, 2, 0, 2, 0, 24, std::uint8_t(origin)};
        for (int r = 0; r < 2; ++r) {
            const int y = top ? 1 - r : r;
            for (int k = 0; k < 2; ++k) {
                const int x = right ? 1 - k : k;
                g.push_back(std::uint8_t(grey[y][x]));
                const glm::u8vec4 p = colour[y][x];
                c.insert(c.end(), {p.b, p.g, p.r});
            }
        }
        const std::string name = "o" + std::to_string(origin);
        const pr::HeightField h = pr::load_height(put(name + "_h.tga", g));
        ASSERT_EQ(h.width, 2);
        ASSERT_EQ(h.height, 2);
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x)
                EXPECT_FLOAT_EQ(h.texels[std::size_t(y * 2 + x)], float(grey[y][x]) / 255.0f)
                    << "origin " << origin << " texel " << x << "," << y;
        const pr::RgbaImage img = pr::load_color(put(name + "_c.tga", c));
        for (int y = 0; y < 2; ++y)
            for (int x = 0; x < 2; ++x)
                EXPECT_EQ(img.at(x, y), colour[y][x]) << "origin " << origin << " pixel " << x << "," << y;
    }
}

// Files that end before their pixels do (found by an exploratory session, sixteenth session):
// stb_image returned uninitialised memory for a truncated PNM (a different map each run), zeros
// for the missing rows of BMP, GIF and run-length TGA, and looped forever on a run-length HDR
// scanline cut short. Each is refused now, with one line; the whole files load.
TEST_F(ImageFiles, FilesThatEndBeforeTheirPixelsAreRefused)
{
    const auto text = [](const std::string& s) { return Bytes(s.begin(), s.end()); };
    const auto refused = [&](const std::string& name, const Bytes& bytes, const std::string& why) {
        refused_both_ways(name, bytes, why);
    };
    // PGM 64x64 with 100 of its 4096 samples.
    Bytes pgm = text("P5\n64 64\n255\n");
    const Bytes whole_pgm = [&] { Bytes b = pgm; b.resize(b.size() + 4096, 0x80); return b; }();
    pgm.resize(pgm.size() + 100, 0x80);
    refused("short.pgm", pgm, "truncated PNM: it needs at least 4109 bytes, the file has 113");
    EXPECT_FLOAT_EQ(pr::load_height(put("whole.pgm", whole_pgm)).at(5, 5), 128.0f / 255.0f);
    // A run-length HDR scanline of 64 pixels cut after its first dump's count: stb read a count
    // of 0 past the end and never advanced.
    Bytes hdr = text("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 64\n");
    hdr.insert(hdr.end(), {2, 2, 0, 64});
    refused("cut.hdr", hdr, "truncated HDR");
    hdr.push_back(0); // a dump of no bytes, then the end: the same loop
    refused("zero.hdr", hdr, "truncated HDR");
    // A 24-bit BMP 4x4, rows of 12 bytes: two rows kept.
    Bytes bmp = bmp_header(4, 4);
    bmp.resize(54 + 24, 0x40);
    refused("cut.bmp", bmp, "truncated BMP: it needs at least 102 bytes, the file has 78");
    // An 8-bit BMP 4x1 with a palette of 2 colours (the offset leaves room for 2): stb looks each
    // index up unchecked, so index 3 read uninitialised memory (found by a review).
    Bytes pal = bmp_header(4, 1);
    pal[10] = 54 + 8; // the data offset
    pal[28] = 8;      // bits per pixel
    pal.resize(54);
    pal.insert(pal.end(), {10, 10, 10, 0, 200, 200, 200, 0, 0, 1, 3, 0});
    refused("index.bmp", pal, "a pixel's colour index is 3, past its palette of 2 colours");
    pal[54 + 8 + 2] = 1;
    EXPECT_FLOAT_EQ(pr::load_height(put("palette.bmp", pal)).at(1, 0), 200.0f / 255.0f);
    // A colour-mapped TGA whose map starts at entry 20: stb skips 20 bytes before the map.
    Bytes mapped = {0, 1, 1, 20, 0, 2, 0, 24, 0, 0, 0, 0, 4, 0, 1, 0, 8, 0};
    mapped.resize(mapped.size() + 20 + 6, 0x50);
    mapped.insert(mapped.end(), {0, 1});
    refused("mapped.tga", mapped, "truncated TGA");
    // A run-length grey TGA 4x2: one run of 4 pixels (0x83, value), then a cut.
    Bytes tga = {0, 0, 11, 0, 0, 0, 0, 0, 0, 0, 0, 0, 4, 0, 2, 0, 8, 0, 0x83, 200};
    refused("cut.tga", tga, "truncated run-length TGA");
    tga.insert(tga.end(), {0x83, 100});
    EXPECT_FLOAT_EQ(pr::load_height(put("whole.tga", tga)).at(0, 0), 200.0f / 255.0f);
    // GIF 2x2 (one LZW block) cut inside its image data: the padding check (decoded twice, the
    // missing bytes read as zeros and as 0xFF) tells.
    const Bytes gif = {'G', 'I', 'F', '8', '9', 'a', 2, 0, 2, 0, 0x80, 0, 0, 0, 0, 0, 255, 255, 255,
                       0x2C, 0, 0, 0, 0, 2, 0, 2, 0, 0, 2, 3, 0x84, 0x1D, 0x05, 0, 0x3B};
    const pr::HeightField whole_gif = pr::load_height(put("whole.gif", gif));
    EXPECT_EQ(whole_gif.width, 2);
    refused("cut.gif", Bytes(gif.begin(), gif.begin() + 33), "the file ends before its pixels do");
    // A GIF complete to its trailer whose image data ends (an end code) after 1 of its 4 pixels:
    // stb filled the rest with the background colour (or left it transparent, said as such, for
    // background index 0) without a word; a frame smaller than its screen likewise; a GIF with no
    // image said "corrupt data" (found by an exploratory session, fiftieth).
    const Bytes head(gif.begin(), gif.begin() + 19);
    const auto with = [&](std::initializer_list<std::uint8_t> rest) {
        Bytes b = head;
        b.insert(b.end(), rest);
        return b;
    };
    refused("early_end.gif", with({0x2C, 0, 0, 0, 0, 2, 0, 2, 0, 0, 2, 2, 0x44, 0x01, 0, 0x3B}),
            "truncated or corrupt data: the GIF's image data ends after 1 of its 4 pixels");
    refused("early_end_no_trailer.gif", with({0x2C, 0, 0, 0, 0, 2, 0, 2, 0, 0, 2, 2, 0x44, 0x01}),
            "the file ends before its pixels do");
    refused("small_frame.gif", with({0x2C, 1, 0, 1, 0, 1, 0, 1, 0, 0, 2, 2, 0x44, 0x01, 0, 0x3B}),
            "the GIF's first frame covers 1x1 pixels, from 1,1 at the top left, of its 2x2 screen");
    refused("no_image.gif", with({0x3B}), "a GIF with no image in it");
    // PSD, RGB 1x1, 16 bits, run-length: stb decodes it as 8-bit data (garbage).
    Bytes psd = text("8BPS");
    psd.insert(psd.end(), {0, 1, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 1, 0, 0, 0, 1, 0, 16, 0, 3});
    psd.insert(psd.end(), {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 3, 0, 3, 0, 3});
    for (int channel = 0; channel < 3; ++channel) psd.insert(psd.end(), {1, 0x12, 0x34});
    refused("rle16.psd", psd, "16-bit PSD with run-length compression");
}

// stb_image 2.27 checks no PNG CRC (nor zlib's Adler-32): a damaged byte in IDAT decoded to
// wrong heights with exit 0 (found by an exploratory session). Every chunk up to IEND is
// checked; a file cut short or without IEND is named as such (stb's reason was empty).
TEST_F(ImageFiles, DamagedOrShortPngsAreRefused)
{
    const auto refused = [&](const std::string& name, const Bytes& bytes, const std::string& why) {
        refused_both_ways(name, bytes, why);
    };
    const Bytes png = make_png(4, 8, 0, {{0, 8, 16, 24}, {32, 40, 48, 56}});
    const auto idat = std::size_t(std::search(png.begin(), png.end(), std::begin("IDAT"), std::end("IDAT") - 1) - png.begin());
    Bytes damaged = png;
    damaged[idat + 4 + 2 + 5 + 1 + 2] ^= 0x20; // the first row's third pixel (zlib header, block header, filter)
    refused("idat.png", damaged, "corrupt PNG: the CRC of its IDAT chunk does not match its data: a damaged file");
    damaged = png;
    damaged.back() ^= 1; // IEND's CRC
    refused("iend.png", damaged, "corrupt PNG: the CRC of its IEND chunk does not match its data");
    refused("no_iend.png", Bytes(png.begin(), png.end() - 12),
            "truncated PNG: the file ends after its IDAT chunk, without the IEND chunk that closes a PNG");
    refused("cut.png", Bytes(png.begin(), png.begin() + std::ptrdiff_t(idat + 10)),
            fmt::format("truncated PNG: it needs at least {} bytes, the file has {}", png.size() - 12, idat + 10));
    refused("cut_header.png", Bytes(png.begin(), png.end() - 5), "truncated PNG: it needs at least");
    // Bytes after IEND are left alone, as stb leaves them.
    Bytes trailing = png;
    trailing.insert(trailing.end(), 100, 0xAB);
    EXPECT_FLOAT_EQ(pr::load_height(put("trailing.png", trailing)).at(2, 1), 16.0f / 255.0f);
}

// stb_image 2.27 looks a palette PNG's indices up unchecked in a palette array of 256 entries,
// only the PLTE's set: index 7 of a 2-colour palette read uninitialised stack memory, with
// exit 0 (found by an exploratory session).
TEST_F(ImageFiles, PngPaletteIndicesPastThePlteAreRefused)
{
    const auto refused = [&](const std::string& name, const Bytes& bytes, const std::string& why) {
        refused_both_ways(name, bytes, why);
    };
    const Bytes two = {0, 0, 0, 255, 255, 255};
    refused("index7.png", make_png(4, 8, 3, {{0, 1, 7, 1}, {3, 0, 0, 0}}, two),
            "corrupt PNG: a pixel's colour index is 7, past its palette of 2 colours");
    // 4 bits a pixel, two pixels a byte: index 2 in the second.
    refused("index2.png", make_png(2, 4, 3, {{0x12}}, two), "a pixel's colour index is 2, past its palette of 2 colours");
    // Indices within a short palette load, also those of 1-bit rows with padding bits set.
    const pr::HeightField h = pr::load_height(put("short.png", make_png(3, 4, 3, {{0x10, 0x00}}, two)));
    EXPECT_FLOAT_EQ(h.at(0, 0), 1.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 0.0f);
    EXPECT_EQ(pr::load_color(put("padded.png", make_png(3, 1, 3, {{0x5F}}, two))).at(1, 0), glm::u8vec4(255, 255, 255, 255));
    // No palette at all, or an empty PLTE chunk: said in words (stb's "no PLTE"; found by an
    // exploratory session, fiftieth).
    refused("no_plte.png", make_png(2, 8, 3, {{0, 0}}), "a palette image without the colours of its palette (PLTE)");
    Bytes empty = png_header(2, 1, 8, 3);
    chunk(empty, "PLTE", {});
    const Bytes rest = make_png(2, 8, 3, {{0, 0}});
    empty.insert(empty.end(), rest.begin() + 33, rest.end()); // (past the signature and IHDR)
    refused("empty_plte.png", empty, "a palette image without the colours of its palette (PLTE)");
}

// A PNM's samples run from 0 to its maxval: stb returns them as stored, so maxval 127 gave
// heights of at most 127/255, and 4095 (12-bit data in 16-bit samples) 1/16 of the range.
TEST_F(ImageFiles, PnmSamplesAreScaledByTheirMaxval)
{
    Bytes p7 = {'P', '5', '\n', '2', ' ', '1', '\n', '1', '2', '7', '\n', 127, 64};
    const pr::HeightField h7 = pr::load_height(put("m7.pgm", p7));
    EXPECT_FLOAT_EQ(h7.at(0, 0), 1.0f);
    EXPECT_NEAR(h7.at(1, 0), 64.0f / 127.0f, 1.0f / 65535.0f);
    EXPECT_EQ(pr::load_color(path("m7.pgm")).at(1, 0), glm::u8vec4(129, 129, 129, 255)); // 64 * 255 / 127
    Bytes p12 = {'P', '5', '\n', '2', ' ', '1', '\n', '4', '0', '9', '5', '\n', 0x0F, 0xFF, 0x08, 0x00};
    const pr::HeightField h12 = pr::load_height(put("m12.pgm", p12));
    EXPECT_EQ(h12.bits, 16);
    EXPECT_FLOAT_EQ(h12.at(0, 0), 1.0f);
    // To 16-bit steps, as the GPU's R16 holds it (it was 2048/4095 itself, half a step off).
    EXPECT_FLOAT_EQ(h12.at(1, 0), std::round(2048.0f / 4095.0f * 65535.0f) / 65535.0f);
    EXPECT_NEAR(h12.at(1, 0), 2048.0f / 4095.0f, 0.5f / 65535.0f);
    EXPECT_EQ(pr::load_color(path("m12.pgm")).at(1, 0), glm::u8vec4(128, 128, 128, 255));
    const Bytes p0 = {'P', '5', '\n', '1', ' ', '1', '\n', '0', '\n', 0};
    const std::string zero = put("m0.pgm", p0);
    EXPECT_TRUE(contains(error_of([&] { pr::load_height(zero); }).problem(), "PNM maxval 0: must be 1 to 65535"));
}

// A sample past its PNM's maxval is a damaged file (netpbm refuses it too): it came out clamped
// to the top height without a word (found by an exploratory session).
TEST_F(ImageFiles, PnmSamplesPastTheirMaxvalAreRefused)
{
    const auto refused = [&](const std::string& name, const Bytes& bytes, const std::string& why) {
        refused_both_ways(name, bytes, why);
    };
    refused("over.pgm", {'P', '5', '\n', '2', ' ', '1', '\n', '1', '0', '0', '\n', 100, 255},
            "corrupt PNM: a sample is 255, more than its maxval of 100");
    refused("over16.pgm", {'P', '5', '\n', '2', ' ', '1', '\n', '1', '0', '0', '0', '\n', 0x03, 0xE8, 0x03, 0xE9},
            "corrupt PNM: a sample is 1001, more than its maxval of 1000");
    refused("over.ppm", {'P', '6', '\n', '1', ' ', '1', '\n', '9', '\n', 9, 9, 10},
            "corrupt PNM: a sample is 10, more than its maxval of 9");
    // At the maxval: the top height.
    EXPECT_FLOAT_EQ(pr::load_height(put("top.pgm", {'P', '5', '\n', '1', ' ', '1', '\n', '1', '0', '0', '\n', 100})).at(0, 0),
                    1.0f);
}

// An uncompressed 16-bit PSD keeps its 16 bits: stb 2.27's stbi_is_16_bit says no to every PSD
// (its test reads the height's first bytes as the depth), and they were read at 8 bits (an
// exploratory session saw 2053 come out as 2056).
TEST_F(ImageFiles, Psd16BitKeepsItsPrecision)
{
    Bytes psd = {'8', 'B', 'P', 'S', 0, 1, 0, 0, 0, 0, 0, 0, 0, 3, 0, 0, 0, 1, 0, 0, 0, 2, 0, 16, 0, 3};
    psd.insert(psd.end(), {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
    for (int channel = 0; channel < 3; ++channel) psd.insert(psd.end(), {0, 5, 0x08, 0x05});
    const pr::HeightField h = pr::load_height(put("p16.psd", psd));
    EXPECT_EQ(h.bits, 16);
    EXPECT_FLOAT_EQ(h.at(0, 0), 5.0f / 65535.0f);
    EXPECT_FLOAT_EQ(h.at(1, 0), 2053.0f / 65535.0f);
}

// A JPEG's EXIF orientation (tag 0x0112): stb ignores it, so a photo taken upright on a phone
// (stored on its side, orientation 6: turn 90 degrees clockwise to show) came out on its side.
TEST_F(ImageFiles, JpegExifOrientationIsApplied)
{
    // Stored 16 x 8: the left half black, the right half white.
    pr::RgbaImage stored;
    stored.width = 16;
    stored.height = 8;
    stored.pixels.resize(16 * 8 * 4);
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 16; ++x)
            for (int c = 0; c < 4; ++c) stored.pixels[std::size_t(y * 16 + x) * 4 + c] = c == 3 || x >= 8 ? 255 : 0;
    Bytes jpeg;
    stbi_write_jpg_to_func([](void* out, void* data, int size) {
        auto* b = static_cast<Bytes*>(out);
        b->insert(b->end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
    }, &jpeg, 16, 8, 4, stored.pixels.data(), 100);
    ASSERT_GT(jpeg.size(), 4u);
    const Bytes plain = jpeg;
    // APP1 after SOI: "Exif\0\0", little-endian TIFF, IFD0 with one SHORT entry 0x0112 = 6.
    const Bytes app1 = {0xFF, 0xE1, 0, 34, 'E', 'x', 'i', 'f', 0, 0, 'I', 'I', 42, 0, 8, 0, 0, 0, 1, 0,
                        0x12, 0x01, 3, 0, 1, 0, 0, 0, 6, 0, 0, 0, 0, 0, 0, 0};
    jpeg.insert(jpeg.begin() + 2, app1.begin(), app1.end());
    const pr::HeightField as_stored = pr::load_height(put("plain.jpg", plain));
    EXPECT_EQ(as_stored.width, 16);
    const pr::HeightField h = pr::load_height(put("turned.jpg", jpeg));
    ASSERT_EQ(h.width, 8);
    ASSERT_EQ(h.height, 16);
    // Shown upright: the black half on top (rows are bottom first here).
    EXPECT_GT(h.at(4, 2), 0.9f);  // bottom: white
    EXPECT_LT(h.at(4, 13), 0.1f); // top: black
    const pr::RgbaImage c = pr::load_color(path("turned.jpg"));
    ASSERT_EQ(c.width, 8);
    EXPECT_GT(c.at(4, 2).r, 230);
    EXPECT_LT(c.at(4, 13).r, 25);
}

// stb keeps the filtered rows' size, (4 width + 1) height, in an int: past 2 GiB it wrapped and the
// buffer it allocated was too small for what it wrote (a compare grid of 16384² tiles). Such
// images are refused (encode_png; compare checks its grid before drawing).
TEST(ImageEncode, PngsPastTheEncodersIntAreRefused)
{
    EXPECT_TRUE(pr::png_encodable(16384, 16384));
    EXPECT_TRUE(pr::png_encodable(1, 1));
    EXPECT_FALSE(pr::png_encodable(49184, 32880));
    EXPECT_FALSE(pr::png_encodable(536870912, 1)); // one row of 2 GiB
    EXPECT_FALSE(pr::png_encodable(0, 16));
}

// Empty IDAT chunks are dropped before stb sees a PNG (stb copied one's data from a null
// pointer): each of them, wherever it stands, and nothing else, bytes after IEND included.
TEST(PngChunks, EmptyIdatChunksAreDroppedAndNothingElse)
{
    const auto chunk = [](std::string_view type, const std::vector<std::uint8_t>& data) {
        std::vector<std::uint8_t> c = {0, 0, 0, std::uint8_t(data.size())};
        for (const char ch : type) c.push_back(std::uint8_t(ch));
        for (const std::uint8_t v : data) c.push_back(v);
        c.insert(c.end(), {1, 2, 3, 4}); // (no CRC is checked here)
        return c;
    };
    const std::vector<std::uint8_t> sig = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    const std::vector<std::vector<std::uint8_t>> kept = {chunk("IHDR", {1, 2, 3}), chunk("IDAT", {9, 9}),
                                                         chunk("tEXt", {}), chunk("IEND", {})};
    const std::vector<std::uint8_t> empty = chunk("IDAT", {}), tail = {'x', 'y', 'z'};
    std::vector<std::uint8_t> with = sig, without = sig;
    for (std::size_t k = 0; k < kept.size(); ++k) {
        if (k == 1 || k == 2) with.insert(with.end(), empty.begin(), empty.end()); // two before data, one after
        if (k == 1) with.insert(with.end(), empty.begin(), empty.end());
        with.insert(with.end(), kept[k].begin(), kept[k].end());
        without.insert(without.end(), kept[k].begin(), kept[k].end());
    }
    with.insert(with.end(), tail.begin(), tail.end());
    without.insert(without.end(), tail.begin(), tail.end());
    pr::drop_empty_png_idat(with);
    EXPECT_EQ(with, without);
    std::vector<std::uint8_t> none = without;
    pr::drop_empty_png_idat(none);
    EXPECT_EQ(none, without);
}

// A Softimage PIC of `w` x `h` whose one packet (channels R, G and B) has compression `type` and
// holds `rows`, top row first.
Bytes pic_file(int w, int h, std::uint8_t type, const Bytes& rows)
{
    Bytes b = {0x53, 0x80, 0xF6, 0x34};
    b.resize(88, 0);
    for (char c : std::string_view("PICT")) b.push_back(std::uint8_t(c));
    for (int v : {w, h}) b.insert(b.end(), {std::uint8_t(v >> 8), std::uint8_t(v)});
    b.insert(b.end(), {0x3F, 0x80, 0, 0, 0, 3, 0, 0}); // ratio 1.0, fields 3, pad
    b.insert(b.end(), {0, 8, type, 0xE0});
    b.insert(b.end(), rows.begin(), rows.end());
    return b;
}

// The PIC check walks the rows as stb reads them (thirty-sixth session): a file it passes decodes
// in each of the three compressions, and the same rows one byte short are refused as truncated,
// before stb allocates the image.
TEST_F(ImageFiles, PicRowsAreWalkedAsStbReadsThem)
{
    // 3 x 2, grey: top row 10 20 30, bottom row 40 40 40.
    const Bytes raw = {10, 10, 10, 20, 20, 20, 30, 30, 30, 40, 40, 40, 40, 40, 40, 40, 40, 40};
    const Bytes pure = {1, 10, 10, 10, 1, 20, 20, 20, 1, 30, 30, 30, 3, 40, 40, 40};
    const Bytes mixed = {2, 10, 10, 10, 20, 20, 20, 30, 30, 30, 128, 0, 3, 40, 40, 40};
    for (const auto& [type, rows] : {std::pair{std::uint8_t(0), raw}, std::pair{std::uint8_t(1), pure},
                                     std::pair{std::uint8_t(2), mixed}}) {
        SCOPED_TRACE(int(type));
        const pr::HeightField h = pr::load_height(put("ok.pic", pic_file(3, 2, type, rows)));
        ASSERT_EQ(h.width, 3);
        ASSERT_EQ(h.height, 2);
        EXPECT_FLOAT_EQ(h.at(0, 1), 10 / 255.0f);
        EXPECT_FLOAT_EQ(h.at(2, 1), 30 / 255.0f);
        EXPECT_FLOAT_EQ(h.at(1, 0), 40 / 255.0f);
        const Bytes cut(rows.begin(), rows.end() - 1);
        const pr::Error e = prtest::error_of([&] { (void)pr::load_height(put("cut.pic", pic_file(3, 2, type, cut))); });
        EXPECT_NE(std::string(e.what()).find("truncated PIC: the file ends in row 2 of 2"), std::string::npos) << e.what();
    }
}
