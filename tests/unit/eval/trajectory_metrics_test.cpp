// ATE after SE(3) alignment, segment drift, end-point error, TUM input/output.
#include "handscan/eval/trajectory_metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "handscan/core/se3.hpp"
#include "handscan/eval/trajectory_plot.hpp"

namespace handscan::eval {
namespace {

// A hand-held-like 3D loop: 60 s around a 10 m x 6 m ellipse with height and attitude wobble.
Trajectory loop(double rate_hz, double t0 = 0.0, double duration = 60.0) {
    Trajectory out;
    for (int k = 0; k * (1.0 / rate_hz) <= duration + 1e-9; ++k) {
        const double t = t0 + k / rate_hz;
        const double a = 2 * M_PI * t / 60.0;
        StampedPose p;
        p.t_s = t;
        p.T.translation() =
            Eigen::Vector3d(5 * std::cos(a), 3 * std::sin(a), 1.5 + 0.2 * std::sin(3 * a));
        p.T.linear() =
            expSO3(Eigen::Vector3d(0.1 * std::sin(2 * a), 0.05 * std::cos(5 * a), a + M_PI / 2));
        out.push_back(p);
    }
    return out;
}

TEST(Ate, ZeroAfterAligningAKnownRigidOffset) {
    const Trajectory gt = loop(200.0);
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
    offset.linear() = expSO3(Eigen::Vector3d(0.3, -0.2, 1.1));
    offset.translation() = Eigen::Vector3d(12.0, -4.0, 2.5);
    Trajectory est = loop(20.0, 0.0025);  // other rate, off-grid times: association interpolates
    for (auto& p : est) p.T = offset * p.T;
    const auto pairs = associate(gt, est);
    ASSERT_GT(pairs.size(), 1000u);
    const AteResult ate = computeAte(pairs);
    EXPECT_LT(ate.translation_m.rmse, 1e-4);  // interpolation of the 200 Hz truth only
    EXPECT_LT(ate.translation_m.max, 2e-4);
    EXPECT_LT(ate.rotation_deg.max, 0.01);
    EXPECT_LT((ate.T_gt_est * offset).translation().norm(), 1e-4);  // recovers offset^-1
    // Relative metrics need no alignment: zero too.
    EXPECT_LT(computeDrift(pairs).mean_translation_percent, 1e-3);
    EXPECT_LT(computeEndPoint(pairs).error_m, 1e-4);
}

TEST(Ate, StatisticsOfAKnownErrorPattern) {
    const Trajectory gt = loop(10.0);
    Trajectory est = gt;
    // +-5 cm alternating perpendicular to the plane: alignment cannot remove it.
    for (std::size_t i = 0; i < est.size(); ++i)
        est[i].T.translation().z() += (i % 2 ? 0.05 : -0.05);
    const AteResult ate = computeAte(associate(gt, est));
    EXPECT_NEAR(ate.translation_m.rmse, 0.05, 2e-3);
    EXPECT_NEAR(ate.translation_m.median, 0.05, 2e-3);
    EXPECT_NEAR(ate.translation_m.max, 0.05, 2e-3);
}

// A walk over flat ground: positions alone fit the estimate's mirror image as well as the estimate
// (a proper rotation turning it upside down does the mirroring). A drifting estimate that happens
// to look mirrored must not be reported 180 degrees off: the orientations choose the branch.
TEST(Ate, PlanarPathDoesNotFlipUpsideDown) {
    Trajectory gt = loop(10.0);
    for (auto& p : gt) p.T.translation().z() = 1.5;
    Trajectory est = gt;
    for (auto& p : est) p.T.translation().y() = -p.T.translation().y() + 0.5;  // the mirror image
    const auto pairs = associate(gt, est);
    const Alignment a = alignTrajectories(pairs);
    EXPECT_TRUE(a.planar);
    EXPECT_TRUE(a.took_other_branch);
    const AteResult ate = computeAte(pairs);
    EXPECT_TRUE(ate.orientation_chose_branch);
    EXPECT_LT(ate.rotation_deg.max, 0.01);   // the orientations are the truth's
    EXPECT_GT(ate.translation_m.rmse, 1.0);  // the positions are not: the error stays visible
    EXPECT_GT((ate.T_gt_est.linear() * Eigen::Vector3d::UnitZ()).z(), 0.999);  // up stays up
}

// A path with real extent in all three directions keeps the plain position fit: a mirrored
// estimate is then reported as the poor fit it is, whatever the orientations say.
TEST(Ate, NonPlanarPathKeepsThePositionFit) {
    Trajectory gt = loop(10.0);
    for (auto& p : gt) p.T.translation().z() = 3.0 * std::sin(2 * M_PI * p.t_s / 30.0);
    Trajectory est = gt;
    for (auto& p : est) p.T.translation().y() = -p.T.translation().y();
    const AteResult ate = computeAte(associate(gt, est));
    EXPECT_FALSE(ate.planar_path);
    EXPECT_FALSE(ate.orientation_chose_branch);
    EXPECT_GT(ate.rotation_deg.rmse, 1.0);
}

TEST(Drift, ScaleDriftGivesItsPercentage) {
    // Straight 100 m walk; the estimate is 1 % too long.
    Trajectory gt, est;
    for (int k = 0; k <= 1000; ++k) {
        StampedPose p;
        p.t_s = k * 0.1;
        p.T.translation() = Eigen::Vector3d(0.1 * k, 0.0, 0.0);
        gt.push_back(p);
        p.T.translation() *= 1.01;
        est.push_back(p);
    }
    const auto pairs = associate(gt, est);
    const DriftResult d = computeDrift(pairs);
    ASSERT_EQ(d.per_length.size(), 4u);
    for (const auto& s : d.per_length) {
        EXPECT_GT(s.segments, 10u) << s.length_m;
        EXPECT_NEAR(s.translation_percent, 1.0, 1e-6) << s.length_m;
        EXPECT_NEAR(s.rotation_deg_per_m, 0.0, 1e-9);
    }
    EXPECT_NEAR(d.mean_translation_percent, 1.0, 1e-6);
    EXPECT_NEAR(d.path_length_m, 100.0, 1e-9);
    const EndPointResult e = computeEndPoint(pairs);
    EXPECT_FALSE(e.is_loop);
    EXPECT_NEAR(e.error_m, 1.0, 1e-9);
    EXPECT_NEAR(e.error_percent, 1.0, 1e-9);
}

TEST(Drift, YawDriftOnALoopShowsInTheEndPoint) {
    const Trajectory gt = loop(10.0);
    // The estimate's heading drifts linearly to 2 deg at the end: positions swing accordingly.
    Trajectory est;
    const Eigen::Vector3d start = gt.front().T.translation();
    for (const auto& p : gt) {
        Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
        drift.linear() = expSO3(Eigen::Vector3d(0, 0, 2.0 * M_PI / 180.0 * p.t_s / 60.0));
        drift.translation() = start - drift.linear() * start;  // about the start point
        est.push_back({p.t_s, drift * p.T});
    }
    const auto pairs = associate(gt, est);
    const EndPointResult e = computeEndPoint(pairs);
    EXPECT_TRUE(e.is_loop);
    ASSERT_EQ(pairs.size(), gt.size());  // 10 Hz truth: every pose pairs up (no rounding gaps)
    EXPECT_NEAR(e.rotation_error_deg, 2.0, 1e-6);
    EXPECT_GT(computeDrift(pairs).mean_rotation_deg_per_m, 0.0);
}

TEST(Tum, RoundTripAndErrors) {
    const Trajectory gt = loop(5.0, 1403715273.262, 4.0);
    const std::string path = std::string(HANDSCAN_BINARY_DIR) + "/eval_roundtrip.tum";
    ASSERT_TRUE(writeTum(path, gt).isOk());
    auto back = readTum(path);
    ASSERT_TRUE(back) << back.status().message();
    ASSERT_EQ(back->size(), gt.size());
    for (std::size_t i = 0; i < gt.size(); ++i) {
        EXPECT_NEAR((*back)[i].t_s, gt[i].t_s, 1e-6);
        EXPECT_LT(((*back)[i].T.translation() - gt[i].T.translation()).norm(), 1e-6);
        EXPECT_LT(rotationAngle((*back)[i].T.linear(), gt[i].T.linear()), 1e-8);
    }
    std::filesystem::remove(path);

    auto short_line = parseTum("# c\n1.0 0 0 0 0 0 0 1\n2.0 1 2 3\n", "x.tum");
    ASSERT_FALSE(short_line.isOk());
    EXPECT_NE(short_line.status().message().find("x.tum:3"), std::string::npos);
    auto backwards = parseTum("2.0 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", "y.tum");
    ASSERT_FALSE(backwards.isOk());
    EXPECT_NE(backwards.status().message().find("y.tum:2"), std::string::npos);
    auto bad_quat = parseTum("1.0 0 0 0 0 0 0 0\n", "z.tum");
    EXPECT_FALSE(bad_quat.isOk());
    EXPECT_FALSE(readTum("/nonexistent/file.tum").isOk());
}

TEST(Plot, WritesATopViewPng) {
    const Trajectory gt = loop(10.0);
    const auto pairs = associate(gt, gt);
    const std::string path = std::string(HANDSCAN_BINARY_DIR) + "/eval_plot.png";
    ASSERT_TRUE(plotTopView(path, pairs, Eigen::Isometry3d::Identity(), 400).isOk());
    EXPECT_GT(std::filesystem::file_size(path), 1000u);
    std::filesystem::remove(path);
    EXPECT_FALSE(
        plotTopView("/nonexistent/dir/p.png", pairs, Eigen::Isometry3d::Identity()).isOk());
}

}  // namespace
}  // namespace handscan::eval
