#include "handscan/camera/frame_record.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "handscan/camera/png_payload.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace handscan::camera {
namespace {

FrameRecordHeader greyHeader() {
    FrameRecordHeader h;
    h.sequence = 0x01020304;
    h.flags = transport::kV4l2BufFlagTimestampMonotonic | transport::kV4l2BufFlagTstampSrcSoe;
    h.timestamp_ns = 0x1122334455667788LL;
    h.fourcc = transport::kFourccGrey;
    h.width = 4;
    h.height = 2;
    h.stride = 6;
    h.exposure_us = 5000;
    h.t_host_ns = 42;
    return h;
}

TEST(FrameRecord, HasTheDocumentedByteLayout) {
    const std::vector<std::uint8_t> payload = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8};
    auto rec = encodeFrameRecord(greyHeader(), payload);
    ASSERT_EQ(rec.size(), 56u + 10u);
    EXPECT_EQ(std::string(rec.begin(), rec.begin() + 4), "HSVF");
    EXPECT_EQ(rec[4], 1);   // version
    EXPECT_EQ(rec[6], 56);  // header size
    EXPECT_EQ(rec[8], 0x04);
    EXPECT_EQ(rec[11], 0x01);  // sequence LE
    EXPECT_EQ(rec[14], 0x01);  // flags 0x12000: TSTAMP_SRC_SOE
    EXPECT_EQ(rec[13], 0x20);  // MONOTONIC
    EXPECT_EQ(rec[16], 0x88);
    EXPECT_EQ(rec[23], 0x11);
    EXPECT_EQ(rec[24], 10);  // bytesused
    EXPECT_EQ(std::string(rec.begin() + 28, rec.begin() + 32), "GREY");
    EXPECT_EQ(rec[32], 4);
    EXPECT_EQ(rec[36], 2);
    EXPECT_EQ(rec[40], 6);
    EXPECT_EQ(rec[44] | (rec[45] << 8), 5000);
    EXPECT_EQ(rec[48], 42);
    EXPECT_EQ(rec[56], 1);
    EXPECT_EQ(rec[65], 8);
}

TEST(FrameRecord, RoundTripsAndConcatenates) {
    const std::vector<std::uint8_t> payload = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8};
    FrameRecordHeader h = greyHeader();
    auto a = encodeFrameRecord(h, payload);
    FrameRecordHeader m = h;
    m.fourcc = transport::kFourccMjpeg;
    m.stride = 0;
    auto b = encodeFrameRecord(m, std::vector<std::uint8_t>{0xFF, 0xD8, 0xFF, 0xD9});
    std::vector<std::uint8_t> both = a;
    both.insert(both.end(), b.begin(), b.end());
    auto r1 = decodeFrameRecord(both);
    ASSERT_TRUE(r1) << r1.status().message();
    h.bytesused = 10;
    EXPECT_EQ(r1->header, h);
    EXPECT_EQ(std::vector<std::uint8_t>(r1->payload.begin(), r1->payload.end()), payload);
    auto r2 = decodeFrameRecord(std::span<const std::uint8_t>(both).subspan(r1->record_size));
    ASSERT_TRUE(r2) << r2.status().message();
    EXPECT_EQ(r2->header.fourcc, transport::kFourccMjpeg);
    EXPECT_EQ(r2->payload.size(), 4u);
}

