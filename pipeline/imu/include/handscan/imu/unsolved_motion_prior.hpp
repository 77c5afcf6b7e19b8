// The motion prior in the translation directions no exteroceptive module solved (paper section 8,
// for a handheld device). There the pose comes from the IMU prediction, but the IMU's velocity
// cannot be trusted for long: every attitude error of the map frame turns gravity into a
// world-fixed acceleration along the unsolved axis (1 deg of pitch = 0.17 m/s^2; a smooth tunnel
// bends the map by ~2 deg over 50 m even with ground-truth motion) and the accelerometer bias
// there is unobservable, so integrated twice over a 90 s tunnel walk the error ran to kilometres.
//
// The prior of a walking operator, applied at every feedback:
//  - the velocity in the unsolved directions is the held one (the velocity after the previous
//    feedback) plus the IMU's velocity change since then, decaying to zero with
//    `held_velocity_decay_s` (an unseen walker does not keep running away);
//  - a walker's acceleration is zero-mean: a small, persistent apparent acceleration along the
//    unsolved directions is a tilt of gravity in the map frame (or accel bias), not motion. It
//    is tracked with `tilt_time_constant_s`, robustly (Cauchy weight with scale
//    `tilt_robust_mps2`, so a walker's starts, stops and turns - large accelerations - pass as
//    motion), removed from the velocity change and handed to the predictor as a gravity
//    correction along the unsolved directions (gravityStep()).
// In solved directions the velocity is the feedback's and passes unchanged. Time with every
// translation solved earns trust in the IMU, from -`imu_trust_ramp_s` (the prior alone, as at
// the start) up to `imu_trusted_s` (its velocity and biases along
// the now unsolved direction were learnt there: a corridor seen along its axis for a while);
// unsolved time spends it, then the prior ramps in over `imu_trust_ramp_s`; along a direction
// never solved since the start (a tunnel from the static start on, an open field) it acts at
// once, and an odd solved sweep there buys only its own period.
#pragma once

#include <Eigen/Core>

#include "handscan/core/time.hpp"

namespace handscan::imu {

struct UnsolvedMotionPriorConfig {
    bool enabled = true;
    // Measured on 90 s simulated walks (seed 1), ATE (m) tunnel / open field: 5.4 / 10.1 with
    // these; decay 30 s: 11.2 / 9.9, 120 s: 3.9 / 17.5; tilt time constant 1 s: 5.2 / 9.1, 3 s
    // (decay 30 s): 10.8 / 11.8, 5 s: 8.0 / 16.9; robust scale 0.05: 6.7 / 15.4, 0.2: 7.1 / 12.4.
    // Without the tilt (velocity relaxing to the held one, 10 s): 16.2 / 15.2. Without a prior:
    // 1484 / 47 (2961 / 67 with the accel bias and gravity also fed from unsolved directions).
    double held_velocity_decay_s = 60.0;
    double tilt_time_constant_s = 2.0;
    double tilt_robust_mps2 = 0.1;
    // Simulated corridor (60 s, seed 1; stretches along its axis unsolved): ATE 0.098 m without
    // the prior, 1.94 m with it acting at once, 0.15 m trusting the IMU 10 s (+10 s ramp),
    // 0.076 m with 20 s (+20 s); tunnel and field unchanged (never solved).
    double imu_trusted_s = 20.0;
    double imu_trust_ramp_s = 20.0;
    double max_accel_error_mps2 = 0.5;  // 3 deg of tilt: beyond, the map frame is broken
};

class UnsolvedMotionPrior {
public:
    explicit UnsolvedMotionPrior(UnsolvedMotionPriorConfig config = {})
        : config_(config), trust_s_(-config.imu_trust_ramp_s) {}

    // At a feedback time t: `v` is the velocity after the feedback (the estimate in the solved
    // directions, the IMU's prediction in the others), `unsolved` the orthogonal projector onto
    // the unsolved translation directions in world axes. Returns the velocity to continue the
    // prediction with; gravityStep() tells how to turn gravity.
    Eigen::Vector3d apply(TimeNs t, const Eigen::Vector3d& v, const Eigen::Matrix3d& unsolved);
    void reset();
    // The velocity (world, m/s) after the last apply().
    const Eigen::Vector3d& held() const { return held_; }
    // The change of gravity (world, m/s^2) the last apply() attributes to a tilt of the map frame
    // along the unsolved directions; the predictor adds it to its gravity.
    const Eigen::Vector3d& gravityStep() const { return gravity_step_; }
    // The apparent acceleration removed so far (world, m/s^2).
    const Eigen::Vector3d& accelError() const { return accel_error_; }
    // How far the last apply() replaced the IMU along the unsolved directions: 0 (IMU trusted)
    // to 1 (the prior alone).
    double strength() const { return strength_; }

private:
    UnsolvedMotionPriorConfig config_;
    Eigen::Vector3d held_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d accel_error_ = Eigen::Vector3d::Zero();
    Eigen::Vector3d gravity_step_ = Eigen::Vector3d::Zero();
    TimeNs last_t_ = 0;
    // IMU trust (s): + while every translation is solved (up to imu_trusted_s), - while not
    // (down to -imu_trust_ramp_s, where the prior acts fully; also the start).
    double trust_s_;
    double strength_ = 1.0;
    bool have_last_ = false;
};

}  // namespace handscan::imu
