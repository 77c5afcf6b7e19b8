// What the status bar says for a given status block: numbers formatted for the operator, and a
// warning for each condition they can act on.
#include "handscan/ui/status_texts.hpp"

#include <gtest/gtest.h>

#include "handscan/shm/text_field.hpp"

namespace handscan::ui {
namespace {

bool hasWarning(const StatusTexts& t, const std::string& start) {
    for (const Line& w : t.warnings) {
        if (w.text.rfind(start, 0) == 0) return true;
    }
    return false;
}

shm::StatusBlock healthyScan() {
    shm::StatusBlock s;
    s.sensor_count = 2;
    shm::setText(s.sensors[0].name, "hokuyo");
    s.sensors[0].connected = 1;
    s.sensors[0].rate_hz = 40.0f;
    s.sensors[0].expected_rate_hz = 40.0f;
    shm::setText(s.sensors[1].name, "xsens");
    s.sensors[1].connected = 1;
    s.sensors[1].rate_hz = 199.6f;
    s.sensors[1].expected_rate_hz = 200.0f;
    s.module_count = 1;
    shm::setText(s.modules[0].name, "scan-match");
    s.modules[0].state = static_cast<std::uint8_t>(shm::ModuleState::kActive);
    s.scan_state = static_cast<std::uint8_t>(shm::ScanState::kScanning);
    s.elapsed_s = 125.7;
    s.distance_m = 12.34;
    s.point_count = 1234567;
    s.free_storage_bytes = 12ull << 30;
    s.total_storage_bytes = 58ull << 30;
    s.linear_speed_mps = 0.8f;
    s.camera_brightness = 120.0f;
    return s;
}

TEST(StatusTexts, FormatsNumbersForTheOperator) {
    EXPECT_EQ(groupThousands(0), "0");
    EXPECT_EQ(groupThousands(999), "999");
    EXPECT_EQ(groupThousands(1234567), "1,234,567");
    EXPECT_EQ(formatDuration(125.7), "02:05");
    EXPECT_EQ(formatDuration(3725), "1:02:05");
    EXPECT_EQ(formatBytes(12.0 * (1ull << 30)), "12.0 GiB");
    EXPECT_EQ(formatBytes(512.0 * (1 << 20)), "512 MiB");
    EXPECT_EQ(dofList(0b101000), "tx+tz");
    EXPECT_EQ(dofList(0), "");
}

TEST(StatusTexts, HealthyScanHasNoWarnings) {
    const StatusTexts t =
        describeStatus(shm::Connection::kConnected, "", healthyScan(), std::nullopt);
    EXPECT_EQ(t.connection.text, "connected");
    EXPECT_EQ(t.scan_state, "SCANNING");
    EXPECT_EQ(t.elapsed, "02:05");
    EXPECT_EQ(t.distance, "12.3 m");
    EXPECT_EQ(t.points, "1,234,567 points");
    EXPECT_EQ(t.storage.text, "free 12.0 GiB of 58.0 GiB");
    ASSERT_EQ(t.sensors.size(), 2u);
    EXPECT_EQ(t.sensors[0].text, "hokuyo 40.0 Hz");
    EXPECT_EQ(t.sensors[1].text, "xsens 199.6 Hz");
    EXPECT_EQ(t.sensors[1].health, Health::kOk);
    ASSERT_EQ(t.modules.size(), 1u);
    EXPECT_EQ(t.modules[0].text, "scan-match active");
    EXPECT_TRUE(t.warnings.empty()) << t.warnings[0].text;
    EXPECT_FALSE(t.dof_valid);
}

TEST(StatusTexts, EachActionableConditionWarns) {
    shm::StatusBlock s = healthyScan();
    s.sensors[1].connected = 0;
    shm::setText(s.sensors[1].last_error, "/dev/ttyUSB0: no data for 2 s");
    s.modules[0].degenerate_dof_mask = 0b001000;
    s.linear_speed_mps = 2.4f;
    s.sensor_count = 3;  // the dark-camera warning needs a camera that runs
    shm::setText(s.sensors[2].name, "tracking-cam");
    s.sensors[2].connected = 1;
    s.sensors[2].rate_hz = s.sensors[2].expected_rate_hz = 50.0f;
    s.camera_brightness = 6.0f;
    s.free_storage_bytes = 100ull << 20;
    const StatusTexts t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    EXPECT_EQ(t.sensors[1].text, "xsens LOST");
    EXPECT_EQ(t.sensors[1].health, Health::kError);
    EXPECT_TRUE(hasWarning(t, "Sensor lost: xsens (/dev/ttyUSB0: no data for 2 s)"));
    EXPECT_TRUE(hasWarning(t, "Laser degenerate along tx"));
    EXPECT_TRUE(hasWarning(t, "Moving too fast (2.4 m/s"));
    EXPECT_TRUE(hasWarning(t, "Camera dark (brightness 6/255)"));
    EXPECT_TRUE(hasWarning(t, "Storage low (100 MiB free)"));
    EXPECT_EQ(t.modules[0].text, "scan-match degenerate tx");
}

TEST(StatusTexts, SlowSensorWarns) {
    shm::StatusBlock s = healthyScan();
    s.sensors[0].rate_hz = 20.0f;
    const StatusTexts t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    EXPECT_EQ(t.sensors[0].health, Health::kWarning);
    EXPECT_TRUE(hasWarning(t, "hokuyo slow: 20.0 Hz of 40 Hz expected"));
}

TEST(StatusTexts, WithoutPipelineSaysSo) {
    const StatusTexts t =
        describeStatus(shm::Connection::kWaiting, "waiting for pipeline (no shared memory /x)",
                       std::nullopt, std::nullopt);
    EXPECT_EQ(t.scan_state, "WAITING FOR PIPELINE");
    EXPECT_EQ(t.connection.text, "waiting for pipeline (no shared memory /x)");
    EXPECT_NE(t.connection.health, Health::kOk);
    const StatusTexts stale = describeStatus(
        shm::Connection::kStale, "pipeline not responding for 3 s", healthyScan(), std::nullopt);
    EXPECT_TRUE(hasWarning(stale, "Pipeline not responding"));
}

TEST(StatusTexts, ExportProgressAndSafeToRemove) {
    shm::StatusBlock s = healthyScan();
    s.scan_state = static_cast<std::uint8_t>(shm::ScanState::kStopped);
    s.export_status.state = static_cast<std::uint8_t>(shm::ExportState::kRunning);
    s.export_status.progress = 0.45f;
    EXPECT_EQ(describeStatus(shm::Connection::kConnected, "", s, std::nullopt).export_line.text,
              "Exporting 45% - do not remove the USB stick");
    s.export_status.state = static_cast<std::uint8_t>(shm::ExportState::kDone);
    s.export_status.safe_to_remove = 1;
    const StatusTexts t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    EXPECT_EQ(t.export_line.text, "Export done: SAFE TO REMOVE the USB stick");
    EXPECT_EQ(t.export_line.health, Health::kOk);
}

// The daemon's calibration: its step with progress while it runs, then each value with its
// standard deviation, or that the walk did not determine it.
TEST(StatusTexts, CalibrationProgressThenValues) {
    shm::StatusBlock s = healthyScan();
    s.calibration.state = static_cast<std::uint8_t>(shm::CalibrationState::kRunning);
    s.calibration.progress = 0.4f;
    shm::setText(s.calibration.message, "round 1: replayed");
    StatusTexts t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    ASSERT_EQ(t.calibration.size(), 1u);
    EXPECT_EQ(t.calibration[0].text, "Calibrating 40%: round 1: replayed");
    s.calibration.state = static_cast<std::uint8_t>(shm::CalibrationState::kDone);
    shm::setText(s.calibration.message, "calibrated: 1 of 2 values written");
    s.calibration.value_count = 2;
    s.calibration.values[0] = {{}, {}, 0.3f, 0.012f, 0.004f, 1, {}};
    shm::setText(s.calibration.values[0].name, "encoder zero");
    shm::setText(s.calibration.values[0].unit, "deg");
    shm::setText(s.calibration.values[1].name, "laser shift along shaft x");
    t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    ASSERT_EQ(t.calibration.size(), 3u);
    EXPECT_EQ(t.calibration[0].text, "calibrated: 1 of 2 values written");
    EXPECT_EQ(t.calibration[1].text, "encoder zero: 0.012 +- 0.004 deg (was 0.300)");
    EXPECT_EQ(t.calibration[2].text,
              "laser shift along shaft x: kept (not determined by the walk)");
    EXPECT_EQ(t.calibration[2].health, Health::kWarning);
}

TEST(StatusTexts, DofBarCombinesLikeFigure14) {
    shm::PoseRecord p;
    p.vio_dof_mask = 0b000111;   // camera solved rotation
    p.scan_dof_mask = 0b011110;  // laser solved ry, rz, tx, ty
    const StatusTexts t = describeStatus(shm::Connection::kConnected, "", healthyScan(), p);
    ASSERT_TRUE(t.dof_valid);
    // Camera first, laser fills in, IMU prediction holds the rest (tz).
    EXPECT_EQ(t.dof[0], DofSource::kVio);
    EXPECT_EQ(t.dof[2], DofSource::kVio);
    EXPECT_EQ(t.dof[3], DofSource::kScan);
    EXPECT_EQ(t.dof[4], DofSource::kScan);
    EXPECT_EQ(t.dof[5], DofSource::kImu);
    EXPECT_TRUE(t.scan_dof[1]);
    EXPECT_FALSE(t.vio_dof[3]);
}

TEST(StatusTexts, NoDarkCameraWarningWithoutACamera) {
    shm::StatusBlock s;
    s.sensor_count = 1;
    shm::setText(s.sensors[0].name, "hokuyo");
    s.camera_brightness = 0.0f;  // a laser + IMU pipeline reports no brightness
    const StatusTexts t = describeStatus(shm::Connection::kConnected, "", s, std::nullopt);
    for (const auto& w : t.warnings)
        EXPECT_EQ(w.text.find("Camera dark"), std::string::npos) << w.text;
}

TEST(StatusTexts, ChangeReportCountsEachKindAndSaysWhenOnlyTheLargestAreDrawn) {
    StatusTexts t;
    shm::ChangeReport r;
    describeChanges(r, t);
    EXPECT_EQ(t.changes.text, "");  // nothing changed: no legend
    r.appeared = 2;
    r.vanished = 1234;
    r.count = 256;
    describeChanges(r, t);
    EXPECT_EQ(t.changes.text,
              "CHANGED SINCE THE EARLIER SCAN: 2 appeared (orange), 1,234 vanished (blue), the 256 "
              "largest drawn");
    EXPECT_EQ(t.changes_appeared, 2u);
    EXPECT_EQ(t.changes_vanished, 1234u);
    r.vanished = 3;
    r.count = 5;
    describeChanges(r, t);
    EXPECT_EQ(t.changes.text,
              "CHANGED SINCE THE EARLIER SCAN: 2 appeared (orange), 3 vanished (blue)");
    r.count = r.appeared = r.vanished = 0;
    describeChanges(r, t);  // a new scan's empty report clears it
    EXPECT_EQ(t.changes.text, "");
    EXPECT_EQ(t.changes_appeared + t.changes_vanished, 0u);
}

}  // namespace
}  // namespace handscan::ui
