// The calibration gate holds what a scan keeps (trajectory poses, sweep records, map sweeps)
// while its calibration check is pending, lets the live poses through, and hands everything on
// in its order once the check gives up (a scan too short to check); disabled, it holds nothing.
#include "handscan/worker/calibration_gate.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace handscan::worker {
namespace {

class RecordingSink final : public WorkerSink {
public:
    Status pose(const PoseEstimate& p) override {
        events.push_back("pose " + std::to_string(p.t_host));
        return Status::ok();
    }
    Status trajectoryPose(const PoseEstimate& p) override {
        events.push_back("trajectory " + std::to_string(p.t_host));
        return Status::ok();
    }
    Status sweepRecord(const journal::SweepRecord& r) override {
        events.push_back("record " + std::to_string(r.index));
        return Status::ok();
    }
    Status sweep(const lio::RegisteredSweep& s, std::span<const journal::MapPoint> pts) override {
        events.push_back("sweep " + std::to_string(s.sweep.index) + " " +
                         std::to_string(pts.size()) + (s.tracking.lost ? " lost" : ""));
        return Status::ok();
    }
    std::vector<std::string> events;
};

PoseEstimate poseAt(TimeNs t) {
    PoseEstimate p;
    p.t_host = t;
    return p;
}

lio::RegisteredSweep sweepNumber(std::uint64_t i) {
    lio::RegisteredSweep s;
    s.sweep.index = i;
    s.sweep.t_start = static_cast<TimeNs>(i) * 500 * kNsPerMs;
    s.sweep.t_end = s.sweep.t_start + 500 * kNsPerMs;
    return s;
}

journal::SweepRecord recordNumber(std::uint64_t i) {
    journal::SweepRecord r;
    r.index = i;
    return r;
}

TEST(CalibrationGate, HoldsWhatTheScanKeepsUntilTheCheckDecidesThenHandsItOnInOrder) {
    RecordingSink out;
    CalibrationCheck check(CalibrationCheckConfig{}, Calibration{});
    CalibrationGate gate(out, check);
    const std::vector<journal::MapPoint> points(3);
    ASSERT_TRUE(gate.pose(poseAt(1)).isOk());
    ASSERT_TRUE(gate.trajectoryPose(poseAt(1)).isOk());
    ASSERT_TRUE(gate.sweepRecord(recordNumber(0)).isOk());
    ASSERT_TRUE(gate.sweep(sweepNumber(0), points).isOk());
    ASSERT_TRUE(gate.pose(poseAt(2)).isOk());
    ASSERT_TRUE(gate.trajectoryPose(poseAt(2)).isOk());
    // Pending (no laser data at all): only the live poses went on.
    EXPECT_EQ(check.verdict(), CalibrationVerdict::kPending);
    EXPECT_EQ(out.events, (std::vector<std::string>{"pose 1", "pose 2"}));
    EXPECT_EQ(gate.held(), 4u);

    // The scan ends before the check could decide: unchecked, everything handed on as it was.
    ASSERT_TRUE(gate.finish().isOk());
    EXPECT_EQ(check.verdict(), CalibrationVerdict::kUnchecked);
    EXPECT_EQ(gate.held(), 0u);
    EXPECT_EQ(out.events, (std::vector<std::string>{"pose 1", "pose 2", "trajectory 1", "record 0",
                                                    "sweep 0 3", "trajectory 2"}));
    // And from then on straight through.
    ASSERT_TRUE(gate.trajectoryPose(poseAt(3)).isOk());
    EXPECT_EQ(out.events.back(), "trajectory 3");
}

TEST(CalibrationGate, ADisabledCheckHoldsNothing) {
    RecordingSink out;
    CalibrationCheckConfig config;
    config.enabled = false;
    CalibrationCheck check(config, Calibration{});
    CalibrationGate gate(out, check);
    ASSERT_TRUE(gate.trajectoryPose(poseAt(1)).isOk());
    ASSERT_TRUE(gate.sweep(sweepNumber(0), {}).isOk());
    EXPECT_EQ(out.events, (std::vector<std::string>{"trajectory 1", "sweep 0 0"}));
}

}  // namespace
}  // namespace handscan::worker
