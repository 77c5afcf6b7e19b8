#include "handscan/replay/replay_engine.hpp"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>
#include <thread>

#include "handscan/core/call_timer.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/json.hpp"
#include "handscan/core/log.hpp"
#include "handscan/journal/journal_writer.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/live_output/live_publisher.hpp"
#include "handscan/live_output/sweep_points.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"
#include "handscan/replay/reference_motion.hpp"
#include "handscan/replay/sweep_ply.hpp"
#include "handscan/sources/recorded_source.hpp"
#include "handscan/viz/viz_sink.hpp"
#include "handscan/worker/pipeline_worker.hpp"
#include "replay_outputs.hpp"

namespace handscan::replay {
namespace {

namespace fs = std::filesystem;

// The replay's decoder counters as the status bar's sensors (nominal rates once data flows).
live_output::LiveSensor replaySensor(const char* name, const StreamCounters& c, float expected_hz) {
    return {name, c.messages > 0, c.messages > 0 ? expected_hz : 0.0f, expected_hz,
            0,    c.last_error};
}

double peakRssMiB() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_maxrss) / 1024.0;  // ru_maxrss is in KiB on Linux
}

Result<worker::WorkerConfig> workerConfig(const ReplayOptions& o, const DeviceConfig& device,
                                          bool colour) {
    worker::WorkerConfig c;
    c.lio = worker::lioConfigFor(device);
    c.lio.laser_enabled = o.use_laser;
    c.lio.imu_feedback = o.imu_feedback;
    c.lio.clocks.enabled = o.track_clocks;
    c.calibration_check.enabled = o.check_calibration;
    c.lio.odometry.max_threads = 1;  // replay is deterministic: sweeps are matched in order
    // Likewise a relocalisation's search (on its own thread) takes effect at the next sweep.
    if (o.fast) c.lio.relocalise.apply = localize::MatchApply::kAtNextSweep;
    if (!o.reference_motion.empty()) {
        auto reference = ReferenceMotion::load(
            o.reference_motion, o.reference_perturb_m, o.reference_perturb_deg * M_PI / 180.0,
            c.lio.odometry.prior_sigma_rot_rad, c.lio.odometry.prior_sigma_trans_m);
        if (!reference.isOk()) return reference.status();
        c.motion_override = *reference;
    }
    c.colourise = colour;
    c.visual = o.use_vision;
    if (!o.prior_map_dir.empty()) {
        auto prior = prior_map::loadPriorMap(o.prior_map_dir);
        if (!prior.isOk()) return prior.status();
        c.prior_map = *prior;
        // The matches to the prior map run on the localizer's thread; --fast applies each at
        // the next sweep (the same bytes run after run), at the recording's pace they take
        // effect when done, as on the device.
        c.localizer.apply =
            o.fast ? localize::MatchApply::kAtNextSweep : localize::MatchApply::kWhenReady;
        if (!o.initial_pose.empty()) {
            auto pose = prior_map::parsePose(o.initial_pose);
            if (!pose.isOk())
                return Status(pose.status().code(), "--initial-pose: " + pose.status().message());
            c.initial_pose = *pose;
        }
    }
    return c;
}

// What replay keeps of the worker's output: trajectory.tum, map.ply and the per-sweep summary
// (ReplayOutputs), the journal, the sweeps as PLY (--dump-sweeps), shared memory (--live).
class ReplaySink final : public worker::WorkerSink {
public:
    ReplaySink(const ReplayOptions& o, ReplayOutputs& outputs, journal::JournalWriter* journal,
               live_output::LivePublisher* live)
        : o_(o), outputs_(outputs), journal_(journal), live_(live) {}

    Status pose(const PoseEstimate& p) override {
        if (live_) live_->pose(p);
        return Status::ok();
    }

    Status trajectoryPose(const PoseEstimate& p) override {
        // Poses guessed while tracking is lost are not the scan's trajectory (neither in
        // trajectory.tum nor in the journal): the IMU's alone, or after an IMU gap those of
        // the lost sweeps' own map, in a frame the relocalisation has yet to find.
        if (p.tracking_lost) return Status::ok();
        if (Status st = outputs_.addPose(p); !st.isOk()) return st;
        if (journal_) (void)journal_->appendPose(live_output::trajectoryPose(p));
        return Status::ok();
    }

