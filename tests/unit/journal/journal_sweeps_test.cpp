// Per-sweep statistics in the journal (ChunkKind::kSweepStats): written and read back field by
// field; a journal without them (older firmware) still reads; a damaged statistics chunk or
// record is named with where it is and skipped, and the points and poses after it are all read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "handscan/journal/journal_format.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::journal {
namespace {

namespace fs = std::filesystem;

SweepRecord record(int k) {
    SweepRecord r;
    r.t_start_s = 100.0 + 0.5 * k;
    r.index = static_cast<std::uint64_t>(k);
    r.solved_mask = k == 3 ? 0x37 : 0x3F;
    r.vio_mask = k == 3 ? 0x08 : 0;
    r.tracking = k == 4 ? SweepTracking::kLost : SweepTracking::kOk;
    r.in_map = k != 4;
    r.vio = k == 2 ? SweepVio::kBypassed : SweepVio::kRunning;
    r.points = 20000u + static_cast<std::uint32_t>(k);
    r.edges = 300;
    r.planars = 2000;
    r.associations = 1800 - k;
    r.rms_m = 0.012;
    r.total_ms = 31.5;
    r.pose[0] = k;
    r.pose[6] = 1;
    r.prior_xyz[1] = -k;
    r.devices = {0.5, 20, 100, 100, 0, 5};
    if (k == 4) r.tracking_reason = "poor_fit";
    return r;
}

class JournalSweepsTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("handscan_journal_sweeps_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        path_ = (dir_ / "journal.hsj").string();
    }
    void TearDown() override { fs::remove_all(dir_); }

    // Five flushes, each: two poses, one sweep record, 100 points. Returns each statistics
    // chunk's offset in the file.
    std::vector<std::uint64_t> write(bool with_sweeps) {
        std::vector<std::uint64_t> stats_at;
        auto w = JournalWriter::create(path_, "{}");
        EXPECT_TRUE(w.isOk());
        for (int k = 0; k < 5; ++k) {
            EXPECT_TRUE((*w)->appendPose({100.0 + 0.5 * k, 0, 0, 0, 0, 0, 0, 1}).isOk());
            EXPECT_TRUE((*w)->appendPose({100.25 + 0.5 * k, 0, 0, 0, 0, 0, 0, 1}).isOk());
            if (with_sweeps) {
                EXPECT_TRUE((*w)->appendSweep(record(k)).isOk());
            }
            std::vector<MapPoint> pts(100, MapPoint{100.0 + 0.5 * k, 1, 2, 3, 4, 5, 6, 7});
            EXPECT_TRUE((*w)->appendPoints(pts).isOk());
            // Header, poses (2 x 64 bytes), then the statistics chunk.
            stats_at.push_back(fs::file_size(path_) + kChunkHeaderBytes + 2 * kPoseRecordBytes);
            EXPECT_TRUE((*w)->flush().isOk());
        }
        EXPECT_TRUE((*w)->finish().isOk());
        return stats_at;
    }
    void flipByte(std::uint64_t offset) {
        std::fstream f(path_, std::ios::in | std::ios::out | std::ios::binary);
        f.seekg(static_cast<std::streamoff>(offset));
        char c = 0;
        f.read(&c, 1);
        c = static_cast<char>(c ^ 0x5A);
        f.seekp(static_cast<std::streamoff>(offset));
        f.write(&c, 1);
    }
    fs::path dir_;
    std::string path_;
};

TEST(SweepRecordFormat, EveryFieldRoundTrips) {
    std::vector<SweepRecord> in = {record(3), record(4)};
    std::vector<std::uint8_t> bytes;
    encodeSweeps(in, bytes);
    EXPECT_EQ(bytes.size(), 2 * kSweepRecordBytes + 8);  // "poor_fit" once
    std::vector<SweepRecord> out;
    EXPECT_EQ(decodeSweeps(bytes, out), "");
    ASSERT_EQ(out.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        const SweepRecord &a = in[i], &b = out[i];
        EXPECT_EQ(a.t_start_s, b.t_start_s);
        EXPECT_EQ(a.index, b.index);
        EXPECT_EQ(a.solved_mask, b.solved_mask);
        EXPECT_EQ(a.vio_mask, b.vio_mask);
        EXPECT_EQ(a.tracking, b.tracking);
        EXPECT_EQ(a.in_map, b.in_map);
        EXPECT_EQ(a.vio, b.vio);
        EXPECT_EQ(a.points, b.points);
        EXPECT_EQ(a.associations, b.associations);
        EXPECT_EQ(a.rms_m, b.rms_m);
        EXPECT_EQ(a.total_ms, b.total_ms);
        for (int j = 0; j < 7; ++j) EXPECT_EQ(a.pose[j], b.pose[j]);
        for (int j = 0; j < 3; ++j) EXPECT_EQ(a.prior_xyz[j], b.prior_xyz[j]);
        EXPECT_EQ(a.devices.window_s, b.devices.window_s);
        EXPECT_EQ(a.devices.imu_samples, b.devices.imu_samples);
        EXPECT_EQ(a.devices.tracking_frames, b.devices.tracking_frames);
        EXPECT_EQ(a.tracking_reason, b.tracking_reason);
    }
    EXPECT_EQ(out[0].degenerateDirections(), 1);
}

