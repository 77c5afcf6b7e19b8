// The daemon in this process with its real device threads and transports: a fake Hokuyo on
// loopback TCP, a fake Xsens on a pty, the motor on the emulated CANopen bus (no CAN in this
// kernel), the cameras and the GPIO chip absent. The test plays the UI through the shared-memory
// command channel: start -> poses in the pose ring, points in the journal; stop; export to a
// directory (progress acks, "safe to remove", files readable); export to a USB stick that is not
// there (a clear failure); new scan -> new epoch, new journal; the laser killed mid-scan -> its
// status shows it lost while poses go on; shutdown -> journal finished and recoverable.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "daemon_rig.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon::test {
namespace {

using shm::CommandState;
using shm::CommandType;

std::uint64_t plyVertexCount(const fs::path& ply) {
    std::ifstream in(ply, std::ios::binary);
    for (std::string line; std::getline(in, line) && line != "end_header";) {
        if (line.rfind("element vertex ", 0) == 0) return std::stoull(line.substr(15));
    }
    return 0;
}

TEST(PipelineDaemonFlow, ScanStopExportNewScanSensorLostShutdown) {
    DaemonRig rig("flow");
    fs::create_directories(rig.dir() / "no-usb");
    std::ofstream(rig.dir() / "no-usb" / "mountinfo") << "";  // a mount table without any stick
    DaemonOptions o;
    o.device_config = rig.deviceYaml();
    o.calibration = DaemonRig::calibrationYaml();
    o.shm_name = rig.shmName();
    o.map_capacity_points = 1 << 18;
    o.usb_paths.mountinfo = (rig.dir() / "no-usb" / "mountinfo").string();
    PipelineDaemon daemon(o);
    ASSERT_TRUE(daemon.open().isOk());
    DaemonThread running(daemon);

    // Every device came up through its real driver; the absent GPIO chip is reported.
    auto up = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return sensorConnected(s, "hokuyo") && sensorConnected(s, "xsens") &&
                   sensorConnected(s, "encoder");
        },
        10.0);
    ASSERT_TRUE(up) << "devices did not come up";
    const shm::SensorStatus* buttons = findSensor(*up, "buttons");
    ASSERT_NE(buttons, nullptr);
    EXPECT_FALSE(buttons->connected);
    EXPECT_NE(shm::getText(buttons->last_error).find("handscan-test-no-such-chip"),
              std::string::npos)
        << shm::getText(buttons->last_error);
    EXPECT_EQ(up->scan_state, static_cast<std::uint8_t>(shm::ScanState::kIdle));

    // Start: poses in the ring, points in the journal.
    auto ack = rig.command(CommandType::kStartScan);
    ASSERT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone))
        << shm::getText(ack.message);
    const std::uint64_t poses_at_start = rig.ui().poseCount();
    auto scanned =
        rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 20000; }, 15.0);
    ASSERT_TRUE(scanned) << "no points registered";
    EXPECT_EQ(scanned->scan_state, static_cast<std::uint8_t>(shm::ScanState::kScanning));
    EXPECT_GT(rig.ui().poseCount(), poses_at_start + 100);  // 200 Hz poses
    auto pose = rig.ui().latestPose();
    ASSERT_TRUE(pose);
    EXPECT_NEAR(pose->position_m[2], 0.0, 0.5);  // at rest: the device has not gone anywhere

    // Stop: the journal holds exactly what the status counted.
    const auto live_before_stop = rig.ui().latestPose();
    ASSERT_TRUE(live_before_stop);
    ack = rig.command(CommandType::kStopScan);
    ASSERT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone))
        << shm::getText(ack.message);
    auto stopped = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kStopped);
        },
        2.0);
    ASSERT_TRUE(stopped);
    ASSERT_EQ(rig.scanDirs().size(), 1u);
    const fs::path journal = rig.scanDirs()[0] / "journal.hsj";
    {
        auto j = journal::JournalReader::open(journal.string());
        ASSERT_TRUE(j.isOk()) << j.status().message();
        EXPECT_EQ(j->summary().points, stopped->point_count);
        ASSERT_GT(j->summary().trajectory.size(), 100u);
        // The kept trajectory runs a sweep or two behind the live one: the stop hands on what
        // no match has closed yet, so the journal holds every pose shown before the stop.
        EXPECT_GE(j->summary().trajectory.back().t_s,
                  static_cast<double>(live_before_stop->t_ns) * 1e-9 - 1e-6);
        EXPECT_TRUE(j->summary().damage.empty()) << j->summary().damage;
    }

    // Export through the command: progress, then done, files there and complete.
    std::vector<CommandState> seen;
    const fs::path target = rig.dir() / "export";
    fs::create_directories(target);
    ack = rig.command(CommandType::kExport, target.string(), &seen);
    ASSERT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone))
        << shm::getText(ack.message);
    EXPECT_NE(std::find(seen.begin(), seen.end(), CommandState::kInProgress), seen.end());
    // The export runs on its own thread; under ASan it alone takes about 2 s, so the wait
    // bounds a hang, not the export's speed.
    auto exported = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.export_status.state == static_cast<std::uint8_t>(shm::ExportState::kDone);
        },
        30.0);
    ASSERT_TRUE(exported);
    EXPECT_EQ(exported->export_status.safe_to_remove, 1);
    std::vector<fs::path> plys, lases;
    for (const auto& e : fs::recursive_directory_iterator(target)) {
        if (e.path().extension() == ".ply") plys.push_back(e.path());
        if (e.path().extension() == ".las") lases.push_back(e.path());
    }
    ASSERT_EQ(plys.size(), 1u);
    ASSERT_EQ(lases.size(), 1u);
    EXPECT_EQ(plyVertexCount(plys[0]), stopped->point_count);

    // "Export to USB" without a stick: refused with a clear reason, the journal untouched.
    ack = rig.command(CommandType::kExport, "usb");
    EXPECT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kFailed));
    EXPECT_NE(std::string(shm::getText(ack.message)).find("USB"), std::string::npos)
        << shm::getText(ack.message);

    // New scan: the display map's epoch changes, the next start journals into a new directory.
    shm::MapCursor cursor;
    shm::MapDelta delta;
    ASSERT_TRUE(rig.ui().readMap(cursor, delta));
    EXPECT_GT(delta.points.size(), 100u);
    ack = rig.command(CommandType::kNewScan);
    ASSERT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone))
        << shm::getText(ack.message);
    ASSERT_TRUE(rig.ui().readMap(cursor, delta));
    EXPECT_TRUE(delta.reset);
    ack = rig.command(CommandType::kStartScan);
    ASSERT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone))
        << shm::getText(ack.message);
    EXPECT_EQ(rig.scanDirs().size(), 2u);
    EXPECT_EQ(rig.command(CommandType::kExport, target.string()).state,
              static_cast<std::uint32_t>(CommandState::kRejected));

    // The laser dies mid-scan: reported lost, the daemon and the IMU poses go on. (The new scan
    // aligns with gravity first; under ASan with another test beside it that took over 10 s.)
    ASSERT_TRUE(rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 0; }, 30.0));
    rig.killHokuyo();
    // The wait bounds a hang: under ASan the report took over 6 s once.
    auto lost = rig.waitStatus(
        [](const shm::StatusBlock& s) { return !sensorConnected(s, "hokuyo"); }, 20.0);
    ASSERT_TRUE(lost) << "the dead laser is not reported";
    const shm::SensorStatus* h = findSensor(*lost, "hokuyo");
    ASSERT_NE(h, nullptr);
    const std::uint64_t poses_after_loss = rig.ui().poseCount();
    auto still = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return !std::string(shm::getText(findSensor(s, "hokuyo")->last_error)).empty();
        },
        5.0);
    ASSERT_TRUE(still);
    EXPECT_NE(std::string(shm::getText(findSensor(*still, "hokuyo")->last_error)).find("127.0.0.1"),
              std::string::npos)
        << shm::getText(findSensor(*still, "hokuyo")->last_error);
    EXPECT_TRUE(sensorConnected(*still, "xsens"));
    EXPECT_EQ(still->scan_state, static_cast<std::uint8_t>(shm::ScanState::kScanning));
    EXPECT_TRUE(rig.waitStatus(
        [&](const shm::StatusBlock&) { return rig.ui().poseCount() > poses_after_loss + 50; }, 3.0))
        << "poses stopped with the laser";

    // Shutdown: acknowledged, the daemon ends cleanly, both journals are finished and intact.
    ack = rig.command(CommandType::kShutdown);
    EXPECT_EQ(ack.state, static_cast<std::uint32_t>(CommandState::kDone));
    const Status result = running.join();
    EXPECT_TRUE(result.isOk()) << result.message();
    for (const fs::path& scan : rig.scanDirs()) {
        auto j = journal::JournalReader::open((scan / "journal.hsj").string());
        ASSERT_TRUE(j.isOk()) << j.status().message();
        EXPECT_TRUE(j->summary().finished) << scan;
        EXPECT_TRUE(j->summary().damage.empty()) << j->summary().damage;
    }
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
