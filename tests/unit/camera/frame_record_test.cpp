#include <gtest/gtest.h>

#include "handscan/camera/frame_record.hpp"
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
    EXPECT_FALSE(decodeFrameRecord(encodeFrameRecord(h, std::vector<std::uint8_t>(9))));  // 6 + 4 needed
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

}  // namespace
}  // namespace handscan::camera
