// MotionEstimator on synthetic key-frame / frame pairs with known motion: eqs. (6)-(8)'s
// Jacobians against numerical differentiation, recovery of the motion from features with depth
// (with outliers), from features without depth, and the section 8 degeneracy: no features leave
// every direction unsolved (the IMU prediction stands), features without depth leave the
// translation's scale along the motion unsolved.
#include "handscan/vio/motion_estimator.hpp"

#include <gtest/gtest.h>

#include <random>

namespace handscan::vio {
namespace {

constexpr double kFocal = 290.0;

Eigen::Isometry3d motion(const Vector6d& xi) { return expSE3(xi); }

// Points in front of the key-frame, projected into frame c through T_l_c with pixel noise.
std::vector<FeatureConstraint> features(const Eigen::Isometry3d& T_l_c, int count, bool depth,
                                        double noise_px, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(-0.9, 0.9), z(1.5, 8.0);
    std::normal_distribution<double> noise(0.0, noise_px / kFocal);
    std::vector<FeatureConstraint> out;
    while (static_cast<int>(out.size()) < count) {
        const double d = z(rng);
        const Eigen::Vector3d X_l(xy(rng) * d, xy(rng) * d, d);
        const Eigen::Vector3d X_c = T_l_c * X_l;
        if (X_c.z() < 0.5) continue;
        FeatureConstraint f;
        f.has_depth = depth;
        f.X_l = depth ? X_l : Eigen::Vector3d(X_l / X_l.z());
        f.xbar_c = X_c.head<2>() / X_c.z() + Eigen::Vector2d(noise(rng), noise(rng));
        out.push_back(f);
    }
    return out;
}

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
    return (a.translation() - b.translation()).norm();
}

TEST(MotionEstimator, JacobiansMatchNumericalDifferentiation) {
    Vector6d xi;
    xi << 0.05, -0.1, 0.02, 0.3, -0.1, 0.2;
    const Eigen::Isometry3d T = motion(xi);
    for (const bool depth : {true, false}) {
        const auto fs = features(T * motion(Vector6d::Constant(0.01)), 5, depth, 0.0, 3);
        for (const FeatureConstraint& f : fs) {
            Eigen::Vector2d r;
            Eigen::Matrix<double, 2, 6> J;
            const int rows = constraintResiduals(f, T, r, J);
            EXPECT_EQ(rows, depth ? 2 : 1);
            for (int k = 0; k < 6; ++k) {
                const double h = 1e-6;
                Eigen::Vector2d rp, rm;
                Eigen::Matrix<double, 2, 6> unused;
                constraintResiduals(f, expSE3(Vector6d::Unit(k) * h) * T, rp, unused);
                constraintResiduals(f, expSE3(-Vector6d::Unit(k) * h) * T, rm, unused);
                const Eigen::Vector2d numeric = (rp - rm) / (2 * h);
                EXPECT_NEAR(J(0, k), numeric(0), 1e-6) << "depth " << depth << " column " << k;
                EXPECT_NEAR(J(1, k), numeric(1), 1e-6) << "depth " << depth << " column " << k;
            }
        }
    }
}

// The residual-only overload (trial steps, reweighting) gives the very values of the full one:
// the estimate must not depend on which of the two computed a residual.
TEST(MotionEstimator, ResidualsWithoutJacobiansAreTheSameBitForBit) {
    Vector6d xi;
    xi << 0.05, -0.1, 0.02, 0.3, -0.1, 0.2;
    const Eigen::Isometry3d T = motion(xi);
    for (const bool depth : {true, false}) {
        for (const FeatureConstraint& f : features(T, 50, depth, 0.7, 4)) {
            Eigen::Vector2d r_full, r_only;
            Eigen::Matrix<double, 2, 6> J;
            const int rows = constraintResiduals(f, T, r_full, J);
            EXPECT_EQ(constraintResiduals(f, T, r_only), rows);
            EXPECT_EQ(r_only(0), r_full(0));
            EXPECT_EQ(r_only(1), r_full(1));
        }
    }
}

TEST(MotionEstimator, RecoversKnownMotionFromFeaturesWithDepthDespiteOutliers) {
    Vector6d xi;
    xi << 0.03, -0.08, 0.02, 0.15, -0.05, 0.2;
    const Eigen::Isometry3d truth = motion(xi);
    auto fs = features(truth, 150, true, 0.7, 1);
    // 20 % gross outliers: features the tracker followed onto something else.
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> off(-0.2, 0.2);
    for (std::size_t i = 0; i < fs.size(); i += 5) fs[i].xbar_c += Eigen::Vector2d(off(rng), 0.1);
    // Start 3 degrees and 10 cm away, as an IMU prediction over a second could be.
    Vector6d err;
    err << 0.03, 0.03, -0.03, 0.06, -0.06, 0.05;
    const MotionEstimator est;
    const MotionResult res = est.estimate(fs, expSE3(err) * truth, std::nullopt, kFocal);
    EXPECT_LT(translationError(res.T_l_c, truth), 0.006) << "m";
    EXPECT_LT(rotationAngle(res.T_l_c.linear(), truth.linear()), 0.002) << "rad";
    // The error is as large as the noise explains: its Mahalanobis distance under the whitened
    // information (noise 0.7 px against the 1 px assumed) below chi2(6 dof, 99.9 %) = 22.5.
    const Vector6d e = logSE3(truth * res.T_l_c.inverse());
    EXPECT_LT(e.dot(res.information * e), 22.5);
    EXPECT_EQ(res.degeneracy.well_conditioned, 6);
    EXPECT_EQ(res.degeneracy.solved_dof_mask, scan::kAllDof);
    int outliers_found = 0, inliers_lost = 0;
    for (std::size_t i = 0; i < fs.size(); ++i) {
        if (i % 5 == 0) outliers_found += res.inlier[i] ? 0 : 1;
        if (i % 5 != 0) inliers_lost += res.inlier[i] ? 0 : 1;
    }
    EXPECT_EQ(outliers_found, 30);
    EXPECT_LE(inliers_lost, 3);
    EXPECT_LT(res.rms_px, 1.2);
}

TEST(MotionEstimator, FeaturesWithoutDepthSolveRotationButNotTheScaleAlongTheMotion) {
    Vector6d xi;
    xi << 0.02, 0.05, -0.01, 0.3, 0.0, 0.1;
    const Eigen::Isometry3d truth = motion(xi);
    const auto fs = features(truth, 200, false, 0.3, 2);
    // The IMU prior holds the true motion but 20 % too long along it.
    ImuMotionPrior prior;
    prior.T_l_c = truth;
    prior.T_l_c.translation() *= 1.2;
    prior.T_l_c.linear() = expSO3(Eigen::Vector3d(0.01, -0.01, 0.01)) * truth.linear();
    prior.information.diagonal() << 1e2, 1e2, 1e2, 1e2, 1e2, 1e2;
    const MotionResult res = MotionEstimator().estimate(fs, prior.T_l_c, prior, kFocal);
    // eq. (8) cannot see the length of t: exactly one unsolved direction, along t itself.
    EXPECT_EQ(res.degeneracy.well_conditioned, 5);
    const Vector6d weakest = res.degeneracy.V.row(5).transpose();
    const Eigen::Vector3d t_dir = truth.translation().normalized();
    EXPECT_GT(std::abs(weakest.tail<3>().dot(t_dir)), 0.95);
    // Rotation comes from the camera, the length along t stays the prior's.
    EXPECT_LT(rotationAngle(res.T_l_c.linear(), truth.linear()), 0.002);
    EXPECT_NEAR(res.T_l_c.translation().norm(), prior.T_l_c.translation().norm(), 0.01);
    EXPECT_GT(res.T_l_c.translation().normalized().dot(t_dir), 0.999);
}

// Shortly after a key-frame the camera has moved less than eq. (8)'s t_min (0.1 m): features
// without depth must not shorten the IMU's translation (t = 0 fits eq. 8 exactly, and their
// noise had pulled the simulated walks' VIO to a standstill: tunnel 62 % drift). With the VIO's
// own prior (eq. 11 at 0.1 s: 5 mm, 1 mrad) the length stays the prior's.
TEST(MotionEstimator, FeaturesWithoutDepthDoNotShortenAShortMotion) {
    Vector6d xi;
    xi << 0.01, -0.02, 0.005, 0.03, 0.005, 0.02;
    const Eigen::Isometry3d truth = motion(xi);
    const auto fs = features(truth, 200, false, 1.0, 5);
    ImuMotionPrior prior;
    prior.T_l_c = truth;
    prior.information.diagonal() << 1e6, 1e6, 1e6, 4e4, 4e4, 4e4;
    const MotionResult res = MotionEstimator().estimate(fs, prior.T_l_c, prior, kFocal);
    EXPECT_NEAR(res.T_l_c.translation().norm(), truth.translation().norm(),
                0.02 * truth.translation().norm());
    EXPECT_LT(rotationAngle(res.T_l_c.linear(), truth.linear()), 0.002);
}

TEST(MotionEstimator, TexturelessFrameKeepsTheImuPredictionInEveryDirection) {
    ImuMotionPrior prior;
    prior.T_l_c = motion((Vector6d() << 0.01, 0.02, 0.0, 0.1, 0.0, 0.05).finished());
    prior.information = Matrix6d::Identity() * 1e4;
    const MotionResult res = MotionEstimator().estimate({}, prior.T_l_c, prior, kFocal);
    EXPECT_EQ(res.degeneracy.well_conditioned, 0);
    EXPECT_EQ(res.degeneracy.solved_dof_mask, 0);
    EXPECT_TRUE(res.T_l_c.isApprox(prior.T_l_c));
}

TEST(MotionEstimator, FewDistantFeaturesLeaveTranslationUnsolved) {
    // Three features 40 m away: rotation is seen, translation hardly (std >> 2 cm).
    Vector6d xi;
    xi << 0.0, 0.02, 0.0, 0.05, 0.0, 0.0;
    const Eigen::Isometry3d truth = motion(xi);
    std::vector<FeatureConstraint> fs;
    for (const Eigen::Vector3d& X :
         {Eigen::Vector3d(-10, 2, 40), Eigen::Vector3d(5, -3, 40), Eigen::Vector3d(0, 6, 40)}) {
        FeatureConstraint f;
        f.has_depth = true;
        f.X_l = X;
        const Eigen::Vector3d Xc = truth * X;
        f.xbar_c = Xc.head<2>() / Xc.z();
        fs.push_back(f);
    }
    const MotionResult res = MotionEstimator().estimate(fs, truth, std::nullopt, kFocal);
    EXPECT_LT(res.degeneracy.well_conditioned, 6);
    EXPECT_GE(res.degeneracy.well_conditioned, 2);
    EXPECT_EQ(res.degeneracy.solved_dof_mask & (scan::kTx | scan::kTy | scan::kTz), 0);
}

}  // namespace
}  // namespace handscan::vio