TEST(FrameRecord, RejectsTruncatedAndInconsistentRecords) {
    const std::vector<std::uint8_t> payload = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8};
    const auto rec = encodeFrameRecord(greyHeader(), payload);
    for (std::size_t cut : {0ul, 7ul, 30ul, 56ul, 65ul}) {
        auto r = decodeFrameRecord(std::span<const std::uint8_t>(rec).first(cut));
        ASSERT_FALSE(r) << cut;
        EXPECT_EQ(r.status().code(), StatusCode::kTruncated) << cut;
    }
    auto bad_magic = rec;
    bad_magic[0] = 'X';
    EXPECT_EQ(decodeFrameRecord(bad_magic).status().code(), StatusCode::kProtocolError);
    FrameRecordHeader h = greyHeader();
    h.stride = 3;  // shorter than a line
    EXPECT_FALSE(decodeFrameRecord(encodeFrameRecord(h, payload)));
    h = greyHeader();
    EXPECT_FALSE(
        decodeFrameRecord(encodeFrameRecord(h, std::vector<std::uint8_t>(9))));  // 6 + 4 needed
    h.width = 0;
    EXPECT_FALSE(decodeFrameRecord(encodeFrameRecord(h, payload)));
    h = greyHeader();
    h.height = 1;
    h.stride = 0x11000000;  // found by fuzz_v4l2_record: a huge stride with one line
    EXPECT_FALSE(decodeFrameRecord(encodeFrameRecord(h, payload)));
    h = greyHeader();
    h.timestamp_ns = -1;  // found by fuzz_v4l2_record: shifting it overflowed
    EXPECT_FALSE(decodeFrameRecord(encodeFrameRecord(h, payload)));
    h = greyHeader();
    h.fourcc = transport::fourcc('R', 'G', 'G', 'B');
    auto unknown = decodeFrameRecord(encodeFrameRecord(h, payload));
    ASSERT_FALSE(unknown);
    EXPECT_NE(unknown.status().message().find("RGGB"), std::string::npos);
}

// Noisy bytes: every value 0..255 occurs, including alpha 0 in the YUYV case, where a PNG
// decoder that premultiplied or dropped "transparent" colour would change bytes.
std::vector<std::uint8_t> noiseBytes(std::size_t n, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<std::uint8_t> v(n);
    for (std::size_t i = 0; i < n; ++i)
        v[i] = static_cast<std::uint8_t>(i % 7 == 0 ? 0 : rng() & 0xFF);
    return v;
}

TEST(FrameRecordPng, GreyWithLinePaddingDecodesToTheExactBytes) {
    FrameRecordHeader h = greyHeader();
    h.width = 37;
    h.height = 11;
    h.stride = 40;  // 3 padding bytes per line, kept as they were
    const auto buffer = noiseBytes(40 * 11, 1);
    const auto rec = encodeFrameRecord(h, buffer, FrameCoding::kPng);
    EXPECT_EQ(rec[4], 2);                      // version 2
    EXPECT_EQ(rec[6], 64);                     // header size
    EXPECT_EQ(rec[56], 1);                     // coding PNG
    EXPECT_EQ(rec[24] | (rec[25] << 8), 440);  // bytesused is the buffer's size, not the PNG's
    const std::size_t stored = rec[60] | (rec[61] << 8) | (rec[62] << 16);
    ASSERT_EQ(rec.size(), 64 + stored);
    EXPECT_EQ(std::string(rec.begin() + 65, rec.begin() + 68), "PNG");  // a plain PNG file
    auto r = decodeFrameRecord(rec);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_EQ(r->coding, FrameCoding::kPng);
    EXPECT_EQ(r->record_size, rec.size());
    EXPECT_EQ(r->stored_size, stored);
    h.bytesused = 440;
    EXPECT_EQ(r->header, h);
    EXPECT_EQ(std::vector<std::uint8_t>(r->payload.begin(), r->payload.end()), buffer);
    // A copy of the view keeps the decoded bytes alive.
    FrameRecordView copy = *r;
    r = Status(StatusCode::kNotFound, "gone");
    EXPECT_EQ(std::vector<std::uint8_t>(copy.payload.begin(), copy.payload.end()), buffer);
    // Header only: the metadata without decoding the payload.
    auto head = decodeFrameRecord(rec, FramePayload::kHeaderOnly);
    ASSERT_TRUE(head);
    EXPECT_EQ(head->header, h);
    EXPECT_TRUE(head->payload.empty());
    EXPECT_EQ(head->record_size, rec.size());
}

