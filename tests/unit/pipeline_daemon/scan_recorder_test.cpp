// The daemon's per-scan raw recording (ScanRecorder): a driver thread writing into its tap while
// recordings start and stop never blocks and never writes into a finished file; each stretch is a
// readable MCAP with the raw channels; the disk budget refuses to start. And the calibration's
// file swap: the new file in place, the old one kept as .prev.
#include "handscan/pipeline_daemon/scan_recorder.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <thread>

#include "handscan/pipeline_daemon/calibrate_job.hpp"
#include "handscan/recording/mcap_reader.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

class ScanRecorderTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("handscan_scan_recorder_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    fs::path dir_;
};

std::uint64_t messagesIn(const std::string& path, const std::string& topic) {
    auto reader = recording::McapReader::open(path);
    EXPECT_TRUE(reader.isOk()) << path;
    if (!reader.isOk()) return 0;
    EXPECT_FALSE((*reader)->truncated()) << path;  // finished with its footer
    std::uint64_t n = 0;
    recording::ReadOptions only;
    only.topics = {topic};
    EXPECT_TRUE(
        (*reader)->forEachMessage(only, [&](const recording::RecordedMessage&) { ++n; }).isOk());
    return n;
}

TEST_F(ScanRecorderTest, StretchesRecordedWhileADriverKeepsWriting) {
    ScanRecorder recorder({true, 0});
    std::atomic<bool> stop{false};
    std::atomic<std::uint64_t> offered{0};
    std::thread driver([&] {
        const std::uint8_t bytes[64] = {1, 2, 3};
        for (TimeNs t = 1; !stop.load(); ++t) {
            recorder.hokuyoTap()->onRaw(t, bytes);
            offered.fetch_add(1);
            std::this_thread::sleep_for(std::chrono::microseconds(200));
        }
    });
    for (int stretch = 0; stretch < 3; ++stretch) {
        const std::string said = recorder.start(dir_.string());
        EXPECT_NE(said.find("recording the raw streams to raw"), std::string::npos) << said;
        EXPECT_TRUE(recorder.recording());
        std::this_thread::sleep_for(std::chrono::milliseconds(60));
        auto stopped = recorder.stop();
        ASSERT_TRUE(stopped.isOk()) << stopped.status().message();
        EXPECT_NE(stopped->find(" 0 dropped"), std::string::npos) << *stopped;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // not recorded
    }
    stop = true;
    driver.join();
    EXPECT_TRUE(fs::exists(dir_ / "raw.mcap"));
    EXPECT_TRUE(fs::exists(dir_ / "raw-2.mcap"));
    EXPECT_TRUE(fs::exists(dir_ / "raw-3.mcap"));
    std::uint64_t recorded = 0;
    for (const char* f : {"raw.mcap", "raw-2.mcap", "raw-3.mcap"}) {
        const std::uint64_t n = messagesIn((dir_ / f).string(), "/hokuyo/raw");
        EXPECT_GT(n, 20u) << f;
        recorded += n;
    }
    EXPECT_LT(recorded, offered.load());  // what came between the stretches went nowhere
    EXPECT_EQ(scanRecording(dir_.string()).empty(), false);
}

TEST_F(ScanRecorderTest, SwitchedOffOrShortOfSpaceNothingIsRecorded) {
    ScanRecorder off({false, 0});
    EXPECT_NE(off.start(dir_.string()).find("storage.record_scans: false"), std::string::npos);
    ScanRecorder full({true, ~0ull >> 1});
    const std::string said = full.start(dir_.string());
    EXPECT_NE(said.find("storage.min_free_gib"), std::string::npos) << said;
    EXPECT_FALSE(full.recording());
    EXPECT_TRUE(fs::is_empty(dir_));
    EXPECT_EQ(scanRecording(dir_.string()), "");
}

TEST_F(ScanRecorderTest, InstallKeepsThePreviousFile) {
    const fs::path target = dir_ / "calibration.yaml", fresh = dir_ / "calibration.yaml.new";
    std::ofstream(target) << "old\n";
    std::ofstream(fresh) << "new\n";
    ASSERT_TRUE(installKeepingPrevious(fresh.string(), target.string()).isOk());
    std::string a, b;
    std::ifstream(target) >> a;
    std::ifstream(dir_ / "calibration.yaml.prev") >> b;
    EXPECT_EQ(a, "new");
    EXPECT_EQ(b, "old");
    EXPECT_FALSE(fs::exists(fresh));
    // Missing fresh file: a clear error, the current file untouched.
    const Status s = installKeepingPrevious(fresh.string(), target.string());
    EXPECT_FALSE(s.isOk());
    EXPECT_NE(s.message().find("calibration.yaml"), std::string::npos) << s.message();
    std::ifstream(target) >> a;
    EXPECT_EQ(a, "new");
}

TEST_F(ScanRecorderTest, TheFieldCalibrationOnceWrittenIsTheOneInUse) {
    const fs::path factory = dir_ / "etc" / "calibration.yaml";
    const fs::path field = dir_ / "var" / "calibration.yaml";
    EXPECT_EQ(calibrationInUse(factory.string(), ""), factory.string());
    EXPECT_EQ(calibrationInUse(factory.string(), field.string()), factory.string());
    fs::create_directories(field);  // a directory of that name is no calibration
    EXPECT_EQ(calibrationInUse(factory.string(), field.string()), factory.string());
    fs::remove(field);
    std::ofstream(field) << "T_shaft_laser: {}\n";
    EXPECT_EQ(calibrationInUse(factory.string(), field.string()), field.string());
}

}  // namespace
}  // namespace handscan::pipeline_daemon
