#include "handscan/imu/unsolved_motion_prior.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::imu {

namespace {
double decay(double dt_s, double tau_s) { return tau_s > 0.0 ? std::exp(-dt_s / tau_s) : 0.0; }
}  // namespace

Eigen::Vector3d UnsolvedMotionPrior::apply(TimeNs t, const Eigen::Vector3d& v,
                                           const Eigen::Matrix3d& unsolved) {
    const double dt = have_last_ && t > last_t_ ? toSeconds(t - last_t_) : 0.0;
    // How far the prior replaces the IMU: not at all while the biases learnt when every
    // direction was solved still hold, fully along a direction not solved for long. Trust is
    // earned by solved time and spent by unsolved time (a leaky bucket from -ramp to +grace),
    // so a long solved stretch (a lobby) buys imu_trusted_s of IMU alone along a corridor,
    // while a single sweep that solved everything (a weak direction confirmed once in a
    // tunnel) buys no more than its own period: the IMU's velocity and biases along the
    // direction were not learnt in it. Before: any solved sweep reset the grace to 20 s, and
    // one confirmed sweep in the 90 s tunnel (seed 3) let the IMU run alone: ATE 13 -> 107 m.
    const double grace = config_.imu_trusted_s, ramp = config_.imu_trust_ramp_s;
    if (unsolved.trace() < 0.5) {
        trust_s_ = std::min(grace, trust_s_ + dt);
    } else {
        trust_s_ = std::max(-ramp, trust_s_ - dt);
    }
    strength_ = trust_s_ >= 0.0 ? 0.0 : (ramp > 0.0 ? -trust_s_ / ramp : 1.0);
    const double strength = strength_;
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
        Eigen::Vector3d step =
            strength * (1.0 - decay(dt, config_.tilt_time_constant_s)) / (1.0 + r * r) * a;
        const Eigen::Vector3d total = accel_error_ + step;
        if (total.norm() > config_.max_accel_error_mps2) {
            step = total.normalized() * config_.max_accel_error_mps2 - accel_error_;
        }
        accel_error_ += step;
        gravity_step_ = -step;
        dv -= step * dt;
    }
    const Eigen::Vector3d held_u =
        unsolved * held_ * decay(strength * dt, config_.held_velocity_decay_s);
    held_ = solved * v + held_u + dv;
    return held_;
}

void UnsolvedMotionPrior::reset() {
    held_.setZero();
    accel_error_.setZero();
    gravity_step_.setZero();
    have_last_ = false;
    trust_s_ = -config_.imu_trust_ramp_s;
    strength_ = 1.0;
}

}  // namespace handscan::imu
