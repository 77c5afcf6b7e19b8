#include "handscan/imu/unsolved_motion_prior.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::imu {

namespace {
double decay(double dt_s, double tau_s) { return tau_s > 0.0 ? std::exp(-dt_s / tau_s) : 0.0; }
}  // namespace

Eigen::Vector3d UnsolvedMotionPrior::apply(TimeNs t, const Eigen::Vector3d& v, const Eigen::Matrix3d& unsolved) {
    const double dt = have_last_ && t > last_t_ ? toSeconds(t - last_t_) : 0.0;
    if (unsolved.trace() < 0.5) {
        solved_t_ = t;
        ever_solved_ = true;
    }
    // How far the prior replaces the IMU: not at all while the biases learnt when every
    // direction was last solved still hold, fully along a direction never solved since the start.
    const double grace = config_.imu_trusted_s, ramp = config_.imu_trust_ramp_s;
    const double since = toSeconds(t - solved_t_);
    double strength = 1.0;
    if (ever_solved_) strength = since <= grace ? 0.0 : (ramp > 0.0 ? std::min(1.0, (since - grace) / ramp) : 1.0);
    have_last_ = true;
    last_t_ = t;
    gravity_step_.setZero();
    if (!config_.enabled) {
        held_ = v;
        return v;
    }
    const Eigen::Matrix3d solved = Eigen::Matrix3d::Identity() - unsolved;
    // The IMU's velocity change along the unsolved directions since the last feedback.
    Eigen::Vector3d dv = unsolved * (v - held_);
    if (dt > 0.0) {
        // Its persistent small part is tilt / bias: tracked robustly, removed, and handed on.
        const Eigen::Vector3d a = dv / dt;
        const double r = a.norm() / config_.tilt_robust_mps2;
        Eigen::Vector3d step = strength * (1.0 - decay(dt, config_.tilt_time_constant_s)) / (1.0 + r * r) * a;
        const Eigen::Vector3d total = accel_error_ + step;
        if (total.norm() > config_.max_accel_error_mps2) {
            step = total.normalized() * config_.max_accel_error_mps2 - accel_error_;
        }
        accel_error_ += step;
        gravity_step_ = -step;
        dv -= step * dt;
    }
    const Eigen::Vector3d held_u = unsolved * held_ * decay(strength * dt, config_.held_velocity_decay_s);
    held_ = solved * v + held_u + dv;
    return held_;
}

void UnsolvedMotionPrior::reset() {
    held_.setZero();
    accel_error_.setZero();
    gravity_step_.setZero();
    have_last_ = false;
    ever_solved_ = false;
}

}  // namespace handscan::imu
