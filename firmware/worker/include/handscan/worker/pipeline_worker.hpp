// PipelineWorker: the one pipeline the scanner runs and the bench measures. `handscan-pipeline`
// feeds it from the live devices (sources::LiveSource), `handscan replay` from a recording
// (sources::RecordedSource). It merges the samples by sample time (SampleMerger: a hold-back
// window behind the source's clock, the whole rest at the end), runs the laser-inertial odometry
// (IMU prediction, sweep assembly, scan matching: pipeline/lio), colours each registered sweep
// from the colour camera (pipeline/colour), and hands the poses and the sweeps' map points to a
// sink: the daemon's shared memory and scan journal, or replay's trajectory, map, stats, journal
// and shared memory. Single-threaded; the caller owns the thread.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "handscan/colour/colouriser.hpp"
#include "handscan/core/call_timer.hpp"
#include "handscan/core/config.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/localize/localizer.hpp"
#include "handscan/sources/sample_source.hpp"
#include "handscan/worker/calibration_check.hpp"
#include "handscan/worker/sample_merger.hpp"
#include "handscan/worker/visual_stage.hpp"

namespace handscan::worker {

// Where the worker's outputs go.
class WorkerSink {
public:
    virtual ~WorkerSink() = default;
    // Every 200 Hz integrated pose as it is estimated: the real-time output (the live display).
    [[nodiscard]] virtual Status pose(const PoseEstimate& pose) = 0;
    // The same poses once the next scan match is known, corrected to meet the matches on both
    // sides (fusion::TrajectorySmoother), a sweep or two later: the trajectory the scan keeps
    // (journal, trajectory.tum, export). Each pose exactly once, in time order.
    [[nodiscard]] virtual Status trajectoryPose(const PoseEstimate& pose) = 0;
    // False: registered sweeps are not wanted now (between scans), so they are not coloured.
    virtual bool wantsSweeps() const { return true; }
    // A registered sweep and its coloured full-resolution map points.
    [[nodiscard]] virtual Status sweep(const lio::RegisteredSweep& sweep,
                                       std::span<const journal::MapPoint> points) = 0;
    // The same sweep as the scan keeps its statistics (every sweep handed on, also those kept
    // out of the map), just before sweep(): the journal's per-sweep record, stats.json's
    // per_sweep, the report's module timeline and device rates.
    [[nodiscard]] virtual Status sweepRecord(const journal::SweepRecord& /*record*/) {
        return Status::ok();
    }
};

struct WorkerConfig {
    lio::LioConfig lio;
    // Diagnostics of a tool (replay --reference-motion), never set on the device.
    std::shared_ptr<const lio::MotionOverride> motion_override;
    bool colourise = true;  // colour the sweeps when colour images come
    // Run the visual-inertial odometry on the tracking-camera frames that come, as scan
    // matching's prior. Off by default: on simulated walks it still makes the pipeline worse
    // (see firmware/cli/cmd_replay.cpp); frames that come are then dropped.
    bool visual = false;
    // Every scan's first seconds check its calibration; what it keeps waits for the verdict.
    CalibrationCheckConfig calibration_check;
    vio::VioConfig vio;
    // Ordering window behind the source's clock (see SampleMerger): longer than any device's
    // delivery delay (a scan's ~30 ms from its first step, a camera frame's exposure).
    TimeNs hold_back = 100 * kNsPerMs;
    // A session continuing an earlier scan (section 9): localized on its feature map, the
    // outputs in its frame once locked and nothing before. Null: a scan of its own.
    std::shared_ptr<const localize::PriorMap> prior_map;
    // The body pose at the session's start in the prior map's frame (the operator's tap);
    // none: the prior scan's start.
    std::optional<Eigen::Isometry3d> initial_pose;
    localize::LocalizerConfig localizer;
    // Trajectory poses kept while not locked, handed on in the prior map's frame at the lock
    // (beyond this many the oldest are dropped: 60 s at 200 Hz).
    std::size_t max_poses_before_lock = 12000;
    // Sweeps (coloured map points) held likewise: 12 s at 2 sweeps/s, a few tens of MB at most;
    // older ones are dropped.
    std::size_t max_sweeps_before_lock = 24;
};

// The odometry's settings for this device (the sweep boundary of the motor), everything else the
// pipeline's defaults.
lio::LioConfig lioConfigFor(const DeviceConfig& device);

class CalibrationGate;

class PipelineWorker {
public:
    // `timer` (may be null): per-stage costs for stats.json.
    PipelineWorker(WorkerConfig config, const Calibration& calibration, WorkerSink& sink,
                   CallTimer* timer = nullptr);
    ~PipelineWorker();
    PipelineWorker(const PipelineWorker&) = delete;
    PipelineWorker& operator=(const PipelineWorker&) = delete;

