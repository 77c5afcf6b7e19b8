// Trajectories are C2 and their analytic derivatives match numerical differentiation; the
// aggressive motion reaches the paper's 370 deg/s; TUM files load.
#include "handscan/sim/trajectory.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "handscan/core/se3.hpp"
#include "handscan/sim/scenes.hpp"

namespace handscan::sim {
namespace {

void expectDerivativesConsistent(const Trajectory& tr, double t0, double t1) {
    const double h = 1e-4;
    for (double t = t0; t < t1; t += 0.37) {
        const BodyState s = tr.at(t), sp = tr.at(t + h), sm = tr.at(t - h);
        const Eigen::Vector3d v_num =
            (sp.T_world_body.translation() - sm.T_world_body.translation()) / (2 * h);
        EXPECT_LT((v_num - s.v_world).norm(), 1e-5) << t;
        const Eigen::Vector3d a_num = (sp.v_world - sm.v_world) / (2 * h);
        EXPECT_LT((a_num - s.a_world).norm(), 1e-3 * (1 + s.a_world.norm()) + 2e-3) << t;
        // omega in the body frame: R^T dR/dt = [omega]x
        const Eigen::Vector3d w_num =
            logSO3(sm.T_world_body.linear().transpose() * sp.T_world_body.linear()) / (2 * h);
        EXPECT_LT((w_num - s.omega_body).norm(), 1e-5 * (1 + s.omega_body.norm())) << t;
        const Eigen::Vector3d al_num = (sp.omega_body - sm.omega_body) / (2 * h);
        EXPECT_LT((al_num - s.alpha_body).norm(), 1e-3 * (1 + s.alpha_body.norm()) + 2e-3) << t;
    }
}

TEST(TrajectoryTest, WalkDerivativesAreExact) {
    WalkOptions o;
    o.duration_s = 40.0;
    const WalkPlan plan = makeWalk(buildScene("office").walk_loop, o);
    expectDerivativesConsistent(plan.trajectory, 0.05, 39.9);
}

TEST(TrajectoryTest, AggressiveReaches370DegPerSecond) {
    WalkOptions o;
    o.duration_s = 60.0;
    o.style = MotionStyle::kAggressive;
    const WalkPlan plan = makeWalk(buildScene("office").walk_loop, o);
    const double peak = plan.trajectory.peakAngularRate(0.002) * 180.0 / std::numbers::pi;
    EXPECT_NEAR(peak, 370.0, 5.0);
    expectDerivativesConsistent(plan.trajectory, 3.0, 59.0);
    // The body frame is the camera {C}: forward is +z, so the still start looks along the path.
    const Eigen::Matrix3d R = plan.trajectory.at(0.0).T_world_body.linear();
    EXPECT_NEAR(R.col(2).z(), std::sin(0.12), 0.2);  // held slightly pitched down
}

TEST(TrajectoryTest, TumRoundTrip) {
    const auto path = std::filesystem::temp_directory_path() / "handscan_sim_traj.tum";
    {
        std::ofstream f(path);
        f << "# t x y z qx qy qz qw\n";
        for (int k = 0; k <= 500; ++k) {
            const double t = 100.0 + 0.01 * k;
            const Eigen::Quaterniond q(
                Eigen::AngleAxisd(0.3 * std::sin(t), Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.2 * t, Eigen::Vector3d::UnitZ()));
            char line[200];
            std::snprintf(line, sizeof line, "%.4f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n", t,
                          std::cos(t), std::sin(t), 1.3, q.x(), q.y(), q.z(), q.w());
            f << line;
        }
    }
    auto tr = loadTum(path.string());
    ASSERT_TRUE(tr.isOk()) << tr.status().message();
    EXPECT_NEAR(tr->duration(), 5.0, 0.011);
    for (double t = 0.5; t < 4.5; t += 0.5) {
        const BodyState s = tr->at(t);
        EXPECT_NEAR(s.T_world_body.translation().x(), std::cos(100.0 + t), 2e-4);
        const Eigen::Quaterniond q(
            Eigen::AngleAxisd(0.3 * std::sin(100.0 + t), Eigen::Vector3d::UnitY()) *
            Eigen::AngleAxisd(0.2 * (100.0 + t), Eigen::Vector3d::UnitZ()));
        EXPECT_LT(rotationAngle(s.T_world_body.linear(), q.toRotationMatrix()), 1e-3);
    }
    {
        std::ofstream f(path);
        f << "1.0 0 0 0 0 0 0 1\n2.0 0 0 zero\n";
    }
    auto bad = loadTum(path.string());
    ASSERT_FALSE(bad.isOk());
    EXPECT_NE(bad.status().message().find(":2:"), std::string::npos) << bad.status().message();
    std::filesystem::remove(path);
}

}  // namespace
}  // namespace handscan::sim
