#include "handscan/imu/preintegration.hpp"

#include "handscan/core/se3.hpp"

namespace handscan::imu {
namespace {

// Right Jacobian of SO(3): J_r(w) = J_l(-w).
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& w) { return leftJacobianSO3(-w); }

}  // namespace

Eigen::Matrix3d Preintegrated::rotation(const ImuBiases& b) const {
    return dR * expSO3(dR_dbg * (b.gyro_radps - biases.gyro_radps));
}

Eigen::Vector3d Preintegrated::velocity(const ImuBiases& b) const {
    return dv + dv_dbg * (b.gyro_radps - biases.gyro_radps) +
           dv_dba * (b.accel_mps2 - biases.accel_mps2);
}

Eigen::Vector3d Preintegrated::position(const ImuBiases& b) const {
    return dp + dp_dbg * (b.gyro_radps - biases.gyro_radps) +
           dp_dba * (b.accel_mps2 - biases.accel_mps2);
}

void Preintegrator::add(const ImuReading& r0, const ImuReading& r1, double dt_s) {
    // Jacobian recursion of Forster et al. (2015), appendix, evaluated at the step's mean reading;
    // the increments themselves use the exact midpoint step of the predictor.
    const Eigen::Vector3d omega = 0.5 * (r0.gyro_radps + r1.gyro_radps);
    const Eigen::Vector3d acc = 0.5 * (r0.accel_mps2 + r1.accel_mps2);
    const Eigen::Matrix3d dRk = expSO3(omega * dt_s);
    const Eigen::Matrix3d Ra = p_.dR * skew(acc);
    const double dt2 = dt_s * dt_s;
    p_.dp_dba += p_.dv_dba * dt_s - 0.5 * p_.dR * dt2;
    p_.dp_dbg += p_.dv_dbg * dt_s - 0.5 * Ra * p_.dR_dbg * dt2;
    p_.dv_dba -= p_.dR * dt_s;
    p_.dv_dbg -= Ra * p_.dR_dbg * dt_s;
    p_.dR_dbg = dRk.transpose() * p_.dR_dbg - rightJacobian(omega * dt_s) * dt_s;

    NavState x;
    x.R_world_imu = p_.dR;
    x.p_world_imu = p_.dp;
    x.v_world_imu = p_.dv;
    const NavState y = integrateStep(x, r0, r1, dt_s, Eigen::Vector3d::Zero());
    p_.dR = y.R_world_imu;
    p_.dp = y.p_world_imu;
    p_.dv = y.v_world_imu;
    p_.dt_s += dt_s;
}

}  // namespace handscan::imu
