// TrajectorySmoother: the trajectory the scan keeps (the journal, trajectory.tum, the export), as
// against the real-time output the operator watches. The 200 Hz output of section 7 carries the
// newest scan-matching pose forward with the IMU's (and VIO's) increments; the matcher reports a
// sweep's pose one to two sweeps after its start, so each real-time pose is a forward prediction
// of up to ~2 s, and the output jumps when the next match lands. Measured on 150 s simulated
// walks that made the 200 Hz trajectory 1.5x as far from the truth as the matched sweep poses
// (office 7.1 vs 4.6 mm ATE, house 3.6 vs 2.3 mm).
//
// Once the match at t_b is known, every output pose between the previous match t_a and t_b is
// re-derived from both ends: the increments carried forward from a (the same chain as the
// real-time output), corrected by the share (t - t_a) / (t_b - t_a) of their disagreement with the
// match at b - rotation in world axes about the body, translation in world axes. The corrected
// segment meets both matches exactly, so the trajectory is as good as the matched poses between
// them. Poses are handed on in time order, each exactly once, a sweep or two late; what is still
// open at the end of the input (or at a stop) is handed on as it was output.
#pragma once

#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"

namespace handscan::fusion {

class TrajectorySmoother {
public:
    // The pose at t carried forward from the previous anchor (the real-time output's chain
    // before the new anchor replaces it).
    using CarriedFn = std::function<Result<Eigen::Isometry3d>(TimeNs t)>;

    // A real-time output pose: kept until the segment it lies in is closed.
    void add(const PoseEstimate& realtime);
    // A new anchor (a scan-matching pose, or without the laser a VIO feedback pose): closes the
    // segment since the previous one. Anchors come in time order; one that does not is ignored.
    void anchor(const PoseEstimate& b, const CarriedFn& carried_from_previous);
    // Hands on every kept pose as it was output (end of input, a stopped scan).
    void flush();
    // The poses closed since the last call, in time order.
    std::vector<PoseEstimate> take();
    std::size_t pending() const { return open_.size(); }

private:
    void release(TimeNs up_to);  // the kept poses at or before up_to, unchanged

    std::deque<PoseEstimate> open_;
    std::optional<PoseEstimate> anchor_;
    std::vector<PoseEstimate> closed_;
};

}  // namespace handscan::fusion
