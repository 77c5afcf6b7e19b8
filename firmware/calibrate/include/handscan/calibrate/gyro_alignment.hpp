// The encoder zero and the IMU's time offset from the rotations the laser and the gyro each see,
// over a whole recording (the model: imu/gyro_hand_eye.hpp). A wrong encoder zero turns every
// sweep about the shaft axis in the body frame, a rigid turn the two halves of a revolution agree
// on, so the half-revolution consistency barely sees it; the hand-eye alignment does. The turn eps
// is added to encoder_zero_offset, the IMU time offset dt to xsens.frame_latency.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/imu/gyro_hand_eye.hpp"

namespace handscan::calibrate {

struct MatchedSweepPose {
    std::uint64_t index = 0;  // sweep number (consecutive numbers are consecutive sweeps)
    double t_s = 0.0;         // sweep start, recording clock
    Eigen::Quaterniond q_world_body = Eigen::Quaterniond::Identity();
};

struct GyroAlignment {
    double zero_rad = 0.0, zero_std_rad = INFINITY;
    double imu_time_s = 0.0, imu_time_std_s = INFINITY;
    Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();  // rad/s, IMU frame
    std::size_t pairs = 0;
    double rms_before_rad = 0.0, rms_after_rad = 0.0;
};

// Decodes the recording's IMU samples with `device`'s latency (as replay does).
Result<std::vector<ImuSample>> loadImu(const std::string& recording, const DeviceConfig& device);

// `axis_body`: the shaft axis in the body frame (T_camera_shaftbase * z).
Result<GyroAlignment> alignGyro(const std::vector<MatchedSweepPose>& sweeps,
                                const std::vector<ImuSample>& imu,
                                const Eigen::Matrix3d& R_body_imu,
                                const Eigen::Vector3d& axis_body);

}  // namespace handscan::calibrate
