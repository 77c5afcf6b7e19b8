#include "handscan/scan/sweep_assembler.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "spin_sim.hpp"

namespace handscan::scan {
namespace {

using testing::assemble;
using testing::deviceGeometry;
using testing::officeRoom;
using testing::simulate;

double maxSurfaceError(const Sweep& sweep, const testing::Scene& scene,
                       const Eigen::Isometry3d& T_world_start) {
    double worst = 0.0;
    for (const SweepPoint& p : sweep.points) {
        worst = std::max(worst, scene.distance(T_world_start * p.p_start));
    }
    return worst;
}

TEST(SweepAssembler, StaticRoomPointsLieOnTheWalls) {
    const auto scene = officeRoom();
    const auto T = testing::pose(0.1, -0.2, 0.3, 0.5, -0.2, 1.0);
    testing::SpinSimConfig sim;
    sim.range_noise_m = 0.0;
    const auto streams =
        simulate(scene, testing::staticPose(T), deviceGeometry(), kNsPerSec, 2 * kNsPerSec, sim);
    const auto sweeps = assemble(streams, deviceGeometry(), testing::staticPose(T));
    ASSERT_EQ(sweeps.size(), 3U);  // half revolutions; the 4th is still open
    for (const Sweep& s : sweeps) {
        EXPECT_EQ(s.lines.size(), 20U);
        EXPECT_GT(s.points.size(), 19000U);
        EXPECT_LT(maxSurfaceError(s, scene, s.T_world_start_odom), 1e-6);
    }
}

TEST(SweepAssembler, MovingDeviceIsDeskewedWithThePoseAtEachStep) {
    // 0.5 m/s and 60 deg/s during the sweep: a rigid-sweep assumption smears the walls by
    // decimetres; per-step poses put every point back on its wall.
    const auto scene = officeRoom();
    const auto traj = [](TimeNs t) {
        const double s = toSeconds(t - kNsPerSec);
        return testing::pose(0.1 * s, 1.0 * s, 0.05, 0.5 * s, 0.0, 0.3 * s);
    };
    testing::SpinSimConfig sim;
    sim.range_noise_m = 0.0;
    const auto streams = simulate(scene, traj, deviceGeometry(), kNsPerSec, 1200 * kNsPerMs, sim);
    const auto sweeps = assemble(streams, deviceGeometry(), traj);
    ASSERT_GE(sweeps.size(), 2U);
    EXPECT_LT(maxSurfaceError(sweeps[1], scene, sweeps[1].T_world_start_odom), 1e-6);
    EXPECT_NEAR(
        (sweeps[1].T_world_start_odom.translation() - traj(sweeps[1].t_start).translation()).norm(),
        0.0, 1e-9);

    const auto rigid =
        assemble(streams, deviceGeometry(), [&](TimeNs) { return traj(sweeps[1].t_start); });
    EXPECT_GT(maxSurfaceError(rigid[1], scene, rigid[1].T_world_start_odom), 0.1);
}

TEST(SweepAssembler, FullRevolutionBoundaryAndSplitScans) {
    const auto scene = officeRoom();
    const auto T = Eigen::Isometry3d::Identity();
    const auto streams =
        simulate(scene, testing::staticPose(T), deviceGeometry(), kNsPerSec, 3 * kNsPerSec);
    SweepAssemblerConfig half;
    SweepAssemblerConfig full;
    full.boundary = SweepBoundary::kFullRevolution;
    const auto h = assemble(streams, deviceGeometry(), testing::staticPose(T), half, true);
    const auto f = assemble(streams, deviceGeometry(), testing::staticPose(T), full, true);
    EXPECT_EQ(h.size(), 6U);
    EXPECT_EQ(f.size(), 3U);
    for (std::size_t i = 0; i + 1 < f.size(); ++i) {
        EXPECT_EQ(f[i].index, i);
        // 40 scans per revolution; a scan that straddles the boundary is split between sweeps.
        EXPECT_GE(f[i].lines.size(), 40U);
        EXPECT_LE(f[i].lines.size(), 41U);
        EXPECT_NEAR(toSeconds(f[i].t_end - f[i].t_start), 1.0, 0.03);
        EXPECT_LT(f[i].t_end, f[i + 1].t_start);
        for (const ScanLine& l : f[i].lines) {
            for (std::size_t k = l.begin + 1; k < l.end; ++k) {
                ASSERT_GT(f[i].points[k].step, f[i].points[k - 1].step);
                ASSERT_GE(f[i].points[k].t, f[i].points[k - 1].t);
            }
        }
    }
}

TEST(SweepAssembler, EncoderGapDropsOnlyTheUncoveredSteps) {
    const auto scene = officeRoom();
    const auto T = Eigen::Isometry3d::Identity();
    auto streams = simulate(scene, testing::staticPose(T), deviceGeometry(), kNsPerSec, kNsPerSec);
    // A 100 ms CAN dropout in the middle of the sweep.
    std::erase_if(streams.encoder, [](const EncoderSample& e) {
        return e.t_host > 1400 * kNsPerMs && e.t_host < 1500 * kNsPerMs;
    });
    SweepAssembler a(deviceGeometry(), {}, testing::staticPose(T));
    std::size_t e = 0;
    for (const LaserScan& s : streams.scans) {
        while (e < streams.encoder.size() &&
               streams.encoder[e].t_host <= s.stepTime(1080) + 10 * kNsPerMs) {
            ASSERT_TRUE(a.addEncoder(streams.encoder[e++]).isOk());
        }
        ASSERT_TRUE(a.addScan(s).isOk());
    }
    while (e < streams.encoder.size()) ASSERT_TRUE(a.addEncoder(streams.encoder[e++]).isOk());
    const Sweep last = a.flush();
    EXPECT_GT(a.stats().dropped_no_encoder, 3U * 1081U);
    EXPECT_LT(a.stats().dropped_no_encoder, 5U * 1081U);
    EXPECT_GT(a.stats().points, 30000U);
    EXPECT_FALSE(last.empty());

    const Status older = a.addEncoder(streams.encoder.front());
    EXPECT_FALSE(older.isOk());
    EXPECT_NE(older.message().find("not after the previous one"), std::string::npos);
    LaserScan bad;
    bad.t_host = 5;
    EXPECT_EQ(a.addScan(bad).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace handscan::scan
