// Every kind of bad configuration value gets its exact message: file, line, key, expected, found.
#include "handscan/core/config.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace handscan {
namespace {

namespace fs = std::filesystem;

class ConfigTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() / ("handscan_config_test_" + std::to_string(::getpid()));
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }
    std::string write(const std::string& name, const std::string& text) {
        const fs::path p = dir_ / name;
        std::ofstream(p) << text;
        return p.string();
    }
    std::string deviceError(const std::string& text) {
        const std::string path = write("device.yaml", text);
        try {
            loadDeviceConfig(path);
        } catch (const ConfigError& e) {
            return std::string(e.what()).substr(path.size());  // strip the temp path
        }
        return "no error";
    }
    fs::path dir_;
};

TEST_F(ConfigTest, ShippedFilesLoad) {
    const std::string dir = HANDSCAN_SOURCE_DIR "/config";
    const DeviceConfig d = loadDeviceConfig(dir + "/device.yaml");
    EXPECT_EQ(d.hokuyo.host, "192.168.0.10");
    EXPECT_EQ(d.hokuyo.port, 10940);
    EXPECT_EQ(d.xsens.baud, 921600);
    EXPECT_DOUBLE_EQ(d.xsens.frame_latency_ms, 1.0);
    EXPECT_DOUBLE_EQ(d.motor.tpdo_latency_ms, 0.12);
    EXPECT_EQ(d.colour_camera.width, 1600);
    const Calibration c = loadCalibration(dir + "/calibration.yaml");
    EXPECT_EQ(c.tracking.resolution[0], 640);
    EXPECT_EQ(c.tracking.distortion_model, "equidistant");
    EXPECT_EQ(c.colour.distortion_model, "radtan");
    EXPECT_NEAR(c.T_colour_tracking.translation().x(), 0.06, 1e-12);
    // The laser's front beam lies along the shaft axis.
    EXPECT_LT(
        (c.T_shaft_laser.linear() * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitZ()).norm(),
        1e-9);
}

TEST_F(ConfigTest, OutOfRangeInteger) {
    EXPECT_EQ(deviceError("hokuyo:\n  host: 10.0.0.1\n  port: 0\n"),
              ":3: hokuyo.port: expected an integer in 1..65535, got 0");
}

TEST_F(ConfigTest, NotAnInteger) {
    EXPECT_EQ(deviceError("hokuyo:\n  port: ten\n"),
              ":2: hokuyo.port: expected an integer in 1..65535, got 'ten'");
}

TEST_F(ConfigTest, UnknownKeyIsATypo) {
    EXPECT_EQ(deviceError("xsens:\n  baudrate: 921600\n"),
              ":2: xsens.baudrate: expected one of the keys {baud, delta_q_v, frame_latency_ms, "
              "rate_hz, serial_path, transport}, "
              "got unknown key 'baudrate'");
}

TEST_F(ConfigTest, EnumValue) {
    EXPECT_EQ(deviceError("tracking_camera:\n  format: RGB3\n"),
              ":2: tracking_camera.format: expected one of 'GREY' 'MJPEG' 'YUYV', got 'RGB3'");
}

TEST_F(ConfigTest, NonStandardBaud) {
    EXPECT_EQ(deviceError("xsens:\n  baud: 100000\n"),
              ":2: xsens.baud: expected one of 9600 19200 38400 57600 115200 230400 460800 921600 "
              "2000000 "
              "4000000, got 100000");
}

TEST_F(ConfigTest, NumberOutOfRange) {
    EXPECT_EQ(deviceError("motor:\n  target_speed_rev_s: -1\n"),
              ":2: motor.target_speed_rev_s: expected a number in 0.05..10, got -1");
}

TEST_F(ConfigTest, XsensFrameLatencyInRange) {
    EXPECT_EQ(deviceError("xsens:\n  frame_latency_ms: -0.5\n"),
              ":2: xsens.frame_latency_ms: expected a number in 0..100, got -0.5");
}

TEST_F(ConfigTest, BooleanValue) {
    EXPECT_EQ(deviceError("xsens:\n  delta_q_v: maybe\n"),
              ":2: xsens.delta_q_v: expected true or false, got 'maybe'");
}

TEST_F(ConfigTest, SectionMustBeAMapping) {
    EXPECT_EQ(deviceError("gpio: 17\n"), ":1: gpio: expected a mapping, got '17'");
}

TEST_F(ConfigTest, ConflictingNodeIds) {
    EXPECT_EQ(deviceError("motor:\n  encoder_node_id: 3\n  drive_node_id: 3\n"),
              ":3: motor.drive_node_id: expected a node id different from encoder_node_id, got 3");
}

TEST_F(ConfigTest, YamlSyntaxError) {
    EXPECT_EQ(deviceError("hokuyo:\n  port: [1, 2\n"),
              ":3: YAML syntax error: end of sequence flow not found");
}

