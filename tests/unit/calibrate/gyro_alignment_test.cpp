// The gyro alignment on synthetic data: matched sweep rotations made from a known motion, turned
// about the shaft axis by a known encoder-zero error, against a gyro that is late by a known time
// and biased; the alignment must find the turn and the time within its reported uncertainty.
#include "handscan/calibrate/gyro_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/core/se3.hpp"

namespace handscan::calibrate {
namespace {

// A hand-held wobble: rates of a few tenths of rad/s on every axis, changing within a second.
Eigen::Vector3d trueRate(double t) {
    return {0.6 * std::sin(1.7 * t) + 0.3 * std::sin(5.1 * t + 1.0),
            0.5 * std::cos(1.3 * t + 0.4) + 0.2 * std::sin(4.3 * t),
            0.4 * std::sin(0.9 * t + 2.0) + 0.25 * std::cos(3.7 * t)};
}

struct Synthetic {
    std::vector<MatchedSweepPose> sweeps;
    std::vector<ImuSample> imu;
};

Synthetic make(double zero_error_rad, double imu_late_s, const Eigen::Vector3d& bias,
               const Eigen::Vector3d& axis) {
    Synthetic s;
    const double dt = 0.0025;  // 400 Hz
    Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(zero_error_rad, axis).toRotationMatrix();
    for (int i = 0; i <= static_cast<int>(30.0 / dt); ++i) {
        const double t = i * dt;
        if (i % 200 == 0) {  // a sweep every half second: the laser sees the body turned
            MatchedSweepPose p;
            p.index = static_cast<std::uint64_t>(i / 200);
            p.t_s = t;
            p.q_world_body = Eigen::Quaterniond(R * turn.transpose());
            s.sweeps.push_back(p);
        }
        // The sample measured at t carries the stamp t + imu_late_s.
        ImuSample m;
        m.t_host = fromSeconds(t + imu_late_s);
        m.gyro_radps_imu = trueRate(t) + bias;
        s.imu.push_back(m);
        R = R * expSO3(trueRate(t + 0.5 * dt) * dt);
    }
    return s;
}

TEST(GyroAlignment, FindsTheShaftTurnAndTheImuDelay) {
    const Eigen::Vector3d axis = Eigen::Vector3d(0.0, 0.0, 1.0);
    const Eigen::Vector3d bias(0.01, -0.02, 0.005);
    const Synthetic s = make(0.3 * M_PI / 180.0, 0.0025, bias, axis);
    auto r = alignGyro(s.sweeps, s.imu, Eigen::Matrix3d::Identity(), axis);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_NEAR(r->zero_rad * 180.0 / M_PI, 0.3, 0.005);
    EXPECT_NEAR(r->imu_time_s * 1e3, 2.5, 0.05);
    EXPECT_NEAR((r->gyro_bias - bias).norm(), 0.0, 1e-3);
    EXPECT_LT(r->rms_after_rad, 0.1 * r->rms_before_rad);
}

TEST(GyroAlignment, TooFewTrustedSweepsIsAnErrorThatSaysWhatToDo) {
    Synthetic s = make(0.0, 0.0, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitZ());
    s.sweeps.resize(4);
    auto r = alignGyro(s.sweeps, s.imu, Eigen::Matrix3d::Identity(), Eigen::Vector3d::UnitZ());
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("pairs of trusted sweeps"), std::string::npos);
}

}  // namespace
}  // namespace handscan::calibrate
