// Relative motion of {I} between two times from the IMU alone (the "IMU-only prediction" that
// section 4.2 compares the laser/visual feedback with), with first-order Jacobians with respect
// to the biases so that a bias change does not need a re-integration (Forster et al. 2015,
// which the paper cites). The increments are the mechanization of eq. (3)-(4) started from the
// identity with zero gravity, using the same midpoint step as the predictor.
#pragma once

#include <Eigen/Core>

#include "handscan/imu/mechanization.hpp"

namespace handscan::imu {

struct Preintegrated {
    double dt_s = 0.0;
    Eigen::Matrix3d dR = Eigen::Matrix3d::Identity();  // R_i^T R_j
    Eigen::Vector3d dv = Eigen::Vector3d::Zero();      // R_i^T (v_j - v_i - g dt)
    Eigen::Vector3d dp = Eigen::Vector3d::Zero();      // R_i^T (p_j - p_i - v_i dt - g dt^2 / 2)
    Eigen::Matrix3d dR_dbg = Eigen::Matrix3d::Zero();  // right-perturbation Jacobian of dR
    Eigen::Matrix3d dv_dbg = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d dv_dba = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d dp_dbg = Eigen::Matrix3d::Zero();
    Eigen::Matrix3d dp_dba = Eigen::Matrix3d::Zero();
    ImuBiases biases;  // linearisation point

    // Increments re-evaluated at other biases (first order).
    Eigen::Matrix3d rotation(const ImuBiases& b) const;
    Eigen::Vector3d velocity(const ImuBiases& b) const;
    Eigen::Vector3d position(const ImuBiases& b) const;
};

class Preintegrator {
public:
    explicit Preintegrator(const ImuBiases& biases) { p_.biases = biases; }
    // One midpoint step between two bias-corrected readings.
    void add(const ImuReading& r0, const ImuReading& r1, double dt_s);
    const Preintegrated& result() const { return p_; }

private:
    Preintegrated p_;
};

}  // namespace handscan::imu
