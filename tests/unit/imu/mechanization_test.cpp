// Mechanization (eqs. (3)-(4)), the lever arm to the body frame and the preintegration Jacobians
// against an analytic motion with exact IMU readings.
#include "handscan/imu/mechanization.hpp"

#include <gtest/gtest.h>

#include "handscan/imu/preintegration.hpp"
#include "synthetic_motion.hpp"

namespace handscan::imu {
namespace {

using testing::SyntheticMotion;

// Integrates the motion for `duration` seconds at `rate_hz` from the true start state.
NavState integrate(const SyntheticMotion& m, double rate_hz, double duration) {
    const double dt = 1.0 / rate_hz;
    NavState x = m.state(0.0);
    ImuReading r0 = correctBiases(m.sample(0.0), {});
    const int steps = static_cast<int>(duration * rate_hz + 0.5);
    for (int k = 1; k <= steps; ++k) {
        const ImuReading r1 = correctBiases(m.sample(k * dt), {});
        x = integrateStep(x, r0, r1, dt, gravityWorld(9.81));
        r0 = r1;
    }
    return x;
}

TEST(Mechanization, FollowsAnalyticMotionWithSecondOrderError) {
    const SyntheticMotion m;
    const double T = 10.0;
    const NavState x200 = integrate(m, 200.0, T);
    const NavState x400 = integrate(m, 400.0, T);
    const double e200 = (x200.p_world_imu - m.p(T)).norm();
    const double e400 = (x400.p_world_imu - m.p(T)).norm();
    const double r200 = rotationAngle(x200.R_world_imu, m.R(T));
    // 10 s of hand-like motion at 200 Hz: the integration itself adds < 1 mm and < 1e-4 rad.
    EXPECT_LT(e200, 1e-3);
    EXPECT_LT(r200, 1e-4);
    EXPECT_LT((x200.v_world_imu - m.v(T)).norm(), 2e-4);
    // Second order: halving the step divides the error by ~4 (a first-order Euler step gives 2).
    EXPECT_GT(e200 / e400, 3.0);
}

TEST(Mechanization, GravityOnlyKeepsAStaticImuStill) {
    ImuReading r;
    r.accel_mps2 = Eigen::Vector3d(0, 0, 9.81);  // at rest the accelerometer reads -g
    NavState x;
    for (int k = 0; k < 200 * 60; ++k) x = integrateStep(x, r, r, 0.005, gravityWorld(9.81));
    EXPECT_LT(x.p_world_imu.norm(), 1e-9);
    EXPECT_LT(x.v_world_imu.norm(), 1e-9);
}

TEST(LeverArm, BodyPoseVelocityAndSpecificForceMatchTheRigidBody) {
    const SyntheticMotion m;
    Eigen::Isometry3d T_imu_body = Eigen::Isometry3d::Identity();
    T_imu_body.linear() = expSO3(Eigen::Vector3d(0.3, -1.2, 0.5));
    T_imu_body.translation() = Eigen::Vector3d(0.04, -0.03, 0.02);  // camchain-sized lever arm
    const double g = 9.81;
    auto bodyAt = [&](double t) { return bodyPose(m.state(t), T_imu_body); };
    for (double t : {0.7, 2.3, 5.1}) {
        const double h = 1e-4;
        const Eigen::Vector3d p0 = bodyAt(t - h).translation(), p1 = bodyAt(t).translation(),
                              p2 = bodyAt(t + h).translation();
        const Eigen::Vector3d v_num = (p2 - p0) / (2 * h);
        const Eigen::Vector3d a_num = (p2 - 2 * p1 + p0) / (h * h);
        EXPECT_LT((bodyVelocity(m.state(t), m.omega(t), T_imu_body) - v_num).norm(), 1e-6);
        // Eq. (4) at the body origin, in {C}: what an IMU there would read.
        const Eigen::Vector3d f_body_expected =
            bodyAt(t).linear().transpose() * (a_num - gravityWorld(g));
        const Eigen::Vector3d f_imu = m.sample(t, {}, g).accel_mps2_imu;
        const Eigen::Vector3d f_body =
            specificForceAtBody(f_imu, m.omega(t), m.omegaDot(t), T_imu_body);
        EXPECT_LT((f_body - f_body_expected).norm(), 1e-3) << "t=" << t;
        // Without the lever-arm terms the error is of the size of omega^2 r: the test sees it.
        const Eigen::Vector3d f_naive = T_imu_body.linear().transpose() * f_imu;
        EXPECT_GT((f_naive - f_body_expected).norm(), 10 * (f_body - f_body_expected).norm());
    }
}

TEST(Preintegration, BiasJacobiansPredictReintegration) {
    const SyntheticMotion m;
    const ImuBiases b0;
    ImuBiases b1;
    b1.gyro_radps = Eigen::Vector3d(0.004, -0.003, 0.005);
    b1.accel_mps2 = Eigen::Vector3d(0.05, -0.04, 0.03);
    auto run = [&](const ImuBiases& b) {
        Preintegrator p(b);
        ImuReading r0 = correctBiases(m.sample(1.0), b);
        for (int k = 1; k <= 200; ++k) {
            const ImuReading r1 = correctBiases(m.sample(1.0 + k * 0.005), b);
            p.add(r0, r1, 0.005);
            r0 = r1;
        }
        return p.result();
    };
    const Preintegrated p0 = run(b0);
    const Preintegrated p1 = run(b1);
    // First-order re-evaluation vs re-integration over 1 s: second-order residue only.
    EXPECT_LT(rotationAngle(p0.rotation(b1), p1.dR), 2e-5);
    EXPECT_LT((p0.velocity(b1) - p1.dv).norm(), 5e-4);  // 2nd order: |a| |dbg T|^2 / 2 ~ 2.5e-4
    EXPECT_GT((p0.dv - p1.dv).norm(), 0.03);
    EXPECT_LT((p0.position(b1) - p1.dp).norm(), 1e-4);
    // ...and the bias change itself is much larger than that residue.
    EXPECT_GT((p0.dp - p1.dp).norm(), 0.01);
    // Increments agree with the true motion: dp = R0^T (p1 - p0 - v0 dt - g dt^2 / 2).
    const Eigen::Vector3d dp_true =
        m.R(1.0).transpose() * (m.p(2.0) - m.p(1.0) - m.v(1.0) - 0.5 * gravityWorld(9.81));
    EXPECT_LT((p0.dp - dp_true).norm(), 1e-4);
}

}  // namespace
}  // namespace handscan::imu
