#include "handscan/pipeline_daemon/pipeline_worker.hpp"

#include <chrono>

#include "handscan/core/log.hpp"
#include "handscan/core/realtime.hpp"
#include "handscan/live_output/sweep_points.hpp"

namespace handscan::pipeline_daemon {
namespace {

constexpr TimeNs kHoldBack = 100 * kNsPerMs;  // ordering window (see the header)
constexpr TimeNs kLoopPeriod = 10 * kNsPerMs;
constexpr TimeNs kStatusPeriod = 100 * kNsPerMs;
constexpr TimeNs kFinishBudget = 3 * kNsPerSec;  // of systemd's 15 s TimeoutStopSec

lio::LioConfig lioConfig(const DeviceConfig& device) {
    lio::LioConfig c;
    c.assembler.boundary = device.motor.sweep_boundary == "full"
                               ? scan::SweepBoundary::kFullRevolution
                               : scan::SweepBoundary::kHalfRevolution;
    // As in replay: scan-matching feedback corrects the IMU prediction (section 4.2).
    c.imu_feedback = true;
    return c;
}

template <typename T>
void drain(SpscQueue<T>& q, std::deque<T>& into) {
    while (auto v = q.tryPop()) into.push_back(std::move(*v));
}

}  // namespace

PipelineWorker::PipelineWorker(const DeviceConfig& device, const Calibration& calibration,
                               std::unique_ptr<live_output::LivePublisher> publisher,
                               std::unique_ptr<ScanSession> session, SampleQueues& queues,
                               WorkerInputs inputs)
    : device_(device),
      calibration_(calibration),
      publisher_(std::move(publisher)),
      session_(std::move(session)),
      queues_(queues),
      inputs_(std::move(inputs)) {
    publisher_->setScanning(false);
    scan_state_.store(session_->state(), std::memory_order_release);
    journal_path_ = session_->journalPath();
    resetPipeline();
    if (device_.colour_camera.enabled) {
        try {
            colouriser_ = std::make_unique<colour::Colouriser>(calibration_);
        } catch (const std::exception& e) {
            log().error("colour camera: {}; the map stays uncoloured", e.what());
        }
    }
}

PipelineWorker::~PipelineWorker() { stop(); }

void PipelineWorker::start(int fifo_priority) {
    last_loop_.store(monotonicNow(), std::memory_order_release);
    thread_ = std::thread([this, fifo_priority] {
        (void)enterRealtimeThread("hs-pipeline", fifo_priority);  // warns once if denied
        run();
    });
}

void PipelineWorker::stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

Result<std::string> PipelineWorker::control(ScanControl c, TimeNs timeout) {
    std::future<Result<std::string>> done;
    {
        std::lock_guard lock(mutex_);
        requests_.push_back(Request{c, {}});
        done = requests_.back().done.get_future();
    }
    if (done.wait_for(std::chrono::nanoseconds(timeout)) != std::future_status::ready) {
        return Status(StatusCode::kTimeout, "pipeline thread did not answer within " +
                                                std::to_string(timeout / kNsPerMs) + " ms");
    }
    return done.get();
}

std::string PipelineWorker::journalPath() const {
    std::lock_guard lock(mutex_);
    return journal_path_;
}

void PipelineWorker::resetPipeline() {
    lio_ = std::make_unique<lio::LaserInertialOdometry>(lioConfig(device_), calibration_);
}

void PipelineWorker::run() {
    while (!stop_.load(std::memory_order_acquire)) {
        const TimeNs now = monotonicNow();
        last_loop_.store(now, std::memory_order_release);
        std::deque<Request> requests;
        {
            std::lock_guard lock(mutex_);
            requests.swap(requests_);
        }
        for (Request& r : requests) handle(r);
        drainQueues();
        feed(now - kHoldBack);
        consume();
        session_->flushIfDue();
        if (now - last_status_ >= kStatusPeriod) publishStatus();
        std::this_thread::sleep_for(std::chrono::nanoseconds(kLoopPeriod));
    }
    std::lock_guard lock(mutex_);
    for (Request& r : requests_)
        r.done.set_value(Status(StatusCode::kDisconnected, "the pipeline is shutting down"));
    requests_.clear();
}

void PipelineWorker::handle(Request& r) {
    Result<std::string> out = std::string();
    switch (r.control) {
        case ScanControl::kStart: {
            const bool fresh = !session_->canResume();
            out = session_->start();
            if (out.isOk() && fresh) {
                // A new scan: a new world frame and an empty map (hold still while it aligns).
                resetPipeline();
                publisher_->newScan();
            }
            break;
        }
        case ScanControl::kStop:
            out = session_->stop();
            break;
        case ScanControl::kNewScan:
            out = session_->newScan();
            if (out.isOk()) {
                resetPipeline();
                publisher_->newScan();
            }
            break;
        case ScanControl::kFinish:
            // Everything the drivers delivered belongs to the scan: process it, with the last
            // partial sweep, before the journal is closed - unless the pipeline is so far behind
            // that this would outlast systemd's stop timeout (then the backlog is dropped).
            drainQueues();
            feed(std::numeric_limits<TimeNs>::max(), monotonicNow() + kFinishBudget);
            if (imu_.empty() && encoder_.empty() && scans_.empty()) lio_->finish();
            consume();
            if (Status s = session_->finish(); !s.isOk())
                out = s;
            else
                out = std::string("journal closed");
            break;
    }
    publisher_->setScanning(session_->scanning());
    scan_state_.store(session_->state(), std::memory_order_release);
    {
        std::lock_guard lock(mutex_);
        journal_path_ = session_->journalPath();
    }
    publishStatus();
    r.done.set_value(std::move(out));
}

void PipelineWorker::drainQueues() {
    drain(queues_.imu, imu_);
    drain(queues_.encoder, encoder_);
    drain(queues_.scans, scans_);
    drain(queues_.colour_images, images_);
}

void PipelineWorker::feed(TimeNs horizon, TimeNs deadline) {
    // Merge the three streams by time up to the horizon.
    for (std::uint64_t n = 1;; ++n) {
        if ((n % 64) == 0 && monotonicNow() > deadline) {
            log().warn(
                "pipeline: {} IMU, {} encoder samples and {} scans not processed before shutdown",
                imu_.size(), encoder_.size(), scans_.size());
            imu_.clear();
            encoder_.clear();
            scans_.clear();
            break;
        }
        const TimeNs t_imu =
            imu_.empty() ? std::numeric_limits<TimeNs>::max() : imu_.front().t_host;
        const TimeNs t_enc =
            encoder_.empty() ? std::numeric_limits<TimeNs>::max() : encoder_.front().t_host;
        const TimeNs t_scan =
            scans_.empty() ? std::numeric_limits<TimeNs>::max() : scans_.front().t_host;
        const TimeNs t = std::min({t_imu, t_enc, t_scan});
        if (t == std::numeric_limits<TimeNs>::max() || t > horizon) break;
        if (t == t_imu) {
            lio_->addImu(imu_.front());
            imu_.pop_front();
        } else if (t == t_enc) {
            lio_->addEncoder(encoder_.front());
            encoder_.pop_front();
        } else {
            lio_->addScan(scans_.front());
            scans_.pop_front();
        }
    }
    while (!images_.empty() && images_.front().t_host <= horizon) {
        if (colouriser_) {
            if (Status s = colouriser_->addImage(images_.front()); !s.isOk())
                log().warn("colour camera: {}", s.message());
        }
        images_.pop_front();
    }
}

void PipelineWorker::consume() {
    for (const PoseEstimate& p : lio_->takePoses()) {
        publisher_->pose(p);
        session_->appendPose(live_output::trajectoryPose(p));
    }
    for (const lio::RegisteredSweep& s : lio_->takeSweeps()) {
        if (!session_->scanning()) continue;  // between scans the map does not grow
        std::optional<colour::ColourResult> colours;
        if (colouriser_ && colouriser_->imageCount() > 0) {
            const colour::PoseAtFn pose_at = [&](TimeNs t) {
                auto p = lio_->integratedPoseAt(t);
                return p.isOk() ? p->T_world_body : Eigen::Isometry3d::Identity();
            };
            colours = colouriser_->colourise(s.points_world, s.times, pose_at);
        }
        const std::vector<journal::MapPoint> pts =
            live_output::sweepMapPoints(s, colours ? &*colours : nullptr);
        session_->appendPoints(pts);
        publisher_->sweep(s, pts);
    }
    if (session_->state() != scan_state_.load(std::memory_order_acquire)) {
        // The journal stopped the scan (disk full): tell everyone.
        publisher_->setScanning(session_->scanning());
        scan_state_.store(session_->state(), std::memory_order_release);
    }
}

void PipelineWorker::publishStatus() {
    last_status_ = monotonicNow();
    // Samples the drivers could not queue: the pipeline fell behind (say so, at most once a
    // second).
    const std::uint64_t dropped = queues_.dropped.load(std::memory_order_relaxed);
    if (dropped > dropped_reported_ && last_status_ - dropped_logged_ >= kNsPerSec) {
        log().warn("pipeline behind: {} samples dropped at full queues ({} in all)",
                   dropped - dropped_reported_, dropped);
        dropped_reported_ = dropped;
        dropped_logged_ = last_status_;
    }
    live_output::LiveStatus s;
    s.sensors = inputs_.sensors();
    s.scan_state = session_->state();
    s.point_count = session_->points();
    s.export_status = inputs_.export_status();
    s.camera_brightness = queues_.camera_brightness.load(std::memory_order_relaxed);
    if (!session_->problem().empty()) {
        s.message = session_->problem();
    } else if (!lio_->aligned()) {
        s.message = "hold still: aligning with gravity";
    } else if (session_->scanning()) {
        s.message = "scanning";
    } else if (session_->state() == shm::ScanState::kStopped) {
        s.message = "scan stopped: export or start a new scan";
    } else {
        s.message = "ready to scan";
    }
    publisher_->status(*lio_, s);
}

}  // namespace handscan::pipeline_daemon
