#include "handscan/pipeline_daemon/pipeline_thread.hpp"

#include <chrono>
#include <filesystem>

#include "handscan/core/log.hpp"
#include "handscan/core/realtime.hpp"
#include "handscan/live_output/sweep_points.hpp"
#include "handscan/prior_map/feature_map_file.hpp"

namespace handscan::pipeline_daemon {
namespace {

constexpr TimeNs kLoopPeriod = 10 * kNsPerMs;
constexpr TimeNs kStatusPeriod = 100 * kNsPerMs;
constexpr TimeNs kFinishBudget = 3 * kNsPerSec;  // of systemd's 15 s TimeoutStopSec

worker::WorkerConfig workerConfig(const DeviceConfig& device, const WorkerInputs& inputs) {
    worker::WorkerConfig c;
    c.prior_map = inputs.prior_map;
    c.initial_pose = inputs.initial_pose;
    c.lio = worker::lioConfigFor(device);
    // As in replay: scan-matching feedback corrects the IMU prediction (section 4.2).
    c.lio.imu_feedback = true;
    c.colourise = device.colour_camera.enabled;
    // Not yet on the device: the check's attempt runs on the pipeline thread (16-150 ms here,
    // 1.5 s under ASan, where the driver queues overflowed and a stop command timed out), and its
    // 8 s hold releases the map and journal in one burst. It needs a thread of its own first.
    c.calibration_check.enabled = false;
    return c;
}

shm::LocalizationState localizationState(const localize::Localizer* l) {
    if (l == nullptr) return shm::LocalizationState::kNone;
    switch (l->lockState()) {
        case localize::LockState::kSearching:
            return shm::LocalizationState::kSearching;
        case localize::LockState::kNotLocked:
            return shm::LocalizationState::kNotLocked;
        case localize::LockState::kLocked:
            return shm::LocalizationState::kLocked;
    }
    return shm::LocalizationState::kNone;
}

}  // namespace

// The worker's outputs: shared memory always, the journal while scanning.
class PipelineThread::Sink final : public worker::WorkerSink {
public:
    Sink(live_output::LivePublisher& publisher, ScanSession& session)
        : publisher_(publisher), session_(session) {}
    Status pose(const PoseEstimate& p) override {
        publisher_.pose(p);
        return Status::ok();
    }
    Status trajectoryPose(const PoseEstimate& p) override {
        // Poses guessed while tracking is lost are not the scan's trajectory.
        if (!p.tracking_lost) session_.appendPose(live_output::trajectoryPose(p));
        return Status::ok();
    }
    bool wantsSweeps() const override { return session_.scanning(); }
    Status sweepRecord(const journal::SweepRecord& r) override {
        session_.appendSweep(r);  // every sweep, also those kept out of the map
        return Status::ok();
    }
    Status sweep(const lio::RegisteredSweep& s, std::span<const journal::MapPoint> pts) override {
        if (!s.tracking.enters_map) return Status::ok();  // kept out of the map: nothing to add
        session_.appendPoints(pts);
        publisher_.sweep(s, pts);
        return Status::ok();
    }

private:
    live_output::LivePublisher& publisher_;
    ScanSession& session_;
};

PipelineThread::PipelineThread(const DeviceConfig& device, const Calibration& calibration,
                               std::unique_ptr<live_output::LivePublisher> publisher,
                               std::unique_ptr<ScanSession> session, SampleQueues& queues,
                               WorkerInputs inputs)
    : device_(device),
      publisher_(std::move(publisher)),
      session_(std::move(session)),
      queues_(queues),
      inputs_(std::move(inputs)),
      source_(queues),
      sink_(std::make_unique<Sink>(*publisher_, *session_)),
      worker_(std::make_unique<worker::PipelineWorker>(workerConfig(device, inputs_), calibration,
                                                       *sink_)),
      journal_root_(session_->root()) {
    listScans();
    publisher_->setScanning(false);
    scan_state_.store(session_->state(), std::memory_order_release);
    journal_path_ = session_->journalPath();
}

PipelineThread::~PipelineThread() { stop(); }

void PipelineThread::start(int fifo_priority) {
    last_loop_.store(monotonicNow(), std::memory_order_release);
    thread_ = std::thread([this, fifo_priority] {
        (void)enterRealtimeThread("hs-pipeline", fifo_priority);  // warns once if denied
        run();
    });
}

void PipelineThread::stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

Result<std::string> PipelineThread::control(ScanControl c, TimeNs timeout) {
    return submit(Request{c, {}, nullptr, std::nullopt}, timeout);
}

Result<std::string> PipelineThread::continueScan(std::shared_ptr<const EarlierScan> earlier,
                                                 std::optional<Eigen::Isometry3d> initial_pose,
                                                 TimeNs timeout) {
    return submit(Request{ScanControl::kContinue, {}, std::move(earlier), initial_pose}, timeout);
}

Result<std::string> PipelineThread::placeAgain(const Eigen::Isometry3d& where, TimeNs timeout) {
    return submit(Request{ScanControl::kPlace, {}, nullptr, where}, timeout);
}

Result<std::string> PipelineThread::submit(Request request, TimeNs timeout) {
    std::future<Result<std::string>> done;
    {
        std::lock_guard lock(mutex_);
        requests_.push_back(std::move(request));
        done = requests_.back().done.get_future();
    }
    if (done.wait_for(std::chrono::nanoseconds(timeout)) != std::future_status::ready) {
        return Status(StatusCode::kTimeout, "pipeline thread did not answer within " +
                                                std::to_string(timeout / kNsPerMs) + " ms");
    }
    return done.get();
}

std::string PipelineThread::journalPath() const {
    std::lock_guard lock(mutex_);
    return journal_path_;
}

void PipelineThread::run() {
    while (!stop_.load(std::memory_order_acquire)) {
        const TimeNs now = monotonicNow();
        last_loop_.store(now, std::memory_order_release);
        std::deque<Request> requests;
        {
            std::lock_guard lock(mutex_);
            requests.swap(requests_);
        }
        for (Request& r : requests) handle(r);
        check(worker_->advance(pull()));
        session_->flushIfDue();
        if (now - last_status_ >= kStatusPeriod) publishStatus();
        std::this_thread::sleep_for(std::chrono::nanoseconds(kLoopPeriod));
    }
    std::lock_guard lock(mutex_);
    for (Request& r : requests_)
        r.done.set_value(Status(StatusCode::kDisconnected, "the pipeline is shutting down"));
    requests_.clear();
}

void PipelineThread::handle(Request& r) {
    Result<std::string> out = std::string();
    switch (r.control) {
        case ScanControl::kStart: {
            const bool fresh = !session_->canResume();
            out = session_->start();
            // A new scan (hold still while it aligns), of its own unless the daemon continues
            // one scan (--prior-map).
            if (out.isOk() && fresh) beginScan(inputs_.prior_map, inputs_.initial_pose);
            break;
        }
        case ScanControl::kStop:
            // The trajectory of the last sweeps, which no match has closed yet, is the scan's.
            check(worker_->flushTrajectory());
            out = session_->stop();
            if (out.isOk()) writeFeatureMap();
            break;
        case ScanControl::kNewScan:
            out = session_->newScan();
            if (out.isOk()) beginScan(inputs_.prior_map, inputs_.initial_pose);
            break;
        case ScanControl::kContinue:
            out = continueOn(r);
            break;
        case ScanControl::kPlace:
            if (session_->scanning() && r.initial_pose && worker_->placeAgain(*r.initial_pose))
                out = std::string("placed: searching for the earlier scan from there");
            else
                out = Status(StatusCode::kInvalidArgument,
                             "no continued scan searching for its place: stop the scan first");
            break;
        case ScanControl::kFinish:
            // Everything the drivers delivered belongs to the scan: process it, with the last
            // partial sweep, before the journal is closed - unless the pipeline is so far behind
            // that this would outlast systemd's stop timeout (then the backlog is dropped).
            (void)pull();
            check(worker_->finish(monotonicNow() + kFinishBudget));
            writeFeatureMap();
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
    listScans();
    publishStatus();
    r.done.set_value(std::move(out));
}

Result<std::string> PipelineThread::continueOn(const Request& r) {
    auto out = session_->continueFrom(r.earlier->dir);
    if (!out.isOk()) return out;
    // Section 9: a new odometry world localized on the earlier map; the screen shows that map
    // (the new scan's points join it once locked, in its frame) and the earlier path.
    beginScan(r.earlier->prior, r.initial_pose);
    publisher_->showEarlierScan(r.earlier->display, r.earlier->trajectory);
    return out;
}

void PipelineThread::beginScan(std::shared_ptr<const localize::PriorMap> prior,
                               std::optional<Eigen::Isometry3d> initial_pose) {
    useNewCalibration();
    worker_->setPriorMap(std::move(prior), initial_pose);
    worker_->reset();
    publisher_->newScan();
}

void PipelineThread::useNewCalibration() {
    const std::optional<std::string> path =
        inputs_.new_calibration ? inputs_.new_calibration() : std::nullopt;
    if (!path) return;
    Calibration calibration;
    try {
        calibration = loadCalibration(*path);
    } catch (const std::exception& e) {  // ConfigError: file, line, key
        log().error("calibration: {}; the scan keeps the calibration in use", e.what());
        return;
    }
    // The drivers keep stamping with the latencies the daemon started with (device_): the new
    // clocks are offsets from those stamps.
    const DeviceConfig clocks = withCalibratedLatencies(device_, calibration);
    const double imu_shift_s =
        (clocks.xsens.frame_latency_ms - device_.xsens.frame_latency_ms) * 1e-3;
    const double encoder_shift_s =
        (clocks.motor.tpdo_latency_ms - device_.motor.tpdo_latency_ms) * 1e-3;
    worker_->recalibrate(calibration, imu_shift_s, encoder_shift_s);
    log().info(
        "calibration: {} in use from this scan (IMU clock {:+.3f} ms, encoder clock {:+.3f} ms "
        "from the drivers' stamps)",
        *path, imu_shift_s * 1e3, encoder_shift_s * 1e3);
}

void PipelineThread::listScans() {
    // What the operator can continue (the touch screen's picker), after every scan control.
    const std::string& journal = session_->journalPath();
    const std::string own =
        journal.empty() ? std::string() : std::filesystem::path(journal).parent_path().string();
    const shm::ScanList scans = continuableScans(journal_root_, own, session_->scanning());
    publisher_->writer().setScanList(scans);
    can_continue_ = newestContinuableScan(journal_root_).isOk();
}

void PipelineThread::writeFeatureMap() {
    // Beside the journal: what a later scan continuing this one localizes on (section 9).
    const std::string& journal = session_->journalPath();
    if (journal.empty()) return;
    const std::string path =
        (std::filesystem::path(journal).parent_path() / prior_map::kFeatureMapFile).string();
    if (Status s = prior_map::writeFeatureMap(path, worker_->featureMap()); !s.isOk())
        log().warn("{} (a later scan cannot continue this one)", s.message());
}

TimeNs PipelineThread::pull() {
    samples_.clear();
    auto clock = source_.next(samples_);  // a live source always answers with now
    const TimeNs now = clock.isOk() && *clock ? **clock : monotonicNow();
    for (sources::Sample& sample : samples_) worker_->add(std::move(sample));
    return now;
}

void PipelineThread::check(const Status& s) {
    // The sinks never fail (the journal reports its own trouble through the session).
    if (!s.isOk()) log().error("pipeline: {}", s.message());
    syncScanState();
}

void PipelineThread::syncScanState() {
    if (session_->state() != scan_state_.load(std::memory_order_acquire)) {
        // The journal stopped the scan (disk full): tell everyone.
        publisher_->setScanning(session_->scanning());
        scan_state_.store(session_->state(), std::memory_order_release);
    }
}

void PipelineThread::publishStatus() {
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
    if (inputs_.calibration_status) s.calibration = inputs_.calibration_status();
    s.camera_brightness = queues_.camera_brightness.load(std::memory_order_relaxed);
    if (!session_->problem().empty()) {
        s.message = session_->problem();
    } else if (session_->scanning() &&
               worker_->calibrationCheck().verdict() == worker::CalibrationVerdict::kWrong) {
        s.message = worker_->calibrationCheck().report().message;
    } else if (!worker_->lio().aligned()) {
        s.message = "hold still: aligning with gravity";
    } else if (session_->scanning() && worker_->localizer() != nullptr &&
               !worker_->localizer()->locked()) {
        s.message = worker_->localizer()->lockState() == localize::LockState::kNotLocked
                        ? "not locked: walk to where the earlier scan started"
                        : "searching for the earlier scan: walk where it went";
    } else if (worker_->lio().tracking().lost()) {
        s.message = fusion::TrackingMonitor::kLostMessage;
    } else if (session_->scanning()) {
        s.message = "scanning";
    } else if (session_->state() == shm::ScanState::kStopped) {
        s.message = "scan stopped: export or start a new scan";
    } else {
        s.message = "ready to scan";
    }
    // The lock while scanning (between scans the localizer waits for the next one).
    s.localization = session_->scanning() ? localizationState(worker_->localizer())
                                          : shm::LocalizationState::kNone;
    s.can_continue = can_continue_;
    publisher_->status(worker_->lio(), s);
    // Where the scene changed since the earlier scan, for the screen (once per used match).
    if (session_->scanning() && worker_->localizer() != nullptr)
        publisher_->changes(*worker_->localizer());
}

}  // namespace handscan::pipeline_daemon
