// Device configuration and calibration, loaded from YAML in config/. Loading validates every
// field and rejects unknown keys; the first problem throws ConfigError with a message naming the
// file, line, key, what was expected and what was found, e.g.
//   config/device.yaml:14: hokuyo.port: expected an integer in 1..65535, got 0
// Programs catch it at start-up, print it and exit non-zero before touching any data.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace handscan {

class ConfigError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct HokuyoConfig {
    std::string host = "192.168.0.10";
    int port = 10940;
    double connect_timeout_s = 2.0;
    double reconnect_max_backoff_s = 5.0;
    // Fixed delay from a scan's last step to its frame leaving the sensor (calibration): the
    // 24-bit timestamp cannot show it, and at 1 rev/s every ms of it turns the cloud by 0.36 deg.
    double frame_latency_ms = 0.0;
};

struct XsensConfig {
    std::string transport = "serial";  // serial | usb
    std::string serial_path = "/dev/ttyUSB0";
    int baud = 921600;
    int rate_hz = 200;
    bool delta_q_v = false;  // also request DeltaQ/DeltaV
    // Fixed delay from a sample's SampleTimeFine to its frame's first byte reaching the host
    // (output processing + USB-serial bridge; calibration). The frame's wire time at `baud` is
    // added per frame. Uncompensated, the whole IMU motion runs this late against the laser:
    // at 370 deg/s every ms turns the sweep and the output pose by 0.37 deg.
    double frame_latency_ms = 0.0;
};

struct MotorConfig {
    std::string can_interface = "can0";
    int encoder_node_id = 1;
    int drive_node_id = 2;
    int encoder_counts_per_rev = 16384;
    int tpdo_period_ms = 5;
    double heartbeat_timeout_s = 0.5;
    double target_speed_rev_s = 1.0;
    std::string sweep_boundary = "half";  // half | full revolution
    // Fixed delay from the encoder sampling its position to the TPDO1 frame's receive time (the
    // frame on the bus, the adapter; calibration). The receive times cannot show it, and at
    // 1 rev/s every 0.1 ms of it turns the shaft angle, and so the sweep, by 0.036 deg.
    double tpdo_latency_ms = 0.0;
};

struct CameraConfig {
    bool enabled = true;
    std::string device = "/dev/video0";
    int width = 640;
    int height = 512;
    double fps = 50.0;
    std::string format = "GREY";  // GREY | YUYV | MJPEG
    double exposure_ms = 5.0;
    // End of exposure to end of frame: how much earlier than an end-of-frame buffer timestamp
    // (UVC) the exposure ended. The frame's time is its mid-exposure; a camera that stamps the
    // start of exposure needs none. A property of the sensor and its link (rolling readout, USB
    // transfer), measured once per camera model.
    double readout_ms = 0.0;
};

struct GpioConfig {
    std::string chip = "gpiochip0";
    int start_button_line = 17;
    int export_button_line = 27;
    int led_ready_line = 5;
    int led_scanning_line = 6;
    int led_fault_line = 13;
    int led_exporting_line = 19;
    double debounce_ms = 20.0;
};

struct StorageConfig {
    std::string journal_dir = "/var/lib/handscan/journal";
    std::string recording_dir = "/var/lib/handscan/recordings";
    double min_free_gib = 1.0;
    // Record each scan's raw laser, IMU and encoder streams beside its journal (raw.mcap) while
    // more than min_free_gib is free: for reprocessing, and the UI's "calibrate".
    bool record_scans = true;
};

struct DeviceConfig {
    std::string source_file;
    HokuyoConfig hokuyo;
    XsensConfig xsens;
    MotorConfig motor;
    CameraConfig tracking_camera;
    CameraConfig colour_camera{true, "/dev/video1", 1600, 1200, 5.0, "YUYV", 10.0};
    GpioConfig gpio;
    StorageConfig storage;
};

// One camera of a Kalibr camchain.
struct CameraIntrinsics {
    std::string camera_model = "pinhole";          // pinhole | omni
    std::array<double, 4> intrinsics{};            // fu fv pu pv
    std::string distortion_model = "equidistant";  // equidistant | radtan | none
    std::vector<double> distortion_coeffs;
    std::array<int, 2> resolution{};  // width height
    Eigen::Isometry3d T_cam_imu = Eigen::Isometry3d::Identity();
    double timeshift_cam_imu_s = 0.0;
};

struct Calibration {
    std::string source_file;
    // Laser frame {L} -> motor shaft frame {S}: where the Hokuyo sits on the spinning shaft.
    Eigen::Isometry3d T_shaft_laser = Eigen::Isometry3d::Identity();
    // Shaft base frame {B} (the shaft at encoder angle 0) -> tracking camera {C} (the body frame).
    Eigen::Isometry3d T_camera_shaftbase = Eigen::Isometry3d::Identity();
    double encoder_zero_offset_rad = 0.0;
    CameraIntrinsics tracking;                                            // cam0 of the camchain
    CameraIntrinsics colour;                                              // cam1 of the camchain
    Eigen::Isometry3d T_colour_tracking = Eigen::Isometry3d::Identity();  // cam1 T_cn_cnm1
    // The sensors' time offsets against the laser, as `handscan calibrate` measures them
    // (calibration.yaml `time_offsets`): when present they take precedence over device.yaml's
    // xsens.frame_latency_ms and motor.tpdo_latency_ms defaults (withCalibratedLatencies).
    std::optional<double> xsens_frame_latency_ms;
    std::optional<double> motor_tpdo_latency_ms;
    // IMU {I} -> tracking camera {C}: the inverse of cam0's T_cam_imu, kept for convenience.
    Eigen::Isometry3d T_camera_imu() const { return tracking.T_cam_imu; }
};

DeviceConfig loadDeviceConfig(const std::string& path);
// calibration.yaml holds the laser/shaft extrinsics and names the camchain file (relative to
// itself) holding the cameras in Kalibr's format.
Calibration loadCalibration(const std::string& path);
// `device` with the latencies calibration.yaml measured in place of its defaults.
DeviceConfig withCalibratedLatencies(DeviceConfig device, const Calibration& calibration);
// Kalibr camchain alone (cam0 = tracking, cam1 = colour).
void loadCamchain(const std::string& path, Calibration& calibration);

// Where config/ lives: $HANDSCAN_CONFIG_DIR, else /etc/handscan, else the source tree's config/.
std::string defaultConfigDir();

}  // namespace handscan
