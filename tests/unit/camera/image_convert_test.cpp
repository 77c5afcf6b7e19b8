#include "handscan/camera/image_convert.hpp"

#include <gtest/gtest.h>
#include <turbojpeg.h>

#include <cstdlib>

namespace handscan::camera {
namespace {

Image yuyv2x1(std::uint8_t y0, std::uint8_t u, std::uint8_t y1, std::uint8_t v, int stride = 4) {
    Image im;
    im.format = PixelFormat::kYuyv;
    im.width = 2;
    im.height = 2;
    im.stride_bytes = stride;
    im.data.assign(static_cast<std::size_t>(stride + 4), 0);
    for (int row = 0; row < 2; ++row) {
        auto* p = im.data.data() + row * stride;
        p[0] = y0, p[1] = u, p[2] = y1, p[3] = v;
    }
    return im;
}

TEST(ImageConvert, YuyvToGreyTakesLumaAndHonoursStride) {
    auto g = toGrey(yuyv2x1(16, 128, 235, 128, 6));
    ASSERT_TRUE(g) << g.status().message();
    EXPECT_EQ(g->format, PixelFormat::kGrey8);
    EXPECT_EQ(g->stride_bytes, 2);
    EXPECT_EQ(g->data, (std::vector<std::uint8_t>{16, 235, 16, 235}));
}

TEST(ImageConvert, YuyvToBgrUsesBt601) {
    // Neutral chroma: grey levels; video range 16..235 maps to 0..255.
    auto n = toBgr(yuyv2x1(16, 128, 235, 128));
    ASSERT_TRUE(n) << n.status().message();
    EXPECT_LE(n->data[0], 1);
    EXPECT_GE(n->data[3], 254);
    // Strong red: V high -> R channel (index 2) well above B.
    auto r = toBgr(yuyv2x1(81, 90, 81, 240));
    ASSERT_TRUE(r);
    EXPECT_GT(r->data[2], 200);
    EXPECT_LT(r->data[0], 40);
}

TEST(ImageConvert, DecodesMjpegWithLibjpegTurbo) {
    const int w = 32, h = 16;
    std::vector<std::uint8_t> grey(static_cast<std::size_t>(w * h));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x)
            grey[static_cast<std::size_t>(y * w + x)] = static_cast<std::uint8_t>(x * 8);
    }
    tjhandle tj = tjInitCompress();
    unsigned char* jpeg = nullptr;
    unsigned long size = 0;
    ASSERT_EQ(tjCompress2(tj, grey.data(), w, w, h, TJPF_GRAY, &jpeg, &size, TJSAMP_GRAY, 95, 0),
              0);
    Image m;
    m.format = PixelFormat::kMjpeg;
    m.width = w;
    m.height = h;
    m.sequence = 7;
    m.data.assign(jpeg, jpeg + size);
    tjFree(jpeg);
    tjDestroy(tj);
    auto g = toGrey(m);
    ASSERT_TRUE(g) << g.status().message();
    ASSERT_EQ(g->data.size(), grey.size());
    for (std::size_t i = 0; i < grey.size(); ++i) ASSERT_NEAR(g->data[i], grey[i], 6) << i;
    auto bgr = toBgr(m);
    ASSERT_TRUE(bgr);
    EXPECT_EQ(bgr->data.size(), grey.size() * 3);
    EXPECT_EQ(bgr->sequence, 7u);

    Image corrupt = m;
    corrupt.data.resize(10);
    auto bad = toGrey(corrupt);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.status().message().find("camera frame 7"), std::string::npos)
        << bad.status().message();
    Image wrong_size = m;
    wrong_size.width = 64;
    EXPECT_FALSE(toGrey(wrong_size));
}

TEST(ImageConvert, RejectsShortBuffers) {
    Image g;
    g.format = PixelFormat::kGrey8;
    g.width = 4;
    g.height = 4;
    g.stride_bytes = 4;
    g.data.resize(15);
    EXPECT_FALSE(toGrey(g));
    g.data.resize(16);
    EXPECT_TRUE(toGrey(g));
}

}  // namespace
}  // namespace handscan::camera
