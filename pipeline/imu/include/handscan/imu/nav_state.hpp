// The inertial navigation state of the IMU frame {I} in the gravity-aligned world {W} (z up), and
// the IMU biases of eqs. (3)-(4). Plain structs, SI units, frames in the names.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "handscan/core/time.hpp"

namespace handscan::imu {

struct ImuBiases {
    Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();  // b_omega of eq. (3), in {I}
    Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();  // b_a of eq. (4), in {I}
};

struct NavState {
    TimeNs t = 0;
    Eigen::Matrix3d R_world_imu = Eigen::Matrix3d::Identity();
    Eigen::Vector3d p_world_imu = Eigen::Vector3d::Zero();  // m
    Eigen::Vector3d v_world_imu = Eigen::Vector3d::Zero();  // m/s

    Eigen::Isometry3d T_world_imu() const {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = R_world_imu;
        T.translation() = p_world_imu;
        return T;
    }
};

// Gravity in {W}: z points up, so g = (0, 0, -|g|).
inline Eigen::Vector3d gravityWorld(double g_mps2) { return {0.0, 0.0, -g_mps2}; }

}  // namespace handscan::imu
