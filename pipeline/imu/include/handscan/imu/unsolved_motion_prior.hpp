// The motion prior in the translation directions no exteroceptive module solved (paper section 8,
// for a handheld device). There the pose comes from the IMU prediction, but the IMU's velocity
// must not be trusted for long: every attitude error turns gravity into a world-fixed
// acceleration along the unsolved axis (1 deg of pitch = 0.17 m/s^2) and the accelerometer
// bias there is unobservable, so integrated twice over a 90 s tunnel walk it ran to kilometres.
// The prior for a walking operator: the velocity in the unsolved directions is the last
// well-observed velocity there, decaying to zero with `held_velocity_decay_s` (a walker who is
// not seen does not keep running away); the IMU contributes only its short-term velocity changes,
// relaxing to the held velocity with `imu_velocity_leak_s` (a step, a stop, a turn within a few
// seconds). In solved directions the velocity is the feedback's, and it renews the held one.
#pragma once

#include <Eigen/Core>

#include "handscan/core/time.hpp"

namespace handscan::imu {

struct UnsolvedMotionPriorConfig {
    bool enabled = true;
    // How long a walker keeps the velocity last seen in a direction that is no longer solved
    // (walking into a tunnel at 1.4 m/s keeps about that pace for a while).
    double held_velocity_decay_s = 20.0;
    // The IMU-only velocity there relaxes to the held one with this time constant: the balance of
    // a walker's speed changes (~1 m/s) against the unobservable acceleration error (tilt and
    // accel bias, 0.02-0.1 m/s^2). Measured on 90 s simulated walks (seed 1), ATE in m for
    // 2/5/10/15/60 s: tunnel 18/18/16/12/274, open field 12/13/15/17/34; without the prior
    // 1484 and 47 (and 2961 and 67 with the bias and gravity also fed from unsolved directions).
    double imu_velocity_leak_s = 10.0;
};

class UnsolvedMotionPrior {
public:
    explicit UnsolvedMotionPrior(UnsolvedMotionPriorConfig config = {}) : config_(config) {}

    // At a feedback time t: `v` is the velocity after the feedback (the estimate in the solved
    // directions, the IMU's in the others), `unsolved` the orthogonal projector onto the unsolved
    // translation directions in world axes. Returns the velocity to continue the prediction with.
    Eigen::Vector3d apply(TimeNs t, const Eigen::Vector3d& v, const Eigen::Matrix3d& unsolved);
    void reset();
    // The held velocity (world, m/s) after the last apply().
    const Eigen::Vector3d& held() const { return held_; }

private:
    UnsolvedMotionPriorConfig config_;
    Eigen::Vector3d held_ = Eigen::Vector3d::Zero();
    TimeNs last_t_ = 0;
    bool have_last_ = false;
};

}  // namespace handscan::imu
