// What `handscan calibrate` writes, loadCalibration reads back as is: transforms near the laser's
// -90 deg pitch (where roll-pitch-yaw is nearly singular), the zero, the time offsets and the
// camchain path made relative to the new file.
#include "handscan/calibrate/calibration_writer.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "handscan/core/se3.hpp"

namespace handscan::calibrate {
namespace {

namespace fs = std::filesystem;

TEST(CalibrationWriter, RoundTripsThroughLoadCalibration) {
    const fs::path dir = fs::temp_directory_path() / "calibration_writer_test";
    fs::remove_all(dir);
    fs::create_directories(dir / "cal");
    fs::copy_file(fs::path(HANDSCAN_SOURCE_DIR) / "config/camchain.yaml", dir / "camchain.yaml");
    Calibration c = loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
    c.T_shaft_laser.linear() =
        expSO3(Eigen::Vector3d(0.0123, -0.0045, 0.0)) * c.T_shaft_laser.linear();
    c.T_shaft_laser.translation() += Eigen::Vector3d(-0.0012, 0.0031, 0.0);
    c.encoder_zero_offset_rad = 0.0321;
    c.xsens_frame_latency_ms = 1.234;
    c.motor_tpdo_latency_ms.reset();
    const std::string out = (dir / "cal" / "calibration.yaml").string();
    ASSERT_TRUE(
        writeCalibrationYaml(out, c, (dir / "camchain.yaml").string(), {"a comment"}).isOk());
    const Calibration back = loadCalibration(out);
    EXPECT_LT(rotationAngle(back.T_shaft_laser.linear(), c.T_shaft_laser.linear()), 1e-9);
    EXPECT_LT((back.T_shaft_laser.translation() - c.T_shaft_laser.translation()).norm(), 1e-9);
    EXPECT_LT(rotationAngle(back.T_camera_shaftbase.linear(), c.T_camera_shaftbase.linear()), 1e-9);
    EXPECT_NEAR(back.encoder_zero_offset_rad, c.encoder_zero_offset_rad, 1e-9);
    ASSERT_TRUE(back.xsens_frame_latency_ms.has_value());
    EXPECT_NEAR(*back.xsens_frame_latency_ms, 1.234, 1e-6);
    EXPECT_FALSE(back.motor_tpdo_latency_ms.has_value());  // not found: device.yaml's stays
    EXPECT_EQ(camchainPathOf(out), (dir / "cal" / "../camchain.yaml").string());
    fs::remove_all(dir);
}

}  // namespace
}  // namespace handscan::calibrate
