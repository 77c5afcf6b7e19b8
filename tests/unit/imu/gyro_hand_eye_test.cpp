// The hand-eye model shared by `handscan calibrate` and the online clock tracker: its residuals
// (summed from per-sample prefix rotations) must equal the gyro integrated pair by pair, and a
// solve must find the total turn when the sweeps of a pair were assembled with different turns
// already applied (the tracker corrects while it measures).
#include "handscan/imu/gyro_hand_eye.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/core/se3.hpp"
#include "synthetic_motion.hpp"

namespace handscan::imu {
namespace {

const Eigen::Vector3d kAxis = Eigen::Vector3d(0.2, 0.1, 1.0).normalized();

// 30 s of gyro at 200 Hz, stamped `late_s` after the instant measured, with `bias`; sweeps every
// 0.5 s whose poses carry the turn eps - applied(k) about kAxis.
HandEyeProblem make(double eps, double late_s, const Eigen::Vector3d& bias,
                    double applied_per_sweep) {
    const testing::SyntheticMotion motion;
    HandEyeProblem p;
    p.axis_body = kAxis;
    for (int i = 0; i <= 6000; ++i) {
        const double t = 0.005 * i;
        ImuSample s = motion.sample(t);
        s.gyro_radps_imu += bias;
        s.t_host = fromSeconds(t + late_s);
        p.imu.push_back(s);
        p.t_s.push_back(t + late_s);
    }
    auto pose = [&](int k) {
        const double applied = applied_per_sweep * k;
        return Eigen::Matrix3d(
            motion.R(0.5 * k) *
            Eigen::AngleAxisd(eps - applied, kAxis).toRotationMatrix().transpose());
    };
    for (int k = 1; k + 1 < 58; ++k)
        for (int gap : {1, 4})
            if (k + gap < 58)
                p.pairs.push_back({0.5 * k, 0.5 * (k + gap), pose(k).transpose() * pose(k + gap),
                                   applied_per_sweep * k, applied_per_sweep * (k + gap)});
    return p;
}

TEST(GyroHandEye, ResidualsEqualThePairByPairIntegration) {
    const HandEyeProblem p = make(0.004, 0.002, Eigen::Vector3d(0.01, -0.02, 0.005), 0.0);
    HandEyeParams x;
    x << 0.003, 0.0015, 0.008, -0.01, 0.0;
    const Eigen::VectorXd r = handEyeResiduals(p, x);
    ASSERT_EQ(r.size(), static_cast<Eigen::Index>(3 * p.pairs.size()));
    for (std::size_t k = 0; k < p.pairs.size(); ++k) {
        const HandEyePair& q = p.pairs[k];
        const Eigen::Matrix3d R = Eigen::AngleAxisd(x[0], kAxis).toRotationMatrix();
        const Eigen::Matrix3d B =
            integrateGyro(p.imu, p.t_s, q.t0_s + x[1], q.t1_s + x[1], p.R_body_imu, x.tail<3>());
        const Eigen::Vector3d direct = logSO3(R.transpose() * q.A * R * B.transpose());
        EXPECT_LT((r.segment<3>(static_cast<Eigen::Index>(3 * k)) - direct).norm(), 1e-9) << k;
    }
}

TEST(GyroHandEye, FindsTheTotalTurnWhileCorrectionsAreApplied) {
    // Each sweep had 0.01 deg more of the turn taken out than the one before (0.3 deg by the end
    // of the walk): without the per-sweep applied turns the pairs disagree on eps.
    const double eps = 0.6 * M_PI / 180.0;
    const Eigen::Vector3d bias(0.01, -0.02, 0.005);
    const HandEyeProblem p = make(eps, 0.0025, bias, 0.01 * M_PI / 180.0);
    HandEyeCovariance covariance;
    const HandEyeParams x = solveHandEye(p, HandEyeParams::Zero(), &covariance);
    EXPECT_NEAR(x[kHandEyeTurn] * 180.0 / M_PI, 0.6, 0.002);
    EXPECT_NEAR(x[kHandEyeImuTime] * 1e3, 2.5, 0.02);
    EXPECT_LT((x.tail<3>() - bias).norm(), 1e-4);
    EXPECT_LT(std::sqrt(covariance(kHandEyeTurn, kHandEyeTurn)), 1e-4);

    HandEyeProblem ignored = p;
    for (HandEyePair& q : ignored.pairs) q.applied_turn0_rad = q.applied_turn1_rad = 0.0;
    const HandEyeParams wrong = solveHandEye(ignored, HandEyeParams::Zero());
    EXPECT_GT(handEyeResiduals(ignored, wrong).norm(), 10.0 * handEyeResiduals(p, x).norm());
}

}  // namespace
}  // namespace handscan::imu
