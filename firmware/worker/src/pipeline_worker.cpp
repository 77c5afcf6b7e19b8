#include "handscan/worker/pipeline_worker.hpp"

#include "handscan/camera/image_convert.hpp"
#include "handscan/core/log.hpp"
#include "handscan/live_output/sweep_points.hpp"
#include "handscan/worker/calibration_gate.hpp"

namespace handscan::worker {

lio::LioConfig lioConfigFor(const DeviceConfig& device) {
    lio::LioConfig c;
    c.assembler.boundary = device.motor.sweep_boundary == "full"
                               ? scan::SweepBoundary::kFullRevolution
                               : scan::SweepBoundary::kHalfRevolution;
    return c;
}

PipelineWorker::PipelineWorker(WorkerConfig config, const Calibration& calibration,
                               WorkerSink& sink, CallTimer* timer)
    : config_(std::move(config)), calibration_(calibration), sink_(sink), timer_(timer) {
    reset();
    makeColouriser();
}

PipelineWorker::~PipelineWorker() = default;

WorkerSink& PipelineWorker::out() { return gate_ ? static_cast<WorkerSink&>(*gate_) : sink_; }

void PipelineWorker::makeColouriser() {
    colouriser_.reset();
    if (!config_.colourise) return;
    try {
        colouriser_ = std::make_unique<colour::Colouriser>(calibration_);
    } catch (const std::exception& e) {
        log().error("colour camera: {}; the map stays uncoloured", e.what());
    }
}

void PipelineWorker::recalibrate(const Calibration& calibration, double imu_shift_s,
                                 double encoder_shift_s) {
    pending_ = Recalibration{calibration, imu_shift_s, encoder_shift_s};
}

void PipelineWorker::reset() {
    lio::ClockTrackerConfig& clocks = config_.lio.clocks;
    if (pending_) {
        // The new calibration's clocks supersede what the last scan tracked.
        calibration_ = std::move(pending_->calibration);
        clocks.configured_imu_offset_s = clocks.start_imu_offset_s = pending_->imu_shift_s;
        clocks.configured_encoder_offset_s = clocks.start_encoder_offset_s =
            pending_->encoder_shift_s;
        pending_.reset();
        makeColouriser();  // cam1's extrinsics may have changed with it
    } else if (lio_ && lio_->clocks().stats().determined > 0) {
        // The clocks the last scan tracked stay with the device: the next scan starts from them.
        clocks.start_imu_offset_s = lio_->clocks().stats().imu_offset_s;
        clocks.start_encoder_offset_s = lio_->clocks().stats().encoder_offset_s;
    }
    lio_ = std::make_unique<lio::LaserInertialOdometry>(config_.lio, calibration_,
                                                        config_.motion_override);
    // Every scan checks its calibration on its first seconds; what it keeps waits for that.
    gate_.reset();
    check_ = std::make_unique<CalibrationCheck>(config_.calibration_check, calibration_);
    if (config_.calibration_check.enabled)
        gate_ = std::make_unique<CalibrationGate>(sink_, *check_);
    visual_.reset();  // made at the first tracking-camera frame
    localizer_.reset();
    poses_before_lock_.clear();
    held_sweeps_.clear();
    sweeps_before_lock_ = 0;
    counts_ = {};
    counts_from_ = 0;
    sweeps_held_ = 0;
    if (config_.prior_map)
        localizer_ = std::make_unique<localize::Localizer>(config_.localizer, config_.prior_map,
                                                           config_.initial_pose);
}

Status PipelineWorker::advance(TimeNs source_clock, TimeNs deadline) {
    return run(source_clock - config_.hold_back, deadline);
}

Status PipelineWorker::finish(TimeNs deadline) {
    if (Status s = run(std::numeric_limits<TimeNs>::max(), deadline); !s.isOk()) return s;
    lio_->finish();
    if (Status s = consume(); !s.isOk()) return s;
    return gate_ ? gate_->finish() : Status::ok();
}

Status PipelineWorker::flushTrajectory() {
    lio_->flushTrajectory();
    if (Status s = consume(); !s.isOk()) return s;
    return gate_ ? gate_->finish() : Status::ok();
}

Status PipelineWorker::run(TimeNs horizon, TimeNs deadline) {
    for (std::uint64_t n = 1;; ++n) {
        if ((n % 64) == 0 && deadline != std::numeric_limits<TimeNs>::max() &&
            monotonicNow() > deadline) {
            log().warn("pipeline: {} samples not processed before shutdown", merger_.size());
            merger_.clear();
            return Status::ok();
        }
        std::optional<sources::Sample> sample = merger_.pop(horizon);
        if (!sample) return Status::ok();
        // The worker's time per sample, all stages: its longest is the longest stall of the
        // real-time outputs (stats.json modules.worker_per_sample.max_us).
        const Status s = timed("worker_per_sample", [&] {
            process(*sample);
            // After every sample, so that what the sink sees (and the colours, which use the
            // integrated motion at that moment) does not depend on how the source batches them.
            return consume();
        });
        if (!s.isOk()) return s;
    }
}

void PipelineWorker::process(sources::Sample& sample) {
    last_sample_ = std::max(last_sample_, sources::sampleTime(sample));
    if (counts_from_ == 0) counts_from_ = last_sample_;
    if (const auto* imu = std::get_if<ImuSample>(&sample)) {
        ++counts_.imu_samples;
        check_->addImu(*imu);
        timed("imu_prediction", [&] { lio_->addImu(*imu); });
    } else if (const auto* position = std::get_if<EncoderSample>(&sample)) {
        ++counts_.encoder_samples;
        check_->addEncoder(*position);
        timed("sweep_assembly_and_matching", [&] { lio_->addEncoder(*position); });
    } else if (const auto* scan = std::get_if<LaserScan>(&sample)) {
        ++counts_.laser_scans;
        check_->addScan(*scan);
        timed("sweep_assembly_and_matching", [&] { lio_->addScan(*scan); });
    } else if (const auto* frame = std::get_if<sources::TrackingFrame>(&sample)) {
        ++counts_.tracking_frames;
        if (!visual_ && config_.visual) {
            try {
                visual_ = std::make_unique<VisualStage>(calibration_, config_.vio);
            } catch (const std::exception& e) {
                log().error("tracking camera: {}; the visual-inertial odometry is off", e.what());
                config_.visual = false;  // once, not at every frame
            }
        }
        if (visual_)
            timed("visual_inertial_odometry", [&] { visual_->frame(frame->image, *lio_); });
    } else if (const auto* image = std::get_if<Image>(&sample)) {
        ++counts_.colour_frames;
        if (!colouriser_) return;
        // The colouriser takes decoded frames (pipeline/ knows no wire format).
        Result<Image> bgr = camera::toBgr(*image);
        if (Status s = bgr ? colouriser_->addImage(std::move(*bgr)) : bgr.status(); !s.isOk()) {
            if (colour_errors_++ == 0) log().warn("colour camera: {}", s.message());
        }
    }
}

Status PipelineWorker::consume() {
    if (localizer_)
        return consumeLocalized(lio_->takePoses(), lio_->takeTrajectory(), lio_->takeSweeps());
    for (const PoseEstimate& p : lio_->takePoses()) {
        if (Status s = out().pose(p); !s.isOk()) return s;
    }
    for (const PoseEstimate& p : lio_->takeTrajectory()) {
        if (Status s = out().trajectoryPose(p); !s.isOk()) return s;
    }
    for (const lio::RegisteredSweep& s : lio_->takeSweeps()) {
        if (Status st = handOn(s); !st.isOk()) return st;
    }
    return Status::ok();
}

namespace {

// What the scan keeps of a sweep (as handed on: in the output frame).
journal::SweepRecord sweepRecord(const lio::RegisteredSweep& s, journal::SweepVio vio) {
    journal::SweepRecord r;
    r.t_start_s = toSeconds(s.sweep.t_start);
    r.index = s.result.sweep_index;
    r.solved_mask = s.result.pose.solved_dof_mask;
    r.vio_mask = s.visual_solved_dof_mask;
    r.tracking = s.tracking.lost         ? journal::SweepTracking::kLost
                 : s.tracking.consistent ? journal::SweepTracking::kOk
                                         : journal::SweepTracking::kRejected;
    r.in_map = s.tracking.enters_map;
    r.vio = vio;
    r.points = static_cast<std::uint32_t>(s.points_world.size());
    r.edges = static_cast<std::uint32_t>(s.result.edges);
    r.planars = static_cast<std::uint32_t>(s.result.planars);
    r.associations = s.result.match.associations;
    r.rms_m = s.result.match.rms_m;
    r.total_ms = s.result.total_ms;
    const Eigen::Isometry3d& T = s.result.pose.T_world_body;
    const Eigen::Quaterniond q(T.linear());
    const Eigen::Vector3d t = T.translation(), tp = s.result.T_world_prior.translation();
    const double pose[7] = {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()};
    std::copy(pose, pose + 7, r.pose);
    r.prior_xyz[0] = tp.x();
    r.prior_xyz[1] = tp.y();
    r.prior_xyz[2] = tp.z();
    if (s.tracking.reason != fusion::LostReason::kNone)
        r.tracking_reason = fusion::lostReasonName(s.tracking.reason);
    return r;
}

PoseEstimate moved(const Eigen::Isometry3d& T, PoseEstimate p) {
    p.T_world_body = T * p.T_world_body;
    return p;
}

}  // namespace

Status PipelineWorker::consumeLocalized(std::vector<PoseEstimate> poses,
                                        std::vector<PoseEstimate> trajectory,
                                        std::vector<lio::RegisteredSweep> sweeps) {
    // Section 9: the odometry's sweeps (those it trusts) go to the localizer first, so that the
    // outputs of this batch use the newest estimate of the odometry's place in the prior map.
    for (const lio::RegisteredSweep& s : sweeps) {
        if (!s.tracking.enters_map || !s.result.features) continue;
        timed("localization", [&] {
            return localizer_->addSweep(s.sweep.t_start, s.result.pose.T_world_body,
                                        s.result.features);
        });
    }
    const Eigen::Isometry3d& T = localizer_->priorFromOdom();
    if (!localizer_->locked()) {
        // Nothing is merged before the lock: the real-time poses have no place on the prior map
        // yet, the trajectory's wait to be moved into the prior's frame.
        for (PoseEstimate& p : trajectory) poses_before_lock_.push_back(std::move(p));
        while (poses_before_lock_.size() > config_.max_poses_before_lock)
            poses_before_lock_.pop_front();
        // Its sweeps are coloured now (the motion they need is at hand now) and held, to be
        // handed on in the prior's frame at the lock.
        for (const lio::RegisteredSweep& s : sweeps) {
            if (timer_ != nullptr) timer_->add("scan_matching", s.result.total_ms * 1e3);
            if (visual_) visual_->sweep(s);
            if (!out().wantsSweeps()) continue;
            held_sweeps_.push_back({s, mapPoints(s)});
            if (held_sweeps_.size() > config_.max_sweeps_before_lock) {
                held_sweeps_.pop_front();
                ++sweeps_before_lock_;
            }
        }
        return Status::ok();
    }
    for (const PoseEstimate& p : poses) {
        if (Status st = out().pose(moved(T, p)); !st.isOk()) return st;
    }
    for (; !poses_before_lock_.empty(); poses_before_lock_.pop_front()) {
        const PoseEstimate p = moved(T, poses_before_lock_.front());
        if (Status st = out().trajectoryPose(p); !st.isOk()) return st;
    }
    for (const PoseEstimate& p : trajectory) {
        if (Status st = out().trajectoryPose(moved(T, p)); !st.isOk()) return st;
    }
    for (; !held_sweeps_.empty(); held_sweeps_.pop_front()) {
        ++sweeps_held_;
        if (Status st = deliver(held_sweeps_.front().sweep, std::move(held_sweeps_.front().points));
            !st.isOk())
            return st;
    }
    for (const lio::RegisteredSweep& s : sweeps) {
        if (Status st = handOn(s); !st.isOk()) return st;
    }
    return Status::ok();
}

Status PipelineWorker::handOn(const lio::RegisteredSweep& s) {
    if (timer_ != nullptr) timer_->add("scan_matching", s.result.total_ms * 1e3);
    if (visual_) visual_->sweep(s);  // laser depth for the camera (5.3)
    if (!out().wantsSweeps()) {      // between scans the map does not grow
        counts_ = {};                // and the device rates count from the scan's first sweep
        counts_from_ = last_sample_;
        return Status::ok();
    }
    return deliver(s, mapPoints(s));
}

std::vector<journal::MapPoint> PipelineWorker::mapPoints(const lio::RegisteredSweep& s) {
    // A sweep the tracking monitor kept out of the map reaches the sink with no points:
    // the sink counts it, but nothing of it is coloured, journaled or shown.
    std::vector<journal::MapPoint> pts;
    if (s.tracking.enters_map) {
        std::optional<colour::ColourResult> colours;
        if (colouriser_ && colouriser_->imageCount() > 0) {
            const colour::PoseAtFn pose_at = [&](TimeNs t) {
                auto p = lio_->integratedPoseAt(t);
                return p.isOk() ? p->T_world_body : Eigen::Isometry3d::Identity();
            };
            colours = timed("colourisation", [&] {
                return colouriser_->colourise(s.points_world, s.times, pose_at);
            });
        }
        pts = live_output::sweepMapPoints(s, colours ? &*colours : nullptr);
    }
    return pts;
}

Status PipelineWorker::deliver(const lio::RegisteredSweep& s, std::vector<journal::MapPoint> pts) {
    if (!localizer_) {
        if (Status st = record(s); !st.isOk()) return st;
        return out().sweep(s, pts);
    }
    // Coloured in the odometry's frame (its poses), handed on in the prior map's.
    const Eigen::Isometry3d& T = localizer_->priorFromOdom();
    lio::RegisteredSweep in_prior = s;
    in_prior.result.pose.T_world_body = T * s.result.pose.T_world_body;
    in_prior.result.T_world_prior = T * s.result.T_world_prior;
    const Eigen::Isometry3f Tf = T.cast<float>();
    for (Eigen::Vector3f& p : in_prior.points_world) p = Tf * p;
    for (journal::MapPoint& p : pts) {
        const Eigen::Vector3f q = Tf * Eigen::Vector3f(p.x, p.y, p.z);
        p.x = q.x();
        p.y = q.y();
        p.z = q.z();
    }
    if (Status st = record(in_prior); !st.isOk()) return st;
    return out().sweep(in_prior, pts);
}

Status PipelineWorker::record(const lio::RegisteredSweep& s) {
    const journal::SweepVio vio = !visual_                 ? journal::SweepVio::kOff
                                  : visual_->bypassedNow() ? journal::SweepVio::kBypassed
                                                           : journal::SweepVio::kRunning;
    journal::SweepRecord r = sweepRecord(s, vio);
    r.devices = counts_;
    r.devices.window_s = toSeconds(last_sample_ - counts_from_);
    counts_ = {};
    counts_from_ = last_sample_;
    return out().sweepRecord(r);
}

scan::FeatureMapPoints PipelineWorker::featureMap() const {
    scan::FeatureMapPoints own = lio_->odometry().featureMap();
    if (!localizer_ || !localizer_->locked())
        return localizer_ ? localizer_->prior().points() : own;
    // The prior's points first; this session's only where they fill an empty leaf (the voxel
    // map's constant density), moved into the prior's frame.
    scan::VoxelMap merged(config_.lio.odometry.map);
    const scan::FeatureMapPoints& prior = localizer_->prior().points();
    const Eigen::Isometry3d& T = localizer_->priorFromOdom();
    merged.recenter(localizer_->prior().start().translation());
    auto toDouble = [](const std::vector<Eigen::Vector3f>& v, const Eigen::Isometry3d& M) {
        std::vector<Eigen::Vector3d> out;
        out.reserve(v.size());
        for (const Eigen::Vector3f& p : v) out.push_back(M * p.cast<double>());
        return out;
    };
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    merged.insert(scan::FeatureKind::kEdge, toDouble(prior.edges, I));
    merged.insert(scan::FeatureKind::kPlanar, toDouble(prior.planars, I),
                  toDouble(prior.planar_origins, I));
    merged.insert(scan::FeatureKind::kEdge, toDouble(own.edges, T));
    merged.insert(scan::FeatureKind::kPlanar, toDouble(own.planars, T),
                  toDouble(own.planar_origins, T));
    return merged.featurePoints();
}

}  // namespace handscan::worker
