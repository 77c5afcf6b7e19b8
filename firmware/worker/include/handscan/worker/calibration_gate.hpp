// CalibrationGate: the worker's sink through a scan's calibration check (calibration_check.hpp).
// What the scan would keep - its trajectory poses, sweep records and map sweeps - is held, in
// order, until the check's first attempt, and handed on then: as it is unless the calibration is
// wrong; then flagged lost (reason calibration_wrong) with no map points, as is everything after
// it (also after a wrong verdict of a later attempt). The real-time poses go on at once (the
// operator sees the device move; after a wrong verdict they are flagged lost too).
#pragma once

#include <deque>
#include <variant>

#include "handscan/worker/calibration_check.hpp"
#include "handscan/worker/pipeline_worker.hpp"

namespace handscan::worker {

class CalibrationGate final : public WorkerSink {
public:
    CalibrationGate(WorkerSink& out, CalibrationCheck& check) : out_(out), check_(check) {}

    Status pose(const PoseEstimate& pose) override;
    Status trajectoryPose(const PoseEstimate& pose) override;
    bool wantsSweeps() const override { return out_.wantsSweeps(); }
    Status sweep(const lio::RegisteredSweep& sweep,
                 std::span<const journal::MapPoint> points) override;
    Status sweepRecord(const journal::SweepRecord& record) override;

    // The scan ends (stop, end of the recording): a check still waiting gives up (unchecked)
    // and what is held is handed on.
    Status finish();
    std::size_t held() const { return held_.size(); }

private:
    struct HeldSweep {
        lio::RegisteredSweep sweep;
        std::vector<journal::MapPoint> points;
    };
    using Held = std::variant<PoseEstimate, journal::SweepRecord, HeldSweep>;
    // Hands on what is held once the check no longer holds (decided, or its first attempt did
    // not decide).
    Status flushIfReleased();
    void logVerdict() const;
    Status forward(Held item);
    bool wrong() const { return check_.verdict() == CalibrationVerdict::kWrong; }

    WorkerSink& out_;
    CalibrationCheck& check_;
    std::deque<Held> held_;
};

}  // namespace handscan::worker
