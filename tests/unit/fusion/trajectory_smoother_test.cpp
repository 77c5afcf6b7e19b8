// The kept trajectory (TrajectorySmoother): the real-time chain corrected to meet the scan matches
// on both sides of each segment.
#include "handscan/fusion/trajectory_smoother.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/core/se3.hpp"

namespace handscan::fusion {
namespace {

constexpr TimeNs kStep = 5 * kNsPerMs;  // 200 Hz

// The true motion: a walk on a circle of 3 m, turning with it, bobbing 2 cm.
Eigen::Isometry3d truth(TimeNs t) {
    const double s = toSeconds(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSO3(Eigen::Vector3d(0.02 * std::sin(3 * s), 0.0, 0.4 * s));
    T.translation() =
        Eigen::Vector3d(3 * std::cos(0.4 * s), 3 * std::sin(0.4 * s), 0.02 * std::sin(11 * s));
    return T;
}

// What the real-time chain carries forward from an anchor at t_a: the truth with a drift that
// grows with time since the anchor, `order` 1 linearly, 2 quadratically (an accelerometer bias).
Eigen::Isometry3d carried(TimeNs t_a, TimeNs t, int order) {
    const double d = std::pow(toSeconds(t - t_a), order);
    Eigen::Isometry3d T = truth(t);
    T.linear() = expSO3(Eigen::Vector3d(0.0, 0.004, 0.01) * d) * T.linear();
    T.translation() += Eigen::Vector3d(0.03, -0.02, 0.01) * d;
    return T;
}

PoseEstimate at(TimeNs t, const Eigen::Isometry3d& T) {
    PoseEstimate p;
    p.t_host = t;
    p.T_world_body = T;
    p.solved_dof_mask = 0x3f;
    return p;
}

double translationError(const PoseEstimate& p) {
    return (p.T_world_body.translation() - truth(p.t_host).translation()).norm();
}

double rotationError(const PoseEstimate& p) {
    return logSO3(p.T_world_body.linear() * truth(p.t_host).linear().transpose()).norm();
}

// Real-time poses from 0 to t_end at 200 Hz carried from the anchor before each, anchors
// (matches equal to the truth) every `period`, reported `delay` after their time.
struct SmoothedRun {
    std::vector<PoseEstimate> kept;
    double worst_realtime_m = 0;
};

SmoothedRun run(TimeNs period, TimeNs delay, TimeNs t_end, int order) {
    TrajectorySmoother smoother;
    SmoothedRun r;
    TimeNs anchor_t = 0;     // the newest anchor the chain carries forward from
    TimeNs next_anchor = 0;  // the next match's time
    for (TimeNs t = 0; t <= t_end; t += kStep) {
        // A match is reported `delay` after its time: close the segment before it.
        if (next_anchor + delay == t) {
            const TimeNs from = anchor_t;
            smoother.anchor(
                at(next_anchor, truth(next_anchor)),
                [&](TimeNs q) -> Result<Eigen::Isometry3d> { return carried(from, q, order); });
            anchor_t = next_anchor;
            next_anchor += period;
        }
        const PoseEstimate p = at(t, carried(anchor_t, t, order));
        r.worst_realtime_m = std::max(r.worst_realtime_m, translationError(p));
        smoother.add(p);
        for (const PoseEstimate& k : smoother.take()) r.kept.push_back(k);
    }
    smoother.flush();
    for (const PoseEstimate& k : smoother.take()) r.kept.push_back(k);
    return r;
}

TEST(TrajectorySmoother, EveryPoseOnceInTimeOrder) {
    const TimeNs t_end = 10 * kNsPerSec;
    const SmoothedRun r = run(kNsPerSec / 2, 3 * kNsPerSec / 2, t_end, 2);
    ASSERT_EQ(r.kept.size(), static_cast<std::size_t>(t_end / kStep + 1));
    for (std::size_t i = 0; i < r.kept.size(); ++i) {
        ASSERT_EQ(r.kept[i].t_host, static_cast<TimeNs>(i) * kStep);
        EXPECT_EQ(r.kept[i].solved_dof_mask, 0x3f);  // the real-time pose's other fields stay
    }
}

TEST(TrajectorySmoother, ALinearDriftIsRemovedBetweenMatches) {
    // The chain drifts linearly from each anchor; the correction is linear in time: exact.
    const SmoothedRun r = run(kNsPerSec / 2, kNsPerSec, 8 * kNsPerSec, 1);
    ASSERT_GT(r.worst_realtime_m, 0.04);  // 1.5 s carried forward: 5 cm off
    double worst_m = 0, worst_rad = 0;
    // Poses after the last match stay as output (nothing closes them).
    for (const PoseEstimate& p : r.kept) {
        if (p.t_host > 7 * kNsPerSec) break;
        worst_m = std::max(worst_m, translationError(p));
        worst_rad = std::max(worst_rad, rotationError(p));
    }
    EXPECT_LT(worst_m, 1e-9);
    EXPECT_LT(worst_rad, 1e-4);  // the rotation correction is a share of the rotation vector
}

TEST(TrajectorySmoother, AQuadraticDriftShrinksToItsResidualBetweenTheEnds) {
    // A bias: the drift d(s) = c s^2 over a 0.5 s segment, minus the linear correction, leaves
    // at most c T^2 / 4 (mid-segment) of the c (T + delay)^2 the real-time output reached.
    const SmoothedRun r = run(kNsPerSec / 2, kNsPerSec, 8 * kNsPerSec, 2);
    double worst_m = 0;
    for (const PoseEstimate& p : r.kept) {
        if (p.t_host > 7 * kNsPerSec) break;
        worst_m = std::max(worst_m, translationError(p));
    }
    const double c = Eigen::Vector3d(0.03, -0.02, 0.01).norm();
    EXPECT_LT(worst_m, c * 0.25 * 0.25 + 1e-6);
    EXPECT_LT(worst_m, 0.05 * r.worst_realtime_m);
}

TEST(TrajectorySmoother, NothingIsHandedOnBeforeItsSegmentCloses) {
    TrajectorySmoother s;
    auto chain = [](TimeNs q) -> Result<Eigen::Isometry3d> { return carried(0, q, 1); };
    for (TimeNs t = 0; t <= kNsPerSec; t += kStep) s.add(at(t, carried(0, t, 1)));
    EXPECT_TRUE(s.take().empty());
    s.anchor(at(kNsPerSec / 2, truth(kNsPerSec / 2)), chain);  // the first: prediction only
    std::vector<PoseEstimate> first = s.take();
    ASSERT_EQ(first.size(), 101u);
    EXPECT_EQ(first.back().t_host, kNsPerSec / 2);
    EXPECT_TRUE(first.back().T_world_body.isApprox(carried(0, kNsPerSec / 2, 1)));
    // An anchor older than the newest is ignored; a newer one closes its segment.
    s.anchor(at(kNsPerSec / 4, truth(kNsPerSec / 4)), chain);
    EXPECT_TRUE(s.take().empty());
    s.anchor(at(kNsPerSec, truth(kNsPerSec)), chain);
    std::vector<PoseEstimate> second = s.take();
    ASSERT_EQ(second.size(), 100u);
    EXPECT_TRUE(second.back().T_world_body.isApprox(truth(kNsPerSec), 1e-12));
    EXPECT_EQ(s.pending(), 0u);
}

TEST(TrajectorySmoother, AChainWithoutTheTimeLeavesThePosesAsOutput) {
    TrajectorySmoother s;
    for (TimeNs t = 0; t <= kNsPerSec; t += kStep) s.add(at(t, carried(0, t, 1)));
    auto chain = [](TimeNs q) -> Result<Eigen::Isometry3d> { return carried(0, q, 1); };
    auto gone = [](TimeNs) -> Result<Eigen::Isometry3d> {
        return Status(StatusCode::kNotFound, "outside the IMU history");
    };
    s.anchor(at(0, truth(0)), chain);
    (void)s.take();
    s.anchor(at(kNsPerSec, truth(kNsPerSec)), gone);
    const std::vector<PoseEstimate> kept = s.take();
    ASSERT_EQ(kept.size(), 200u);
    for (const PoseEstimate& p : kept)
        EXPECT_TRUE(p.T_world_body.isApprox(carried(0, p.t_host, 1)));
}

}  // namespace
}  // namespace handscan::fusion
