#include "handscan/worker/pipeline_worker.hpp"

#include "handscan/camera/image_convert.hpp"
#include "handscan/core/log.hpp"
#include "handscan/live_output/sweep_points.hpp"

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
    if (config_.colourise) {
        try {
            colouriser_ = std::make_unique<colour::Colouriser>(calibration_);
        } catch (const std::exception& e) {
            log().error("colour camera: {}; the map stays uncoloured", e.what());
        }
    }
}

void PipelineWorker::reset() {
    lio_ = std::make_unique<lio::LaserInertialOdometry>(config_.lio, calibration_,
                                                        config_.motion_override);
    visual_.reset();  // made at the first tracking-camera frame
}

Status PipelineWorker::advance(TimeNs source_clock, TimeNs deadline) {
    return run(source_clock - config_.hold_back, deadline);
}

Status PipelineWorker::finish(TimeNs deadline) {
    if (Status s = run(std::numeric_limits<TimeNs>::max(), deadline); !s.isOk()) return s;
    lio_->finish();
    return consume();
}

Status PipelineWorker::flushTrajectory() {
    lio_->flushTrajectory();
    return consume();
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
        process(*sample);
        // After every sample, so that what the sink sees (and the colours, which use the
        // integrated motion at that moment) does not depend on how the source batches them.
        if (Status s = consume(); !s.isOk()) return s;
    }
}

void PipelineWorker::process(sources::Sample& sample) {
    if (const auto* imu = std::get_if<ImuSample>(&sample)) {
        timed("imu_prediction", [&] { lio_->addImu(*imu); });
    } else if (const auto* position = std::get_if<EncoderSample>(&sample)) {
        timed("sweep_assembly_and_matching", [&] { lio_->addEncoder(*position); });
    } else if (const auto* scan = std::get_if<LaserScan>(&sample)) {
        timed("sweep_assembly_and_matching", [&] { lio_->addScan(*scan); });
    } else if (const auto* frame = std::get_if<sources::TrackingFrame>(&sample)) {
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
        if (!colouriser_) return;
        // The colouriser takes decoded frames (pipeline/ knows no wire format).
        Result<Image> bgr = camera::toBgr(*image);
        if (Status s = bgr ? colouriser_->addImage(*bgr) : bgr.status(); !s.isOk()) {
            if (colour_errors_++ == 0) log().warn("colour camera: {}", s.message());
        }
    }
}

Status PipelineWorker::consume() {
    for (const PoseEstimate& p : lio_->takePoses()) {
        if (Status s = sink_.pose(p); !s.isOk()) return s;
    }
    for (const PoseEstimate& p : lio_->takeTrajectory()) {
        if (Status s = sink_.trajectoryPose(p); !s.isOk()) return s;
    }
    for (const lio::RegisteredSweep& s : lio_->takeSweeps()) {
        if (timer_ != nullptr) timer_->add("scan_matching", s.result.total_ms * 1e3);
        if (visual_) visual_->sweep(s);      // laser depth for the camera (5.3)
        if (!sink_.wantsSweeps()) continue;  // between scans the map does not grow
        // A sweep the tracking monitor kept out of the map reaches the sink with no points:
        // the sink counts it, but nothing of it is coloured, journaled or shown.
        if (!s.tracking.enters_map) {
            if (Status st = sink_.sweep(s, {}); !st.isOk()) return st;
            continue;
        }
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
        const std::vector<journal::MapPoint> pts =
            live_output::sweepMapPoints(s, colours ? &*colours : nullptr);
        if (Status st = sink_.sweep(s, pts); !st.isOk()) return st;
    }
    return Status::ok();
}

}  // namespace handscan::worker
