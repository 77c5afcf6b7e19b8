#include "handscan/worker/calibration_gate.hpp"

#include "handscan/core/log.hpp"

namespace handscan::worker {

Status CalibrationGate::pose(const PoseEstimate& pose) {
    if (!wrong()) return out_.pose(pose);
    PoseEstimate lost = pose;
    lost.tracking_lost = true;
    return out_.pose(lost);
}

Status CalibrationGate::trajectoryPose(const PoseEstimate& pose) {
    check_.addTrajectoryPose(pose);
    if (check_.holding()) {
        held_.emplace_back(pose);
        return Status::ok();
    }
    if (Status s = flushIfReleased(); !s.isOk()) return s;
    return forward(pose);
}

Status CalibrationGate::sweepRecord(const journal::SweepRecord& record) {
    if (check_.holding()) {
        held_.emplace_back(record);
        return Status::ok();
    }
    if (Status s = flushIfReleased(); !s.isOk()) return s;
    return forward(record);
}

Status CalibrationGate::sweep(const lio::RegisteredSweep& sweep,
                              std::span<const journal::MapPoint> points) {
    check_.addSweep(sweep.sweep.t_start, sweep.sweep.t_end,
                    sweep.tracking.consistent && sweep.tracking.enters_map, sweep.tracking.lost);
    const CalibrationVerdict before = check_.verdict();
    const bool was_holding = check_.holding();
    check_.update();  // at sweep ends: the trajectory up to here is in
    if (check_.verdict() != before) {
        logVerdict();
    } else if (was_holding && !check_.holding()) {
        const CalibrationCheckReport& r = check_.report();
        log().info(
            "calibration check: not decided after {:.1f} s ({} planes, laser tilt {:.2f} +- {:.2f} "
            "deg); mapping, checking on",
            r.checked_after_s, r.residuals, r.rotation_rad * 180.0 / M_PI,
            r.rotation_std_rad * 180.0 / M_PI);
    }
    if (check_.holding() || !held_.empty()) {
        held_.emplace_back(HeldSweep{sweep, {points.begin(), points.end()}});
        return flushIfReleased();
    }
    if (Status s = flushIfReleased(); !s.isOk()) return s;
    return forward(HeldSweep{sweep, {points.begin(), points.end()}});
}

Status CalibrationGate::finish() {
    const CalibrationVerdict before = check_.verdict();
    check_.giveUp();
    if (check_.verdict() != before) logVerdict();
    return flushIfReleased();
}

void CalibrationGate::logVerdict() const {
    const CalibrationCheckReport& r = check_.report();
    if (r.verdict == CalibrationVerdict::kWrong)
        log().error(
            "{} (after {:.1f} s: the two halves of each turn disagree by {:.0f} mm, {:.0f} mm "
            "with the laser moved by {:.2f} +- {:.2f} deg and {:.0f} +- {:.0f} mm; {} planes)",
            r.message, r.checked_after_s, r.sigma_before_m * 1e3, r.sigma_after_m * 1e3,
            r.rotation_rad * 180.0 / M_PI, r.rotation_std_rad * 180.0 / M_PI, r.shift_m * 1e3,
            r.shift_std_m * 1e3, r.residuals);
    else
        log().info("{} (after {:.1f} s of the scan, {} planes, {:.0f} ms)", r.message,
                   r.checked_after_s, r.residuals, r.solve_ms);
}

Status CalibrationGate::flushIfReleased() {
    if (check_.holding()) return Status::ok();
    for (; !held_.empty(); held_.pop_front()) {
        if (Status s = forward(std::move(held_.front())); !s.isOk()) return s;
    }
    return Status::ok();
}

Status CalibrationGate::forward(Held item) {
    const bool flag = wrong();
    if (auto* p = std::get_if<PoseEstimate>(&item)) {
        if (flag) p->tracking_lost = true;
        return out_.trajectoryPose(*p);
    }
    if (auto* r = std::get_if<journal::SweepRecord>(&item)) {
        if (flag) {
            r->tracking = journal::SweepTracking::kLost;
            r->in_map = false;
            r->tracking_reason = fusion::lostReasonName(fusion::LostReason::kCalibrationWrong);
        }
        return out_.sweepRecord(*r);
    }
    auto& s = std::get<HeldSweep>(item);
    if (flag) {
        s.sweep.tracking.lost = true;
        s.sweep.tracking.enters_map = false;
        s.sweep.tracking.reason = fusion::LostReason::kCalibrationWrong;
        s.points.clear();
    }
    return out_.sweep(s.sweep, s.points);
}

}  // namespace handscan::worker