    Status sweep(const lio::RegisteredSweep& s, std::span<const journal::MapPoint> pts) override {
        if (!o_.dump_sweeps_dir.empty()) {
            std::ostringstream name;
            name << "sweep_" << std::setw(6) << std::setfill('0') << s.sweep.index << ".ply";
            if (Status st =
                    writeSweepPly((fs::path(o_.dump_sweeps_dir) / name.str()).string(), s.sweep);
                !st.isOk()) {
                return st;
            }
        }
        // A sweep the tracking monitor kept out of the map is journaled and shown nowhere.
        if (!s.tracking.enters_map) return Status::ok();
        if (Status st = outputs_.addSweep(s, pts); !st.isOk()) return st;
        if (journal_) {
            if (Status st = journal_->appendPoints(pts); !st.isOk()) return st;
            if (Status st = journal_->flushIfDue(); !st.isOk()) return st;
        }
        if (live_) live_->sweep(s, pts);
        return Status::ok();
    }

    Status sweepRecord(const journal::SweepRecord& r) override {
        outputs_.addSweepRecord(r);
        return journal_ ? journal_->appendSweep(r) : Status::ok();
    }

private:
    const ReplayOptions& o_;
    ReplayOutputs& outputs_;
    journal::JournalWriter* journal_;
    live_output::LivePublisher* live_;
};

live_output::LiveStatus replayStatus(const lio::LaserInertialOdometry& pipeline,
                                     const sources::RecordedSource& source,
                                     const ReplayOutputs& outputs, bool finished) {
    live_output::LiveStatus s;
    s.sensors = {replaySensor("hokuyo", source.hokuyo(), 40.0f),
                 replaySensor("xsens", source.xsens(), 200.0f),
                 replaySensor("encoder", source.encoder(), 200.0f)};
    s.scan_state = finished ? shm::ScanState::kStopped : shm::ScanState::kScanning;
    s.point_count = outputs.registeredPoints();
    s.message = finished                     ? "replay finished"
                : !pipeline.aligned()        ? "hold still: aligning with gravity"
                : pipeline.tracking().lost() ? fusion::TrackingMonitor::kLostMessage
                                             : "replaying";
    return s;
}

}  // namespace