    void add(sources::Sample sample) { merger_.push(std::move(sample)); }
    // Runs every queued sample taken more than the hold-back before `source_clock` through the
    // pipeline, in time order, and hands the outputs to the sink. Past `deadline` (host monotonic
    // time) the rest is dropped with a warning (a shutdown that must not outlast its timeout).
    [[nodiscard]] Status advance(TimeNs source_clock,
                                 TimeNs deadline = std::numeric_limits<TimeNs>::max());
    // End of input: every queued sample, then the last partial sweep.
    [[nodiscard]] Status finish(TimeNs deadline = std::numeric_limits<TimeNs>::max());
    // Hands the trajectory poses still held back to the sink as they were output (the scan
    // stops: its last seconds are not left out of the journal).
    [[nodiscard]] Status flushTrajectory();
    // A new scan: a new world frame and an empty map (the queued samples stay).
    void reset();
    // A calibration installed while the daemon runs (`calibrate` from the UI), in use from the
    // next reset(). The drivers keep stamping with the latencies they started with; its clocks
    // are applied as offsets from those stamps: `imu_shift_s` / `encoder_shift_s` = its latency
    // minus the stamped one. The clocks the last scan tracked are superseded by it.
    void recalibrate(const Calibration& calibration, double imu_shift_s, double encoder_shift_s);
    // The prior map the scans from the next reset() on localize on (null: scans of their own),
    // and the operator's start hint on it.
    void setPriorMap(std::shared_ptr<const localize::PriorMap> prior,
                     std::optional<Eigen::Isometry3d> initial_pose) {
        config_.prior_map = std::move(prior);
        config_.initial_pose = initial_pose;
    }

    const lio::LaserInertialOdometry& lio() const { return *lio_; }
    // The calibration the current scan runs with, and its check on the scan's first seconds.
    const Calibration& calibration() const { return calibration_; }
    const CalibrationCheck& calibrationCheck() const { return *check_; }
    std::size_t pending() const { return merger_.size(); }
    std::uint64_t colourErrors() const { return colour_errors_; }
    bool colourising() const { return colouriser_ != nullptr; }
    // The visual-inertial odometry (null: not configured or cam0 unusable).
    const VisualStage* visual() const { return visual_.get(); }
    // A new start hint for the localizer (see localize::Localizer::placeAt); false when there is
    // no localizer or it has locked.
    bool placeAgain(const Eigen::Isometry3d& hint) {
        return localizer_ != nullptr && localizer_->placeAt(hint);
    }
    // The localizer on the prior map (null without one).
    const localize::Localizer* localizer() const { return localizer_.get(); }
    // Sweeps left out of the outputs because the localizer had not locked within
    // max_sweeps_before_lock of them, and those held and handed on at the lock.
    std::uint64_t sweepsBeforeLock() const { return sweeps_before_lock_; }
    std::uint64_t sweepsHeldUntilLock() const { return sweeps_held_; }
    // The scan's feature map in its output frame (the prior map's, when continuing one: the
    // prior's points plus this session's where they add to it), for a later session.
    scan::FeatureMapPoints featureMap() const;

private:
    [[nodiscard]] Status run(TimeNs horizon, TimeNs deadline);
    void process(sources::Sample& sample);
    [[nodiscard]] Status consume();
    // consume() of a session localized on a prior map: outputs in its frame, none before lock.
    [[nodiscard]] Status consumeLocalized(std::vector<PoseEstimate> poses,
                                          std::vector<PoseEstimate> trajectory,
                                          std::vector<lio::RegisteredSweep> sweeps);
    [[nodiscard]] Status handOn(const lio::RegisteredSweep& s);
    // The sweep's coloured map points in the odometry's frame (none if kept out of the map).
    std::vector<journal::MapPoint> mapPoints(const lio::RegisteredSweep& s);
    // To the sink, in the prior map's frame when localized.
    [[nodiscard]] Status deliver(const lio::RegisteredSweep& s, std::vector<journal::MapPoint> pts);
    // The sweep's record (as handed on) with the samples taken since the last, to the sink.
    [[nodiscard]] Status record(const lio::RegisteredSweep& s);
    template <typename Fn>
    auto timed(const char* module, Fn&& fn) {
        if (timer_ != nullptr) return timer_->time(module, fn);
        return fn();
    }

    // The colouriser of the calibration in use (none when colour is off or cam1 unusable).
    void makeColouriser();

    // Where the outputs go: through the calibration gate while the scan checks its calibration.
    WorkerSink& out();

    WorkerConfig config_;
    Calibration calibration_;
    struct Recalibration {
        Calibration calibration;
        double imu_shift_s, encoder_shift_s;
    };
    std::optional<Recalibration> pending_;  // in use from the next reset()
    WorkerSink& sink_;
    CallTimer* timer_;
    std::unique_ptr<CalibrationCheck> check_;
    std::unique_ptr<CalibrationGate> gate_;
    SampleMerger merger_;
    std::unique_ptr<lio::LaserInertialOdometry> lio_;
    std::unique_ptr<colour::Colouriser> colouriser_;
    std::unique_ptr<VisualStage> visual_;
    std::uint64_t colour_errors_ = 0;
    std::unique_ptr<localize::Localizer> localizer_;
    std::deque<PoseEstimate> poses_before_lock_;
    std::uint64_t sweeps_before_lock_ = 0;
    struct HeldSweep {
        lio::RegisteredSweep sweep;
        std::vector<journal::MapPoint> points;
    };
    std::deque<HeldSweep> held_sweeps_;
    std::uint64_t sweeps_held_ = 0;
    // Samples taken since the last sweep record, and the sample time that window began.
    journal::DeviceCounts counts_;
    TimeNs counts_from_ = 0, last_sample_ = 0;
};

}  // namespace handscan::worker