// A later layout may append fields: this reader takes the ones it knows and the reason (the
// record's last bytes).
TEST(SweepRecordFormat, ALongerRecordOfALaterLayoutReads) {
    std::vector<std::uint8_t> bytes;
    encodeSweeps(std::vector<SweepRecord>{record(4)}, bytes);
    bytes.insert(bytes.begin() + kSweepRecordBytes, 12, 0xEE);  // new fields before the reason
    bytes[0] = static_cast<std::uint8_t>(bytes.size());
    bytes[2] = 2;  // layout 2
    std::vector<SweepRecord> out;
    EXPECT_EQ(decodeSweeps(bytes, out), "");
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].tracking_reason, "poor_fit");
    EXPECT_EQ(out[0].devices.tracking_frames, 5u);
}

TEST(SweepRecordFormat, ATruncatedRecordIsNamedAndTheOnesBeforeKept) {
    std::vector<std::uint8_t> bytes;
    encodeSweeps(std::vector<SweepRecord>{record(0), record(1), record(2)}, bytes);
    bytes.resize(bytes.size() - 30);
    std::vector<SweepRecord> out;
    const std::string bad = decodeSweeps(bytes, out);
    EXPECT_EQ(out.size(), 2u);
    EXPECT_NE(bad.find("record 2 at payload byte 336"), std::string::npos) << bad;
    EXPECT_NE(bad.find("truncated"), std::string::npos) << bad;
}

TEST_F(JournalSweepsTest, WrittenAndReadBackInOrder) {
    write(true);
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const JournalSummary& s = r->summary();
    ASSERT_EQ(s.sweeps.size(), 5u);
    for (int k = 0; k < 5; ++k) EXPECT_EQ(s.sweeps[k].index, static_cast<std::uint64_t>(k));
    EXPECT_EQ(s.sweeps[4].tracking_reason, "poor_fit");
    EXPECT_TRUE(s.sweep_damage.empty());
    EXPECT_EQ(s.points, 500u);
    EXPECT_TRUE(s.finished);
}

TEST_F(JournalSweepsTest, AJournalWithoutThemStillReads) {
    write(false);
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_TRUE(r->summary().sweeps.empty());
    EXPECT_TRUE(r->summary().sweep_damage.empty());
    EXPECT_EQ(r->summary().points, 500u);
    EXPECT_TRUE(r->summary().damage.empty());
}

// A flipped byte inside the third statistics chunk's payload: that chunk is named (chunk number
// and byte offset) and left out; every point and pose, the later sweeps and the end of scan read.
TEST_F(JournalSweepsTest, ACorruptStatisticsChunkIsSkippedWithWhere) {
    const auto stats_at = write(true);
    flipByte(stats_at[2] + kChunkHeaderBytes + 20);
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const JournalSummary& s = r->summary();
    ASSERT_EQ(s.sweep_damage.size(), 1u);
    EXPECT_NE(s.sweep_damage[0].find("at byte " + std::to_string(stats_at[2])), std::string::npos)
        << s.sweep_damage[0];
    EXPECT_NE(s.sweep_damage[0].find("CRC"), std::string::npos) << s.sweep_damage[0];
    ASSERT_EQ(s.sweeps.size(), 4u);
    EXPECT_EQ(s.sweeps[2].index, 3u);
    EXPECT_EQ(s.points, 500u);
    EXPECT_EQ(s.trajectory.size(), 10u);
    EXPECT_TRUE(s.finished);
    EXPECT_TRUE(s.damage.empty()) << s.damage;
    std::uint64_t n = 0;
    ASSERT_TRUE(r->forEachPoints([&](std::span<const MapPoint> p) { n += p.size(); }).isOk());
    EXPECT_EQ(n, 500u);
    // Recovery keeps the whole file (nothing after the bad chunk is cut).
    auto rec = recoverJournal(path_);
    ASSERT_TRUE(rec.isOk());
    EXPECT_EQ(rec->good_bytes, rec->file_bytes);
}

// The file cut inside the last statistics chunk (power cut mid-write): everything before it.
TEST_F(JournalSweepsTest, ATruncatedStatisticsChunkAtTheEndKeepsWhatCameBefore) {
    const auto stats_at = write(true);
    fs::resize_file(path_, stats_at[4] + kChunkHeaderBytes + 50);
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const JournalSummary& s = r->summary();
    EXPECT_NE(s.damage.find("at byte " + std::to_string(stats_at[4])), std::string::npos)
        << s.damage;
    EXPECT_NE(s.damage.find("truncated payload"), std::string::npos) << s.damage;
    EXPECT_EQ(s.sweeps.size(), 4u);
    EXPECT_EQ(s.points, 400u);
    EXPECT_EQ(s.trajectory.size(), 10u);
}

}  // namespace
}  // namespace handscan::journal
