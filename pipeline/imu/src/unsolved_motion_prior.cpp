#include "handscan/imu/unsolved_motion_prior.hpp"

#include <cmath>

namespace handscan::imu {

namespace {
double decay(double dt_s, double tau_s) { return tau_s > 0.0 ? std::exp(-dt_s / tau_s) : 0.0; }
}  // namespace

Eigen::Vector3d UnsolvedMotionPrior::apply(TimeNs t, const Eigen::Vector3d& v, const Eigen::Matrix3d& unsolved) {
    const double dt = have_last_ && t > last_t_ ? toSeconds(t - last_t_) : 0.0;
    have_last_ = true;
    last_t_ = t;
    const Eigen::Matrix3d solved = Eigen::Matrix3d::Identity() - unsolved;
    const Eigen::Vector3d held_u = unsolved * held_ * decay(dt, config_.held_velocity_decay_s);
    held_ = solved * v + held_u;
    if (!config_.enabled) return v;
    // The IMU's deviation from the held velocity since the last feedback, relaxed.
    const Eigen::Vector3d v_u = held_u + unsolved * (v - held_u) * decay(dt, config_.imu_velocity_leak_s);
    return solved * v + v_u;
}

void UnsolvedMotionPrior::reset() {
    held_.setZero();
    have_last_ = false;
}

}  // namespace handscan::imu
