#include "handscan/sim/imu_model.hpp"

#include <cmath>

namespace handscan::sim {

ImuModel::ImuModel(const ImuNoise& noise, const Eigen::Isometry3d& T_cam_imu, double rate_hz,
                   Rng rng)
    : n_(noise),
      R_ci_(T_cam_imu.linear()),
      t_ci_(T_cam_imu.translation()),
      dt_(1.0 / rate_hz),
      rng_(rng) {
    bg_ = Eigen::Vector3d(rng_.gauss(), rng_.gauss(), rng_.gauss()) * n_.gyro_turn_on_bias;
    ba_ = Eigen::Vector3d(rng_.gauss(), rng_.gauss(), rng_.gauss()) * n_.accel_turn_on_bias;
}

void ImuModel::ideal(const BodyState& s, Eigen::Vector3d& accel_imu,
                     Eigen::Vector3d& gyro_imu) const {
    const Eigen::Matrix3d R_wc = s.T_world_body.linear();
    // Acceleration of the IMU point, rigidly attached at t_ci in {C}:
    // a_I = a_C + R_wc (alpha x r + omega x (omega x r)).
    const Eigen::Vector3d& w = s.omega_body;
    const Eigen::Vector3d a_wi =
        s.a_world + R_wc * (s.alpha_body.cross(t_ci_) + w.cross(w.cross(t_ci_)));
    const Eigen::Vector3d g_w(0.0, 0.0, -n_.gravity);
    const Eigen::Matrix3d R_wi = R_wc * R_ci_;
    accel_imu = R_wi.transpose() * (a_wi - g_w);  // specific force: at rest it reads +g upwards
    gyro_imu = R_ci_.transpose() * w;
}

ImuMeasurement ImuModel::sample(const BodyState& s) {
    ImuMeasurement m;
    m.t = s.t;
    ideal(s, m.true_accel, m.true_gyro);
    // Discrete white noise: sigma = density * sqrt(rate).
    const double sg = n_.gyro_noise_density / std::sqrt(dt_),
                 sa = n_.accel_noise_density / std::sqrt(dt_);
    const Eigen::Vector3d ng(rng_.gauss(), rng_.gauss(), rng_.gauss());
    const Eigen::Vector3d na(rng_.gauss(), rng_.gauss(), rng_.gauss());
    m.gyro = (m.true_gyro + bg_ + sg * ng).cwiseMax(-n_.gyro_range).cwiseMin(n_.gyro_range);
    m.accel = (m.true_accel + ba_ + sa * na).cwiseMax(-n_.accel_range).cwiseMin(n_.accel_range);
    const double sq = std::sqrt(dt_);
    bg_ +=
        n_.gyro_bias_random_walk * sq * Eigen::Vector3d(rng_.gauss(), rng_.gauss(), rng_.gauss());
    ba_ +=
        n_.accel_bias_random_walk * sq * Eigen::Vector3d(rng_.gauss(), rng_.gauss(), rng_.gauss());
    return m;
}

}  // namespace handscan::sim
