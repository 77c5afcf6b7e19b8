// The rotations the laser and the gyro each see between two sweeps, aligned (hand-eye).
// A turn eps of the laser's sweeps about the shaft axis (a wrong encoder zero, or at a near
// constant shaft speed an encoder clock that is off: both turn the sweep alike) makes the scan
// matcher report each rotation increment conjugated by that turn, A = R(eps) B R(eps)^T, against
// the gyro's B; a late IMU shifts the window the gyro is integrated over by dt. Unknowns: eps,
// dt and the gyro bias; residuals log(R(eps)^T A_k R(eps) B_k(dt, bias)^T) over pairs of sweeps
// the scan matcher trusted. `handscan calibrate` solves it once over a recording; the pipeline
// tracks it online (lio::ClockTracker).
#pragma once

#include <Eigen/Geometry>
#include <limits>
#include <vector>

#include "handscan/core/samples.hpp"

namespace handscan::imu {

struct HandEyePair {
    double t0_s = 0.0, t1_s = 0.0;                    // the two sweeps' starts, the laser's clock
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();  // the laser's increment, body frame at t0
    // Turns about the shaft already applied to each sweep's encoder angles (the online tracker's
    // correction at the time): the solved turn is the total; sweep k's pose saw eps - applied_k,
    // so A = R(eps - applied0) B R(eps - applied1)^T.
    double applied_turn0_rad = 0.0, applied_turn1_rad = 0.0;
};

// x = [eps (rad), dt (s), gyro bias x y z (rad/s, IMU frame)].
using HandEyeParams = Eigen::Matrix<double, 5, 1>;
using HandEyeCovariance = Eigen::Matrix<double, 5, 5>;
constexpr int kHandEyeTurn = 0;
constexpr int kHandEyeImuTime = 1;

// The gyro's rotation over [a_s, b_s] in the body frame (piecewise-linear rate); `t_s` holds the
// samples' times in seconds.
Eigen::Matrix3d integrateGyro(const std::vector<ImuSample>& imu, const std::vector<double>& t_s,
                              double a_s, double b_s, const Eigen::Matrix3d& R_body_imu,
                              const Eigen::Vector3d& bias);

struct HandEyeProblem {
    std::vector<HandEyePair> pairs;
    std::vector<ImuSample> imu;  // time order
    std::vector<double> t_s;     // imu's times in seconds
    Eigen::Matrix3d R_body_imu = Eigen::Matrix3d::Identity();
    Eigen::Vector3d axis_body = Eigen::Vector3d::UnitZ();  // the shaft axis, unit
    // A zero-mean prior on each unknown (its standard deviation; infinite: none). Keeps an
    // unknown the data do not determine (the turn while the scanner turns only about the shaft,
    // everything while it stands still) at zero, with the prior's std, instead of letting
    // Gauss-Newton wander along a flat residual and drag the others with it.
    HandEyeParams prior_sigma = HandEyeParams::Constant(std::numeric_limits<double>::infinity());
};

// The stacked residuals at x (3 per pair).
Eigen::VectorXd handEyeResiduals(const HandEyeProblem& p, const HandEyeParams& x);

// Gauss-Newton with Huber weights per residual (a bad match must not steer the clock), from x0;
// the formal covariance at the solution when asked.
HandEyeParams solveHandEye(const HandEyeProblem& p, HandEyeParams x0,
                           HandEyeCovariance* covariance = nullptr);

}  // namespace handscan::imu