TEST(FrameRecordPng, YuyvRoundTripsAndIsSmallerForImageLikeData) {
    FrameRecordHeader h = greyHeader();
    h.fourcc = transport::kFourccYuyv;
    h.width = 16;
    h.height = 8;
    h.stride = 32;
    const auto noise = noiseBytes(32 * 8, 2);
    auto r = decodeFrameRecord(encodeFrameRecord(h, noise, FrameCoding::kPng));
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_EQ(r->coding, FrameCoding::kPng);
    EXPECT_EQ(std::vector<std::uint8_t>(r->payload.begin(), r->payload.end()), noise);
    // A smooth grey ramp with a little noise, as a camera sees a wall: well under the raw size.
    h.fourcc = transport::kFourccGrey;
    h.width = h.stride = 320;
    h.height = 240;
    std::mt19937 rng(3);
    std::normal_distribution<double> sensor(0.0, 1.5);
    std::vector<std::uint8_t> wall(320 * 240);
    for (std::size_t i = 0; i < wall.size(); ++i) {
        wall[i] = static_cast<std::uint8_t>(
            std::clamp(60.0 + 0.3 * static_cast<double>(i % 320) + sensor(rng), 0.0, 255.0));
    }
    const auto rec = encodeFrameRecord(h, wall, FrameCoding::kPng);
    EXPECT_LT(rec.size(), wall.size() * 6 / 10);
    auto w = decodeFrameRecord(rec);
    ASSERT_TRUE(w);
    EXPECT_EQ(std::vector<std::uint8_t>(w->payload.begin(), w->payload.end()), wall);
}

TEST(FrameRecordPng, BuffersPngCannotHoldExactlyStayUncoded) {
    FrameRecordHeader h = greyHeader();  // 4x2, stride 6
    // The last line without its padding: 10 bytes, not 12.
    const std::vector<std::uint8_t> short_last = {1, 2, 3, 4, 0, 0, 5, 6, 7, 8};
    const auto rec = encodeFrameRecord(h, short_last, FrameCoding::kPng);
    EXPECT_EQ(rec, encodeFrameRecord(h, short_last));
    h.fourcc = transport::kFourccMjpeg;
    h.stride = 0;
    const std::vector<std::uint8_t> jpeg = {0xFF, 0xD8, 0xFF, 0xD9};
    EXPECT_EQ(encodeFrameRecord(h, jpeg, FrameCoding::kPng), encodeFrameRecord(h, jpeg));
    EXPECT_FALSE(canStorePng(h));
}

TEST(FrameRecordPng, DamagedCodedRecordsAreErrorsNotWrongPixels) {
    FrameRecordHeader h = greyHeader();
    h.width = h.stride = 24;
    h.height = 6;
    const auto buffer = noiseBytes(24 * 6, 4);
    const auto rec = encodeFrameRecord(h, buffer, FrameCoding::kPng);
    // Cut anywhere: incomplete, not misread.
    for (std::size_t cut : {60ul, 64ul, 80ul, rec.size() - 1}) {
        auto r = decodeFrameRecord(std::span<const std::uint8_t>(rec).first(cut));
        ASSERT_FALSE(r) << cut;
        EXPECT_EQ(r.status().code(), StatusCode::kTruncated) << cut;
    }
    // A flipped bit inside the PNG: its CRC (or zlib's Adler-32) fails.
    auto flipped = rec;
    flipped[rec.size() / 2] ^= 0x10;
    auto bad = decodeFrameRecord(flipped);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), StatusCode::kProtocolError);
    EXPECT_NE(bad.status().message().find("PNG payload"), std::string::npos)
        << bad.status().message();
    // The header claims another size than the PNG holds.
    auto taller = rec;
    taller[36] = 7;  // height 7, bytesused still 144
    EXPECT_FALSE(decodeFrameRecord(taller));
    FrameRecordHeader wider = h;
    wider.width = wider.stride = 36;
    wider.height = 4;  // same 144 bytes, other shape
    wider.bytesused = 144;
    std::vector<std::uint8_t> png(rec.begin() + 64, rec.end());
    std::vector<std::uint8_t> out;
    const Status s = decodePngPayload(wider, png, out);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("the header implies 36x4"), std::string::npos) << s.message();
    // Unknown coding.
    auto unknown = rec;
    unknown[56] = 9;
    EXPECT_NE(decodeFrameRecord(unknown).status().message().find("unknown payload coding 9"),
              std::string::npos);
}

}  // namespace
}  // namespace handscan::camera
