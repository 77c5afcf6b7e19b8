// An analytic, smooth 6-DOF hand-held-like motion with exact IMU readings derived from it, so the
// integration error can be measured against the truth.
#pragma once

#include <cmath>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/se3.hpp"
#include "handscan/imu/nav_state.hpp"

namespace handscan::imu::testing {

struct SyntheticMotion {
    double scale = 1.0;  // amplitude multiplier

    Eigen::Matrix3d R(double t) const {
        return expSO3(scale * Eigen::Vector3d(0.4 * std::sin(1.3 * t),
                                              0.3 * std::sin(0.9 * t + 0.5),
                                              0.6 * std::sin(0.5 * t)));
    }
    Eigen::Vector3d p(double t) const {
        return scale * Eigen::Vector3d(1.5 * std::sin(0.6 * t), 0.8 * std::sin(1.1 * t),
                                       0.3 * std::sin(0.8 * t));
    }
    Eigen::Vector3d v(double t) const {
        return scale * Eigen::Vector3d(0.9 * std::cos(0.6 * t), 0.88 * std::cos(1.1 * t),
                                       0.24 * std::cos(0.8 * t));
    }
    Eigen::Vector3d a(double t) const {
        return scale * Eigen::Vector3d(-0.54 * std::sin(0.6 * t), -0.968 * std::sin(1.1 * t),
                                       -0.192 * std::sin(0.8 * t));
    }
    // Body rate by a central difference on SO(3) (truncation ~1e-9 rad/s).
    Eigen::Vector3d omega(double t) const {
        const double h = 1e-4;
        return logSO3(R(t - h).transpose() * R(t + h)) / (2.0 * h);
    }
    Eigen::Vector3d omegaDot(double t) const {
        const double h = 1e-4;
        return (omega(t + h) - omega(t - h)) / (2.0 * h);
    }
    NavState state(double t) const {
        NavState x;
        x.t = fromSeconds(t);
        x.R_world_imu = R(t);
        x.p_world_imu = p(t);
        x.v_world_imu = v(t);
        return x;
    }
    ImuSample sample(double t, const ImuBiases& b = {}, double g = 9.81) const {
        ImuSample s;
        s.t_host = fromSeconds(t);
        s.gyro_radps_imu = omega(t) + b.gyro_radps;
        s.accel_mps2_imu = R(t).transpose() * (a(t) - gravityWorld(g)) + b.accel_mps2;
        return s;
    }
};

}  // namespace handscan::imu::testing
