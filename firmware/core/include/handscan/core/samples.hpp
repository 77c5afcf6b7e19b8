// Typed, timestamped samples that drivers hand out and the pipeline consumes. Plain structs:
// host time first (TimeNs of CLOCK_MONOTONIC), SI units, frames named in the field names.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan {

// One IMU measurement in the IMU frame {I}.
struct ImuSample {
    TimeNs t_host = 0;                // host time of the sample instant
    std::int64_t t_device_ticks = 0;  // device clock (Xsens SampleTimeFine, 10 kHz ticks)
    Eigen::Vector3d accel_mps2_imu = Eigen::Vector3d::Zero();  // specific force, m/s^2
    Eigen::Vector3d gyro_radps_imu = Eigen::Vector3d::Zero();  // angular rate, rad/s
    std::uint32_t status_word = 0;                             // Xsens StatusWord
    std::uint16_t packet_counter = 0;
};

// One 2D scan of the spinning laser, in the laser frame {L} (x forward at the front step,
// rotation about +z). Each step has its own time: the beam sweeps 270 deg in ~18.75 ms.
struct LaserScan {
    TimeNs t_host = 0;                       // host time of step 0
    std::uint32_t t_device_ms = 0;           // 24-bit millisecond scan timestamp (SCIP)
    TimeNs step_period_ns = 0;               // time between consecutive steps
    int first_step = 0;                      // SCIP step index of ranges_m[0]
    double angle_min_rad = 0.0;              // beam angle of ranges_m[0]
    double angle_increment_rad = 0.0;        // beam angle step
    std::vector<float> ranges_m;             // NaN where the sensor reported an error code
    std::vector<std::uint16_t> intensities;  // empty when the scan carried no intensity
    std::vector<std::uint16_t> error_codes;  // raw value (< DMIN) per step, 0 when valid

    std::size_t size() const { return ranges_m.size(); }
    TimeNs stepTime(std::size_t i) const {
        return t_host + static_cast<TimeNs>(i) * step_period_ns;
    }
    double stepAngle(std::size_t i) const {
        return angle_min_rad + static_cast<double>(i) * angle_increment_rad;
    }
};

// Motor-encoder shaft angle.
struct EncoderSample {
    TimeNs t_host = 0;
    std::uint32_t raw_position = 0;  // encoder counts as sent (CiA 406 0x6004)
    double angle_rad = 0.0;          // continuous (unwrapped) shaft angle
    double speed_radps = 0.0;        // estimated shaft speed
};

enum class PixelFormat : std::uint8_t { kGrey8 = 0, kYuyv = 1, kMjpeg = 2, kBgr8 = 3 };

// One camera frame. `data` holds the buffer as the device delivered it (stride may exceed width).
struct Image {
    TimeNs t_host = 0;           // host time of mid-exposure
    std::uint32_t sequence = 0;  // V4L2 sequence number (gaps = dropped frames)
    PixelFormat format = PixelFormat::kGrey8;
    int width = 0;
    int height = 0;
    int stride_bytes = 0;
    TimeNs exposure_ns = 0;
    std::vector<std::uint8_t> data;
};

enum class GpioEdgeType : std::uint8_t { kRising = 1, kFalling = 2 };

struct GpioEdge {
    TimeNs t_host = 0;
    unsigned line = 0;
    GpioEdgeType edge = GpioEdgeType::kRising;
};

// Per-DOF solve status as in section 8: a bit per DOF (rx, ry, rz, tx, ty, tz) that was
// well-conditioned in the last scan match; unset bits were held from the prediction.
enum class PoseSource : std::uint8_t {
    kImuPrediction = 0,
    kVisualOdometry = 1,
    kScanMatching = 2,
    kIntegrated = 3
};

struct PoseEstimate {
    TimeNs t_host = 0;
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    Eigen::Matrix<double, 6, 6> covariance =
        Eigen::Matrix<double, 6, 6>::Identity();  // (rot, trans)
    std::uint8_t solved_dof_mask = 0x3F;
    // The directions the visual-inertial odometry solved at this pose (section 8): on the 200 Hz
    // output the newest camera frame's while frames keep coming, 0 without a camera or while it
    // is bypassed (the live map's VIO column).
    std::uint8_t visual_solved_dof_mask = 0;
    PoseSource source = PoseSource::kIntegrated;
    // The pipeline's tracking monitor has lost the map (fusion::TrackingMonitor): the pose is
    // the IMU prediction's guess; nothing placed with it may enter the map or the journal.
    bool tracking_lost = false;
};

}  // namespace handscan
