// recompensateSweep: a sweep assembled with one motion estimate is placed again with another
// (the IMU prediction after a scan-matching correction), exactly as if it had been assembled with
// it, and a motion estimate that does not cover the sweep leaves it untouched with an error.
#include "handscan/lio/motion_compensation.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/core/se3.hpp"

namespace handscan::lio {
namespace {

// A smooth body motion (walking speed, turning) and a second one offset from it by a constant
// correction after t = 0.3 s: the prediction before and after a feedback arrived mid-sweep.
Eigen::Isometry3d motion(TimeNs t) {
    const double s = toSeconds(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSO3(Eigen::Vector3d(0.1 * std::sin(2.0 * s), 0.05 * s, 0.8 * s));
    T.translation() =
        Eigen::Vector3d(1.0 * s, 0.2 * std::sin(3.0 * s), 1.3 + 0.02 * std::sin(11.0 * s));
    return T;
}

scan::Sweep sweepAssembledWith(const std::function<Eigen::Isometry3d(TimeNs)>& assembled_with) {
    scan::Sweep sweep;
    sweep.t_start = 0;
    sweep.T_world_start_odom = assembled_with(0);
    for (int i = 0; i < 500; ++i) {
        scan::SweepPoint p;
        p.t = static_cast<TimeNs>(i) * kNsPerMs;  // 0.5 s of points
        p.p_body =
            Eigen::Vector3d(3.0 * std::cos(0.1 * i), 2.0 * std::sin(0.1 * i), 0.5 + 0.01 * i);
        p.p_start = sweep.T_world_start_odom.inverse() * assembled_with(p.t) * p.p_body;
        sweep.points.push_back(p);
    }
    sweep.t_end = sweep.points.back().t;
    return sweep;
}

TEST(MotionCompensation, PlacesEveryPointWithTheCorrectedMotion) {
    // Assembled partly before a correction (the first 300 ms with the old prediction).
    const Eigen::Isometry3d correction =
        expSE3((Vector6d() << 0.01, -0.02, 0.03, 0.10, -0.05, 0.02).finished());
    auto before_then_after = [&](TimeNs t) {
        return t < 300 * kNsPerMs ? motion(t) : correction * motion(t);
    };
    scan::Sweep sweep = sweepAssembledWith(before_then_after);
    const scan::Sweep expected =
        sweepAssembledWith([&](TimeNs t) { return correction * motion(t); });
    double before = 0.0;
    for (std::size_t i = 0; i < sweep.points.size(); ++i)
        before = std::max(before, (sweep.points[i].p_start - expected.points[i].p_start).norm());
    EXPECT_GT(before, 0.05);  // the mixed sweep is torn by the correction

    auto query = [&](TimeNs t) -> Result<Eigen::Isometry3d> { return correction * motion(t); };
    ASSERT_TRUE(recompensateSweep(sweep, query).isOk());
    double after = 0.0;
    for (std::size_t i = 0; i < sweep.points.size(); ++i)
        after = std::max(after, (sweep.points[i].p_start - expected.points[i].p_start).norm());
    // The motion is sampled every 2 ms and interpolated: sub-millimetre.
    EXPECT_LT(after, 1e-4);
    EXPECT_TRUE(
        (sweep.T_world_start_odom.matrix() - expected.T_world_start_odom.matrix()).isZero(1e-12));
}

TEST(MotionCompensation, AnUncoveredTimeLeavesTheSweepUnchanged) {
    scan::Sweep sweep = sweepAssembledWith(motion);
    const scan::Sweep original = sweep;
    auto query = [](TimeNs t) -> Result<Eigen::Isometry3d> {
        if (t > 200 * kNsPerMs) return Status(StatusCode::kNotFound, "beyond the IMU history");
        return motion(t);
    };
    const Status s = recompensateSweep(sweep, query);
    EXPECT_EQ(s.code(), StatusCode::kNotFound);
    for (std::size_t i = 0; i < sweep.points.size(); ++i)
        EXPECT_EQ(sweep.points[i].p_start, original.points[i].p_start);
    EXPECT_TRUE(sweep.T_world_start_odom.isApprox(original.T_world_start_odom));
}

}  // namespace
}  // namespace handscan::lio
