#include "handscan/imu/gravity_alignment.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::imu {

Eigen::Matrix3d levelRotationFromSpecificForce(const Eigen::Vector3d& f_imu) {
    // At rest f = R_world_imu^T (0, 0, g): "up" in {I} is f / |f|.
    return Eigen::Quaterniond::FromTwoVectors(f_imu.normalized(), Eigen::Vector3d::UnitZ())
        .toRotationMatrix();
}

void StaticStartAligner::Sums::add(const ImuSample& s) {
    if (n == 0) t_first = s.t_host;
    t_last = s.t_host;
    ++n;
    gyro += s.gyro_radps_imu;
    accel += s.accel_mps2_imu;
    gyro_sq += s.gyro_radps_imu.cwiseAbs2();
    accel_sq += s.accel_mps2_imu.cwiseAbs2();
}

void StaticStartAligner::Sums::add(const Sums& o) {
    if (n == 0) t_first = o.t_first;
    t_last = o.t_last;
    n += o.n;
    gyro += o.gyro;
    accel += o.accel;
    gyro_sq += o.gyro_sq;
    accel_sq += o.accel_sq;
}

void StaticStartAligner::reset() {
    block_ = {};
    run_ = {};
}

bool StaticStartAligner::blockIsStatic() const {
    const double n = static_cast<double>(block_.n);
    const Eigen::Vector3d mg = block_.gyro / n, ma = block_.accel / n;
    const double gyro_std = std::sqrt(std::max(0.0, (block_.gyro_sq / n - mg.cwiseAbs2()).sum()));
    const double accel_std = std::sqrt(std::max(0.0, (block_.accel_sq / n - ma.cwiseAbs2()).sum()));
    if (gyro_std > config_.max_gyro_std_radps || accel_std > config_.max_accel_std_mps2)
        return false;
    if (run_.n == 0) return true;
    const double rn = static_cast<double>(run_.n);
    return (mg - run_.gyro / rn).norm() <= config_.max_gyro_dev_radps &&
           (ma - run_.accel / rn).norm() <= config_.max_accel_dev_mps2;
}

std::optional<GravityAlignment> StaticStartAligner::add(const ImuSample& s) {
    if (!s.gyro_radps_imu.allFinite() || !s.accel_mps2_imu.allFinite()) return std::nullopt;
    block_.add(s);
    if (toSeconds(block_.t_last - block_.t_first) < config_.block_s) return std::nullopt;
    if (blockIsStatic()) {
        run_.add(block_);
    } else {
        run_ = {};  // motion: the static run starts again after this block
    }
    block_ = {};
    if (run_.n == 0 || toSeconds(run_.t_last - run_.t_first) < config_.min_static_s)
        return std::nullopt;
    const GravityAlignment a = estimate();
    if (std::abs(a.accel_norm_error_mps2) > config_.max_norm_error_mps2) {
        // A constant acceleration (e.g. a lift) passes the stillness test but not this one.
        reset();
        return std::nullopt;
    }
    return a;
}

GravityAlignment StaticStartAligner::estimate() const {
    GravityAlignment a;
    const double n = static_cast<double>(run_.n);
    a.samples = run_.n;
    a.t_start = run_.t_first;
    a.t_end = run_.t_last;
    a.mean_specific_force_imu = run_.accel / n;
    a.biases.gyro_radps = run_.gyro / n;
    a.R_world_imu = levelRotationFromSpecificForce(a.mean_specific_force_imu);
    a.accel_norm_error_mps2 = a.mean_specific_force_imu.norm() - config_.gravity_mps2;
    // The accel bias along gravity is observable at rest (the norm error); taking it keeps the
    // prediction from sinking or rising at (|f| - g) / 2 t^2 until feedback arrives. The
    // horizontal part is not: it only tilts the levelled frame.
    a.biases.accel_mps2 = a.mean_specific_force_imu.normalized() * a.accel_norm_error_mps2;
    return a;
}

}  // namespace handscan::imu
