// replay::ReferenceMotion: the --reference-motion diagnostic's motion and priors.
#include "handscan/replay/reference_motion.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "handscan/core/se3.hpp"

namespace handscan::replay {
namespace {

tum::Trajectory straightWalk() {
    tum::Trajectory tr;
    for (int i = 0; i <= 10; ++i) {
        tum::StampedPose p;
        p.t_s = 1.0 + 0.1 * i;
        p.T.translation() = Eigen::Vector3d(0.1 * i, 0.0, 1.5);
        p.T.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
        tr.push_back(p);
    }
    return tr;
}

TEST(ReferenceMotion, InterpolatesBetweenPosesAndClampsAtTheEnds) {
    const ReferenceMotion m(straightWalk(), 0.0, 0.0, 0.01, 0.01);
    const Eigen::Isometry3d mid = m.poseAt(fromSeconds(1.25));
    EXPECT_NEAR(mid.translation().x(), 0.25, 1e-9);
    EXPECT_NEAR(rotationAngle(mid.linear(), Eigen::Matrix3d::Identity()), 0.125, 1e-9);
    EXPECT_NEAR(m.poseAt(fromSeconds(0.0)).translation().x(), 0.0, 1e-12);
    EXPECT_NEAR(m.poseAt(fromSeconds(9.0)).translation().x(), 1.0, 1e-12);
}

TEST(ReferenceMotion, PerturbsEveryMatchButTheOneThatFoundsTheMapAndTheSameOnEveryRun) {
    const double perturb_m = 0.05, perturb_rad = 0.01;
    const ReferenceMotion m(straightWalk(), perturb_m, perturb_rad, 0.02, 0.1);
    scan::Sweep sweep;
    sweep.index = 7;
    sweep.T_world_start_odom = m.poseAt(fromSeconds(1.3));

    const auto founding = m.matchPrior(sweep, 0);
    ASSERT_EQ(founding.size(), 1u);
    EXPECT_TRUE(founding[0].T_world_body.isApprox(sweep.T_world_start_odom, 1e-12));

    const auto later = m.matchPrior(sweep, 3);
    ASSERT_EQ(later.size(), 1u);
    const Eigen::Isometry3d d = sweep.T_world_start_odom.inverse() * later[0].T_world_body;
    EXPECT_NEAR(d.translation().norm(), perturb_m, 1e-9);
    EXPECT_NEAR(rotationAngle(d.linear(), Eigen::Matrix3d::Identity()), perturb_rad, 1e-9);
    EXPECT_TRUE(m.matchPrior(sweep, 3)[0].T_world_body.isApprox(later[0].T_world_body, 0.0));
    EXPECT_DOUBLE_EQ(later[0].information(0, 0), 1.0 / (0.02 * 0.02));
    EXPECT_DOUBLE_EQ(later[0].information(5, 5), 1.0 / (0.1 * 0.1));

    // Another sweep, another error direction.
    sweep.index = 8;
    const Eigen::Isometry3d d8 =
        sweep.T_world_start_odom.inverse() * m.matchPrior(sweep, 4)[0].T_world_body;
    EXPECT_GT((d8.translation() - d.translation()).norm(), 1e-3);
}

TEST(ReferenceMotion, LoadNamesTheFileThatCannotServe) {
    const auto dir = std::filesystem::temp_directory_path() / "handscan_reference_motion_test";
    std::filesystem::create_directories(dir);
    const std::string one_pose = (dir / "one.tum").string();
    std::ofstream(one_pose) << "1.0 0 0 0 0 0 0 1\n";
    auto r = ReferenceMotion::load(one_pose, 0.0, 0.0, 0.01, 0.01);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find(one_pose), std::string::npos);
    EXPECT_NE(r.status().message().find("two poses"), std::string::npos);

    auto missing = ReferenceMotion::load((dir / "missing.tum").string(), 0.0, 0.0, 0.01, 0.01);
    ASSERT_FALSE(missing.isOk());
    EXPECT_NE(missing.status().message().find("missing.tum"), std::string::npos);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace handscan::replay
