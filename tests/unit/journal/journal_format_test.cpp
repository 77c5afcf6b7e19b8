#include "handscan/journal/journal_format.hpp"

#include <gtest/gtest.h>

namespace handscan::journal {
namespace {

TEST(JournalFormat, HeaderRoundTripAndCorruptionDetected) {
    ChunkHeader h;
    h.kind = ChunkKind::kPoints;
    h.sequence = 42;
    h.record_count = 7;
    h.payload_bytes = 7 * kPointRecordBytes;
    h.t_last_s = 123.25;
    h.payload_crc = 0xDEADBEEF;
    std::vector<std::uint8_t> bytes = encodeHeader(h);
    ASSERT_EQ(bytes.size(), kChunkHeaderBytes);
    ChunkHeader back;
    ASSERT_TRUE(decodeHeader(bytes, back));
    EXPECT_EQ(back.sequence, 42u);
    EXPECT_EQ(back.kind, ChunkKind::kPoints);
    EXPECT_EQ(back.t_last_s, 123.25);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        std::vector<std::uint8_t> bad = bytes;
        bad[i] ^= 0x10;
        EXPECT_FALSE(decodeHeader(bad, back)) << "flipped bit in byte " << i << " not detected";
    }
}

TEST(JournalFormat, CrcMatchesTheStandardCheckValue) {
    const std::string s = "123456789";
    EXPECT_EQ(crc32(std::span(reinterpret_cast<const std::uint8_t*>(s.data()), s.size())),
              0xCBF43926u);
}

TEST(JournalFormat, PointsAndPosesRoundTrip) {
    std::vector<MapPoint> pts{{1.5, 1.f, -2.f, 3.5f, 10, 20, 30, 400},
                              {2.0, 0.f, 0.f, 0.f, 255, 0, 1, 65535}};
    std::vector<std::uint8_t> bytes;
    encodePoints(pts, bytes);
    ASSERT_EQ(bytes.size(), 2 * kPointRecordBytes);
    std::vector<MapPoint> back;
    decodePoints(bytes, back);
    ASSERT_EQ(back.size(), 2u);
    EXPECT_EQ(back[0].t_s, 1.5);
    EXPECT_EQ(back[0].z, 3.5f);
    EXPECT_EQ(back[1].r, 255);
    EXPECT_EQ(back[1].intensity, 65535);
    std::vector<TrajectoryPose> poses{{1.0, 1, 2, 3, 0, 0, 0.6, 0.8}};
    bytes.clear();
    encodePoses(poses, bytes);
    std::vector<TrajectoryPose> poses_back;
    decodePoses(bytes, poses_back);
    ASSERT_EQ(poses_back.size(), 1u);
    EXPECT_EQ(poses_back[0].qz, 0.6);
    EXPECT_EQ(poses_back[0].z, 3.0);
}

}  // namespace
}  // namespace handscan::journal
