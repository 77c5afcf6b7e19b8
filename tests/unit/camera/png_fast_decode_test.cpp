// decodePlainPng (libdeflate + our unfilter) against libpng itself: every PNG row filter, grey
// and grey+alpha, one and many IDAT chunks must give libpng's bytes; whatever lies outside the
// subset it reads (other chunks, interlacing, 16 bit, another size, a damaged file) is left to
// libpng, and decodePngPayload still reads those exactly.
#include "handscan/camera/png_fast_decode.hpp"

#include <gtest/gtest.h>
#include <png.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "handscan/camera/png_payload.hpp"
#include "handscan/core/v4l2_types.hpp"

namespace handscan::camera {
namespace {

struct PngOptions {
    int channels = 1;
    int filters = PNG_FILTER_AVG;  // libpng's mask: one filter, or several (adaptive)
    int interlace = PNG_INTERLACE_NONE;
    int bit_depth = 8;
    std::size_t zbuf = 1u << 16;  // compressed bytes per IDAT chunk
    bool text = false;            // adds a tEXt chunk
};

void append(png_structp png, png_bytep data, png_size_t n) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + n);
}
void noFlush(png_structp) {}

// libpng writes the file (the reference encoder, any filter); rows of width * channels bytes
// (twice that at 16 bit).
std::vector<std::uint8_t> writeWithLibpng(const std::vector<std::uint8_t>& px, std::uint32_t w,
                                          std::uint32_t h, const PngOptions& o) {
    std::vector<std::uint8_t> out;
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        ADD_FAILURE() << "libpng could not write the test image";
        return {};
    }
    png_set_write_fn(png, &out, append, noFlush);
    png_set_IHDR(png, info, w, h, o.bit_depth,
                 o.channels == 1 ? PNG_COLOR_TYPE_GRAY : PNG_COLOR_TYPE_GRAY_ALPHA, o.interlace,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, o.filters);
    png_set_compression_buffer_size(png, o.zbuf);
    png_text text{};
    char key[] = "Comment";
    char value[] = "not ours";
    if (o.text) {
        text.compression = PNG_TEXT_COMPRESSION_NONE;
        text.key = key;
        text.text = value;
        png_set_text(png, info, &text, 1);
    }
    png_write_info(png, info);
    const std::size_t row = std::size_t{w} * static_cast<std::size_t>(o.channels) *
                            static_cast<std::size_t>(o.bit_depth / 8);
    std::vector<png_bytep> rows(h);
    for (std::uint32_t y = 0; y < h; ++y)
        rows[y] = const_cast<png_bytep>(px.data() + y * row);  // libpng only reads them
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return out;
}

// A camera-like image (smooth shading, edges, noise, every byte value somewhere) so that every
// filter's predictions wrap around 0/255.
std::vector<std::uint8_t> image(std::uint32_t w, std::uint32_t h, int channels, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> px(std::size_t{w} * h * static_cast<std::size_t>(channels));
    for (std::size_t i = 0; i < px.size(); ++i) {
        const std::size_t x = (i / static_cast<std::size_t>(channels)) % w;
        const std::size_t y = i / (std::size_t{w} * static_cast<std::size_t>(channels));
        const int base = static_cast<int>(3 * x + 2 * y) + (((x / 5) + (y / 3)) % 2 ? 90 : 0);
        px[i] = static_cast<std::uint8_t>((base + static_cast<int>(rng() % 9)) & 0xFF);
        if (i % 13 == 0) px[i] = static_cast<std::uint8_t>(rng() & 0xFF);
    }
    return px;
}

TEST(PngFastDecode, EveryFilterAndChunkingGivesLibpngsBytes) {
    // Odd sizes: no loop lands on a round number (rows go four at a time where they can), and
    // images narrower than those four rows' stagger.
    const std::uint32_t h = 23;
    for (const std::uint32_t w : {61u, 2u, 1u})
        for (const int channels : {1, 2}) {
            const auto px = image(w, h, channels, 3 + static_cast<unsigned>(channels));
            for (const int filters : {PNG_FILTER_NONE, PNG_FILTER_SUB, PNG_FILTER_UP,
                                      PNG_FILTER_AVG, PNG_FILTER_PAETH, PNG_ALL_FILTERS}) {
                for (const std::size_t zbuf : {std::size_t{1} << 16, std::size_t{97}}) {
                    PngOptions o;
                    o.channels = channels;
                    o.filters = filters;
                    o.zbuf = zbuf;
                    const auto png = writeWithLibpng(px, w, h, o);
                    std::vector<std::uint8_t> out;
                    ASSERT_TRUE(decodePlainPng(png, w, h, channels, out))
                        << "width " << w << " channels " << channels << " filters " << filters
                        << " zbuf " << zbuf;
                    EXPECT_EQ(out, px)
                        << "width " << w << " channels " << channels << " filters " << filters;
                }
            }
        }
}

TEST(PngFastDecode, OnlyOurSubsetElseLibpngReadsIt) {
    const std::uint32_t w = 40, h = 9;
    const auto px = image(w, h, 1, 11);
    const auto plain = writeWithLibpng(px, w, h, {});
    std::vector<std::uint8_t> out;
    ASSERT_TRUE(decodePlainPng(plain, w, h, 1, out));
    // The size or the pixel type the caller expects is not the file's.
    EXPECT_FALSE(decodePlainPng(plain, w + 1, h, 1, out));
    EXPECT_FALSE(decodePlainPng(plain, w, h - 1, 1, out));
    EXPECT_FALSE(decodePlainPng(plain, w / 2, h, 2, out));
    // A damaged file: a flipped bit in the pixel data (CRC), a cut file, not a PNG at all.
    auto flipped = plain;
    flipped[flipped.size() / 2] ^= 0x10;
    EXPECT_FALSE(decodePlainPng(flipped, w, h, 1, out));
    EXPECT_FALSE(decodePlainPng(std::span(plain).first(plain.size() - 20), w, h, 1, out));
    EXPECT_FALSE(decodePlainPng(std::span(plain).first(4), w, h, 1, out));
    EXPECT_FALSE(decodePlainPng({}, w, h, 1, out));
    EXPECT_FALSE(decodePlainPng(std::vector<std::uint8_t>(100, 0x89), w, h, 1, out));

    // Outside the subset: left to libpng, which decodePngPayload then uses for the exact bytes.
    FrameRecordHeader header;
    header.fourcc = kFourccGrey;
    header.width = w;
    header.height = h;
    header.stride = w;
    header.bytesused = w * h;
    PngOptions text;
    text.text = true;
    PngOptions interlaced;
    interlaced.interlace = PNG_INTERLACE_ADAM7;
    for (const PngOptions& o : {text, interlaced}) {
        const auto png = writeWithLibpng(px, w, h, o);
        EXPECT_FALSE(decodePlainPng(png, w, h, 1, out));
        std::vector<std::uint8_t> buffer;
        ASSERT_TRUE(decodePngPayload(header, png, buffer).isOk());
        EXPECT_EQ(buffer, px);
    }
    // 16 bit: neither reads it as an 8-bit buffer.
    PngOptions deep;
    deep.bit_depth = 16;
    const auto px16 = image(w, h, 2, 12);  // w x h samples of two bytes
    const auto png16 = writeWithLibpng(px16, w, h, deep);
    EXPECT_FALSE(decodePlainPng(png16, w, h, 1, out));
    std::vector<std::uint8_t> buffer;
    EXPECT_FALSE(decodePngPayload(header, png16, buffer).isOk());
}

}  // namespace
}  // namespace handscan::camera
