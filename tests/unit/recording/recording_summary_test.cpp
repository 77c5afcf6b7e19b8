// `handscan info`'s numbers: counts, rates, durations and gaps of each channel, computed from a
// recording with known rates and known holes, and the truncation flag.
#include "handscan/recording/recording_summary.hpp"

#include <gtest/gtest.h>

#include <sstream>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"
#include "mcap_test_util.hpp"

namespace handscan::recording {
namespace {

// IMU at 200 Hz for 10 s with messages 1000..1002 lost (one 20 ms gap), laser at 40 Hz for
// 10 s, and a ground-truth channel with a single message.
std::vector<std::uint8_t> makeRecording() {
    McapWriterOptions o;
    o.chunk_size_bytes = 16 * 1024;
    auto w = McapWriter::inMemory(o);
    const auto imu = *(*w)->addChannel("/imu/samples", "handscan.imu_sample.v1");
    const auto laser = *(*w)->addChannel("/laser/scans", "handscan.laser_scan.v1");
    const auto gt = *(*w)->addChannel("/groundtruth/pose", "handscan.groundtruth_pose.v1");
    const TimeNs t0 = 7 * kNsPerSec;
    std::vector<std::uint8_t> data(70, 1);
    for (int i = 0; i < 2000; ++i) {
        if (i % 5 == 0) {
            EXPECT_TRUE((*w)->write(laser, t0 + i * 5 * kNsPerMs + kNsPerMs,
                                    std::vector<std::uint8_t>(500, 2)));
        }
        if (i >= 1000 && i <= 1002) continue;
        EXPECT_TRUE((*w)->write(imu, t0 + i * 5 * kNsPerMs, data));
    }
    EXPECT_TRUE((*w)->write(gt, t0 + 3 * kNsPerSec, std::vector<std::uint8_t>(64, 3)));
    EXPECT_TRUE((*w)->close());
    return (*w)->takeBuffer();
}

TEST(RecordingSummary, CountsRatesAndGaps) {
    auto r = McapReader::fromBuffer(makeRecording(), "office.mcap");
    ASSERT_TRUE(r);
    auto s = summarizeRecording(**r);
    ASSERT_TRUE(s) << s.status().message();
    EXPECT_EQ(s->messages, 1997u + 400u + 1u);
    EXPECT_FALSE(s->truncated);
    EXPECT_TRUE(s->indexed);
    ASSERT_EQ(s->channels.size(), 3u);

    const auto& imu = s->channels[0];
    EXPECT_EQ(imu.topic, "/imu/samples");
    EXPECT_EQ(imu.messages, 1997u);
    EXPECT_EQ(imu.bytes, 1997u * 70);
    EXPECT_EQ(imu.first, 7 * kNsPerSec);
    EXPECT_EQ(imu.last, 7 * kNsPerSec + 1999 * 5 * kNsPerMs);
    EXPECT_DOUBLE_EQ(imu.rate_hz, 1996.0 / 9.995);  // (n - 1) intervals over the span
    EXPECT_EQ(imu.median_period_ns, 5 * kNsPerMs);
    EXPECT_EQ(imu.largest_gap_ns, 20 * kNsPerMs);
    EXPECT_EQ(imu.largest_gap_after, 7 * kNsPerSec + 999 * 5 * kNsPerMs);
    EXPECT_EQ(imu.gaps, 1u);

    const auto& laser = s->channels[1];
    EXPECT_EQ(laser.messages, 400u);
    EXPECT_NEAR(laser.rate_hz, 40.0, 1e-9);
    EXPECT_EQ(laser.median_period_ns, 25 * kNsPerMs);
    EXPECT_EQ(laser.gaps, 0u);  // 20 ms of lost IMU does not touch the laser

    const auto& gt = s->channels[2];
    EXPECT_EQ(gt.messages, 1u);
    EXPECT_EQ(gt.rate_hz, 0.0);
    EXPECT_EQ(s->start, 7 * kNsPerSec);
    EXPECT_EQ(s->duration(), 1999 * 5 * kNsPerMs);  // first to last IMU sample

    std::ostringstream json;
    printSummaryJson(*s, json);
    EXPECT_NE(json.str().find(
                  "\"topic\":\"/imu/"
                  "samples\",\"message_encoding\":\"handscan.imu_sample.v1\",\"messages\":1997,"),
              std::string::npos)
        << json.str();
    EXPECT_NE(json.str().find("\"truncated\":false,\"recovered\":false"), std::string::npos);
    ASSERT_TRUE(checkRecordingCrcs(**r, *s));
    EXPECT_EQ(s->crc_problems, "");
    std::ostringstream text;
    printSummaryText(*s, text);
    EXPECT_NE(text.str().find("office.mcap: "), std::string::npos);
    EXPECT_NE(text.str().find("CRC check: every CRC matches"), std::string::npos);
    EXPECT_NE(text.str().find("/laser/scans"), std::string::npos);
    EXPECT_EQ(text.str().find("TRUNCATED"), std::string::npos);
}

TEST(RecordingSummary, TruncatedFileIsFlaggedAndCountsWhatSurvived) {
    auto bytes = makeRecording();
    const auto chunks = test::recordsWithOp(bytes, 0x06);
    ASSERT_GT(chunks.size(), 4u);
    bytes.resize(chunks[3].offset + chunks[3].size / 2);
    auto r = McapReader::fromBuffer(bytes, "cut.mcap");
    ASSERT_TRUE(r);
    auto s = summarizeRecording(**r);
    ASSERT_TRUE(s);
    EXPECT_TRUE(s->truncated);
    EXPECT_EQ(s->messages, test::readAll(**r).size());
    EXPECT_GT(s->messages, 0u);
    ASSERT_EQ(s->dropped.size(), 1u);
    EXPECT_EQ(s->dropped[0].offset, chunks[3].offset);
    ASSERT_TRUE(checkRecordingCrcs(**r, *s));
    EXPECT_TRUE(s->crc_checked);
    EXPECT_NE(s->crc_problems.find("no Data End record (file cut short)"), std::string::npos)
        << s->crc_problems;
    std::ostringstream text;
    printSummaryText(*s, text);
    EXPECT_NE(text.str().find("TRUNCATED"), std::string::npos);
    EXPECT_NE(text.str().find("CRC check: cut.mcap: "), std::string::npos) << text.str();
    std::ostringstream json;
    printSummaryJson(*s, json);
    EXPECT_NE(json.str().find("\"truncated\":true,\"recovered\":true,\"dropped\":[{\"offset\":" +
                              std::to_string(chunks[3].offset)),
              std::string::npos)
        << json.str();
}

}  // namespace
}  // namespace handscan::recording