TEST_F(ConfigTest, MissingFile) {
    try {
        loadDeviceConfig((dir_ / "nope.yaml").string());
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()),
                  (dir_ / "nope.yaml").string() + ": cannot open: file does not exist");
    }
}

TEST_F(ConfigTest, CamchainNonRigidTransform) {
    const std::string path =
        write("camchain.yaml",
              "cam0:\n  camera_model: pinhole\n  intrinsics: [300, 300, 320, 256]\n"
              "  distortion_model: radtan\n  distortion_coeffs: [0, 0, 0, 0]\n"
              "  resolution: [640, 512]\n  T_cam_imu:\n  - [2, 0, 0, 0]\n  - [0, 1, 0, 0]\n"
              "  - [0, 0, 1, 0]\n  - [0, 0, 0, 1]\n");
    Calibration c;
    try {
        loadCamchain(path, c);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        const std::string msg = std::string(e.what()).substr(path.size());
        EXPECT_EQ(msg.rfind(":8: cam0.T_cam_imu: expected a rigid transform (orthonormal rotation, "
                            "det +1), got a "
                            "rotation with |R R^T - I| = 3",
                            0),
                  0u)
            << msg;
    }
}

TEST_F(ConfigTest, CamchainWrongDistortionCount) {
    const std::string path =
        write("camchain.yaml",
              "cam0:\n  camera_model: pinhole\n  intrinsics: [300, 300, 320, 256]\n"
              "  distortion_model: equidistant\n  distortion_coeffs: [0, 0]\n"
              "  resolution: [640, 512]\n");
    Calibration c;
    try {
        loadCamchain(path, c);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).substr(path.size()),
                  ":5: cam0.distortion_coeffs: expected a list of 4 numbers, got a list of 2");
    }
}

TEST_F(ConfigTest, CalibrationMissingTransform) {
    const std::string path = write(
        "calibration.yaml", "T_shaft_laser:\n  translation: [0, 0, 0]\n  rpy_deg: [0, 0, 0]\n");
    try {
        loadCalibration(path);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).substr(path.size()),
                  ":1: T_camera_shaftbase: expected a transform {translation, rpy_deg}, got "
                  "nothing (missing)");
    }
}

constexpr const char* kTransforms =
    "T_shaft_laser:\n  translation: [0, 0, 0.05]\n  rpy_deg: [0, -90, 0]\n"
    "T_camera_shaftbase:\n  translation: [0, 0.08, 0]\n  rpy_deg: [0, 0, 0]\n";

TEST_F(ConfigTest, CalibratedTimeOffsetsTakePrecedenceOverDeviceLatencies) {
    const Calibration c = loadCalibration(
        write("calibration.yaml", std::string(kTransforms) +
                                      "time_offsets:\n  xsens_frame_latency_ms: 2.25\n"
                                      "  motor_tpdo_latency_ms: 0.3\n"));
    ASSERT_TRUE(c.xsens_frame_latency_ms && c.motor_tpdo_latency_ms);
    DeviceConfig d;
    d.xsens.frame_latency_ms = 1.0;
    d.motor.tpdo_latency_ms = 0.12;
    const DeviceConfig out = withCalibratedLatencies(d, c);
    EXPECT_DOUBLE_EQ(out.xsens.frame_latency_ms, 2.25);
    EXPECT_DOUBLE_EQ(out.motor.tpdo_latency_ms, 0.3);
    // Without the keys, device.yaml's defaults stand.
    const Calibration plain = loadCalibration(write("plain.yaml", kTransforms));
    EXPECT_FALSE(plain.xsens_frame_latency_ms || plain.motor_tpdo_latency_ms);
    EXPECT_DOUBLE_EQ(withCalibratedLatencies(d, plain).xsens.frame_latency_ms, 1.0);
    EXPECT_DOUBLE_EQ(withCalibratedLatencies(d, plain).motor.tpdo_latency_ms, 0.12);
}

TEST_F(ConfigTest, CalibratedTimeOffsetsValidated) {
    const std::string bad =
        write("calibration.yaml",
              std::string(kTransforms) + "time_offsets:\n  xsens_frame_latency_ms: -1\n");
    try {
        loadCalibration(bad);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).substr(bad.size()),
                  ":8: time_offsets.xsens_frame_latency_ms: expected a number in 0..100, got -1");
    }
    const std::string typo =
        write("typo.yaml", std::string(kTransforms) + "time_offsets:\n  imu_latency_ms: 1\n");
    try {
        loadCalibration(typo);
        FAIL() << "no error";
    } catch (const ConfigError& e) {
        EXPECT_EQ(std::string(e.what()).substr(typo.size()),
                  ":8: time_offsets.imu_latency_ms: expected one of the keys "
                  "{motor_tpdo_latency_ms, xsens_frame_latency_ms}, got unknown key "
                  "'imu_latency_ms'");
    }
}

}  // namespace
}  // namespace handscan
