// VizSink: the viz file (VizWriter) as a sink of the pipeline worker, beside the sink that keeps
// the scan (replay's outputs, the daemon's journal and shared memory): it writes what the worker
// hands out (poses, registered sweeps) and passes it on unchanged, and it writes the samples the
// worker is given (IMU, encoder, scans, colour frames) and, from a recording, the frames and
// ground truth the worker does not take (RecordedExtras, tapped from the recorded source).
// `handscan replay --viz` uses it; the daemon and `handscan hil` can wrap their sinks the same way.
//
// The viz file is a by-product: when writing it fails (disk full), the failure is logged once,
// the file is given up, and the scan goes on; close() then reports the failure.
#pragma once

#include <memory>
#include <span>
#include <string>

#include "handscan/core/call_timer.hpp"
#include "handscan/sources/sample_source.hpp"
#include "handscan/viz/recorded_extras.hpp"
#include "handscan/viz/viz_writer.hpp"
#include "handscan/worker/pipeline_worker.hpp"

namespace handscan::viz {

struct VizSinkOptions {
    std::string path;               // the viz file
    bool recording_colour = false;  // recorded(): the colour frames too (not in the samples)
    VizConfig config;
    CallTimer* timer = nullptr;  // the cost, as module "viz"
};

class VizSink final : public worker::WorkerSink {
public:
    // `next`: the sink the worker's outputs go on to (may be null).
    [[nodiscard]] static Result<std::unique_ptr<VizSink>> create(const VizSinkOptions& options,
                                                                 const Calibration& calibration,
                                                                 worker::WorkerSink* next);

    [[nodiscard]] Status pose(const PoseEstimate& pose) override;
    // /pose and /tf hold the trajectory the scan keeps (as trajectory.tum).
    [[nodiscard]] Status trajectoryPose(const PoseEstimate& pose) override;
    bool wantsSweeps() const override { return next_ == nullptr || next_->wantsSweeps(); }
    [[nodiscard]] Status sweep(const lio::RegisteredSweep& sweep,
                               std::span<const journal::MapPoint> points) override;
    // Each sweep's record comes just before it: its device counts are the sweep's rates.
    [[nodiscard]] Status sweepRecord(const journal::SweepRecord& record) override {
        devices_ = record.devices;
        return next_ != nullptr ? next_->sweepRecord(record) : Status::ok();
    }

    // The samples given to the worker (before they are).
    void samples(std::span<const sources::Sample> samples);
    // A recording's message (RecordedSourceOptions::tap) of recordedTopics(): frames and ground
    // truth the samples do not carry.
    void recorded(const recording::RecordedMessage& msg);
    // The topics recorded() wants (`recording_colour` as in the options).
    static std::vector<std::string> recordedTopics(bool recording_colour) {
        return RecordedExtras::topics(recording_colour);
    }
    // Closes the file; the first error, if any.
    [[nodiscard]] Status close();

    std::uint64_t bytesWritten() const { return writer_->bytesWritten(); }

private:
    VizSink(std::unique_ptr<VizWriter> writer, bool recording_colour, worker::WorkerSink* next,
            CallTimer* timer, std::string path);
    void keep(const Status& s);  // the first failure gives the file up
    template <typename Fn>
    void timed(Fn&& fn) {
        if (timer_ != nullptr)
            timer_->time("viz", fn);
        else
            fn();
    }

    std::unique_ptr<VizWriter> writer_;
    RecordedExtras extras_;
    worker::WorkerSink* next_;
    CallTimer* timer_;
    std::string path_;
    journal::DeviceCounts devices_;  // of the last sweep record
    Status failed_;
    bool closed_ = false;
};

}  // namespace handscan::viz
