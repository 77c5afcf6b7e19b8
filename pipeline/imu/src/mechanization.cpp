#include "handscan/imu/mechanization.hpp"

#include "handscan/core/se3.hpp"

namespace handscan::imu {

ImuReading correctBiases(const ImuSample& s, const ImuBiases& b) {
    return {s.gyro_radps_imu - b.gyro_radps, s.accel_mps2_imu - b.accel_mps2};
}

ImuReading lerp(const ImuReading& a, const ImuReading& b, double s) {
    return {a.gyro_radps + s * (b.gyro_radps - a.gyro_radps),
            a.accel_mps2 + s * (b.accel_mps2 - a.accel_mps2)};
}

NavState integrateStep(const NavState& x, const ImuReading& r0, const ImuReading& r1, double dt_s,
                       const Eigen::Vector3d& gravity_world) {
    NavState y;
    // Eq. (3): orientation from the mean rate over the step (exact exponential on SO(3)).
    const Eigen::Vector3d omega = 0.5 * (r0.gyro_radps + r1.gyro_radps);
    y.R_world_imu = x.R_world_imu * expSO3(omega * dt_s);
    // Eq. (4): specific force rotated into {W} at both ends, plus gravity (f = a - R g).
    const Eigen::Vector3d a0 = x.R_world_imu * r0.accel_mps2;
    const Eigen::Vector3d a1 = y.R_world_imu * r1.accel_mps2;
    const Eigen::Vector3d a = 0.5 * (a0 + a1) + gravity_world;
    y.p_world_imu = x.p_world_imu + x.v_world_imu * dt_s + 0.5 * a * dt_s * dt_s;
    y.v_world_imu = x.v_world_imu + a * dt_s;
    y.t = x.t + fromSeconds(dt_s);
    return y;
}

NavState integrateOrHold(const NavState& x, const ImuReading& r0, const ImuReading& r1, double dt_s,
                         const Eigen::Vector3d& gravity_world, double max_gap_s) {
    if (dt_s <= max_gap_s) return integrateStep(x, r0, r1, dt_s, gravity_world);
    NavState y = x;
    y.p_world_imu += x.v_world_imu * dt_s;
    y.t = x.t + fromSeconds(dt_s);
    return y;
}

Eigen::Isometry3d bodyPose(const NavState& x, const Eigen::Isometry3d& T_imu_body) {
    return x.T_world_imu() * T_imu_body;
}

Eigen::Vector3d bodyVelocity(const NavState& x, const Eigen::Vector3d& omega_imu,
                             const Eigen::Isometry3d& T_imu_body) {
    return x.v_world_imu + x.R_world_imu * omega_imu.cross(T_imu_body.translation());
}

Eigen::Vector3d specificForceAtBody(const Eigen::Vector3d& f_imu, const Eigen::Vector3d& omega_imu,
                                    const Eigen::Vector3d& omega_dot_imu,
                                    const Eigen::Isometry3d& T_imu_body) {
    const Eigen::Vector3d& r = T_imu_body.translation();
    const Eigen::Vector3d f_at_body_imu =
        f_imu + omega_imu.cross(omega_imu.cross(r)) + omega_dot_imu.cross(r);
    return T_imu_body.linear().transpose() * f_at_body_imu;
}

}  // namespace handscan::imu