Result<ReplayReport> runReplay(const ReplayOptions& o) {
    const std::string config_dir = defaultConfigDir();
    const Calibration calibration =
        loadCalibration(o.calibration.empty() ? config_dir + "/calibration.yaml" : o.calibration);
    // The latencies calibration.yaml measured (`handscan calibrate`) replace device.yaml's.
    const DeviceConfig device = withCalibratedLatencies(
        loadDeviceConfig(o.device_config.empty() ? config_dir + "/device.yaml" : o.device_config),
        calibration);

    CallTimer timer;
    sources::RecordedSourceOptions source_options;
    source_options.laser = o.use_laser;
    source_options.colour = o.colourise;
    source_options.tracking = o.use_vision;
    source_options.skip_every_other = o.skip_every_other;
    source_options.fast = o.fast;
    source_options.speed = o.speed;
    source_options.timer = &timer;
    // --viz: the recording's frames and ground truth too, tapped into the viz file once open.
    viz::VizSink* viz_tap = nullptr;
    if (!o.viz_path.empty()) {
        source_options.extra_topics = viz::VizSink::recordedTopics(!o.colourise);
        source_options.tap = [&viz_tap](const recording::RecordedMessage& m) {
            if (viz_tap != nullptr) viz_tap->recorded(m);
        };
    }
    auto opened = sources::RecordedSource::open(o.recording, device, source_options);
    if (!opened.isOk()) return opened.status();
    sources::RecordedSource& source = **opened;
    if (o.vision_required && !source.hasTracking())
        return Status(StatusCode::kNotFound,
                      o.recording + ": no /camera/track channel; --modules imu,vision needs the " +
                          "tracking camera (or choose --modules imu,laser)");
    std::error_code ec;
    fs::create_directories(o.out_dir, ec);
    if (ec)
        return Status(StatusCode::kIoError,
                      "replay: cannot create " + o.out_dir + ": " + ec.message());
    if (!o.dump_sweeps_dir.empty()) fs::create_directories(o.dump_sweeps_dir, ec);

    TiledMapConfig map_config;
    map_config.voxel_m = o.map_voxel_m;
    map_config.tile_m = o.map_tile_m;
    map_config.memory_budget_bytes = static_cast<std::uint64_t>(o.map_memory_mib * (1 << 20));
    map_config.spill_dir = o.map_spill_dir.empty() ? o.out_dir : o.map_spill_dir;
    ReplayOutputs outputs(o.out_dir, map_config);
    if (Status st = outputs.open(); !st.isOk()) return st;
    std::unique_ptr<journal::JournalWriter> journal;
    if (o.write_journal) {
        const std::string path = (fs::path(o.out_dir) / "journal.hsj").string();
        fs::remove(path, ec);
        Json meta = {{"source", "replay"}, {"recording", o.recording}};
        // A session localized on an earlier scan is in that scan's frame (handscan merge).
        if (!o.prior_map_dir.empty()) meta["prior_map"] = o.prior_map_dir;
        auto j = journal::JournalWriter::create(path, jsonText(meta));
        if (!j.isOk()) return j.status();
        journal = std::move(*j);
    }
    std::unique_ptr<live_output::LivePublisher> live;
    if (o.live) {
        auto p = live_output::LivePublisher::create(o.shm_name, o.out_dir);
        if (!p.isOk()) return p.status();
        live = std::move(*p);
    }

    auto worker_config = workerConfig(o, device, source.hasColour());
    if (!worker_config.isOk()) return worker_config.status();
    ReplaySink sink(o, outputs, journal.get(), live.get());
    std::unique_ptr<viz::VizSink> viz;
    if (!o.viz_path.empty()) {
        auto v = viz::VizSink::create({o.viz_path, !o.colourise, {}, &timer}, calibration, &sink);
        if (!v.isOk()) return v.status();
        viz = std::move(*v);
        viz_tap = viz.get();
    }
    worker::PipelineWorker worker(std::move(*worker_config), calibration,
                                  viz ? static_cast<worker::WorkerSink&>(*viz) : sink, &timer);
    const auto wall_start = std::chrono::steady_clock::now();
    const double duration_hint = source.durationHint();
    std::vector<sources::Sample> samples;
    for (std::uint64_t n = 1;; ++n) {
        samples.clear();
        auto clock = source.next(samples);
        if (!clock.isOk()) return clock.status();
        if (!*clock) break;
        if (viz) viz->samples(samples);
        for (sources::Sample& s : samples) worker.add(std::move(s));
        if (Status st = worker.advance(**clock); !st.isOk()) return st;
        if (live && (n % 64) == 0) {
            live->status(worker.lio(), replayStatus(worker.lio(), source, outputs, false));
            if (worker.localizer() != nullptr) live->changes(*worker.localizer());
        }
        if (o.progress && duration_hint > 0 && (n % 256) == 0)
            o.progress(toSeconds(**clock - source.firstTime()) / duration_hint);
    }
    if (Status st = worker.finish(); !st.isOk()) return st;
    // A failed viz file is reported after the scan's own outputs are written (below).
    const Status viz_status = viz ? viz->close() : Status::ok();
    if (journal) {
        if (Status st = journal->finish(); !st.isOk()) return st;
    }
    const double wall_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    const lio::LaserInertialOdometry& pipeline = worker.lio();
    ReplayReport report;
    report.recording_s = toSeconds(source.lastTime() - source.firstTime());
    report.wall_s = wall_s;
    report.realtime_factor = wall_s > 0 ? report.recording_s / wall_s : 0.0;
    report.poses = pipeline.stats().poses_out;
    report.sweeps = pipeline.stats().sweeps;
    if (Status st = outputs.writeTrajectory(); !st.isOk()) return st;
    // The feature map a later session localizes on (in this scan's output frame).
    if (o.use_laser) {
        if (Status st = prior_map::writeFeatureMap(
                (fs::path(o.out_dir) / prior_map::kFeatureMapFile).string(), worker.featureMap());
            !st.isOk())
            return st;
    }
    report.prior_map = worker.localizer() != nullptr;
    report.locked = report.prior_map && worker.localizer()->locked();
    auto map_points = outputs.writeMap();
    if (!map_points.isOk()) return map_points.status();
    report.map_points = *map_points;
    StatsInputs in{report,
                   timer.summary(),
                   pipeline,
                   worker.visual(),
                   source.hokuyo(),
                   source.xsens(),
                   source.encoder(),
                   peakRssMiB(),
                   source.reader().truncated(),
                   source.reader().dropped().size(),
                   worker.localizer(),
                   worker.sweepsBeforeLock(),
                   worker.sweepsHeldUntilLock(),
                   &worker.calibrationCheck()};
    auto stats_path = outputs.writeStats(in);
    if (!stats_path.isOk()) return stats_path.status();
    report.stats_json_path = *stats_path;
    if (viz) report.viz_bytes = viz->bytesWritten();
    if (!viz_status.isOk()) return viz_status;
    if (live) {
        live->status(pipeline, replayStatus(pipeline, source, outputs, /*finished=*/true));
        if (worker.localizer() != nullptr) live->changes(*worker.localizer());
        while (o.hold && !(o.interrupted && o.interrupted())) {
            live->heartbeat();
            std::this_thread::sleep_for(std::chrono::milliseconds(100));
        }
    }
    return report;
}

}  // namespace handscan::replay
