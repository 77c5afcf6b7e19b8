// PipelineThread: the daemon's pipeline thread. It runs the one pipeline `handscan replay` runs
// too (worker::PipelineWorker: samples merged by sample time, 100 ms behind now, laser-inertial
// odometry, colourisation) on the live source (sources::LiveSource: the drivers' SPSC queues),
// and writes every output: poses, display map, status and a continued scan's change report to
// shared memory (live_output::LivePublisher, the same code as replay --live), poses and
// full-resolution points to the scan's journal while scanning (ScanSession). Scan control runs on
// this thread too, so the journal and the map epoch have a single owner.
#pragma once

#include <atomic>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "handscan/live_output/live_publisher.hpp"
#include "handscan/pipeline_daemon/earlier_scan.hpp"
#include "handscan/pipeline_daemon/scan_session.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"
#include "handscan/sources/live_source.hpp"
#include "handscan/worker/pipeline_worker.hpp"

namespace handscan::pipeline_daemon {

enum class ScanControl { kStart, kStop, kNewScan, kFinish, kContinue, kPlace };

struct WorkerInputs {
    // Status of every device (thread-safe snapshots), for the status block.
    std::function<std::vector<live_output::LiveSensor>()> sensors;
    std::function<shm::ExportStatus()> export_status;
    std::function<shm::CalibrationStatus()> calibration_status;  // may be empty
    // A calibration.yaml installed since the last call (CalibrateJob::takeInstalled), to use from
    // the next scan; may be empty.
    std::function<std::optional<std::string>()> new_calibration;
    // Continue an earlier scan: the worker localizes on it (null: a scan of its own).
    std::shared_ptr<const localize::PriorMap> prior_map;
    std::optional<Eigen::Isometry3d> initial_pose;
};

class PipelineThread {
public:
    PipelineThread(const DeviceConfig& device, const Calibration& calibration,
                   std::unique_ptr<live_output::LivePublisher> publisher,
                   std::unique_ptr<ScanSession> session, SampleQueues& queues, WorkerInputs inputs);
    ~PipelineThread();
    PipelineThread(const PipelineThread&) = delete;
    PipelineThread& operator=(const PipelineThread&) = delete;

    // Starts the pipeline thread, SCHED_FIFO at `fifo_priority` when permitted (0: normal).
    void start(int fifo_priority = 0);
    void stop();
    // Runs `control` on the pipeline thread; the operator's message or why it was refused.
    Result<std::string> control(ScanControl control, TimeNs timeout = 5 * kNsPerSec);
    // A new scan continuing `earlier` (loaded by the caller): localized on its feature map from
    // `initial_pose` (none: where it started), its map and path on the screen meanwhile.
    Result<std::string> continueScan(std::shared_ptr<const EarlierScan> earlier,
                                     std::optional<Eigen::Isometry3d> initial_pose,
                                     TimeNs timeout = 5 * kNsPerSec);
    // While a continued scan searches for its place: the operator's new start hint (where they
    // stand now), the search starts again around it.
    Result<std::string> placeAgain(const Eigen::Isometry3d& where, TimeNs timeout = 5 * kNsPerSec);
    // Where the scans are journaled (one directory each).
    const std::string& journalRoot() const { return journal_root_; }

    shm::ScanState scanState() const { return scan_state_.load(std::memory_order_acquire); }
    std::string journalPath() const;
    // Host time of the thread's last loop: the watchdog is fed only while this advances.
    TimeNs lastLoop() const { return last_loop_.load(std::memory_order_acquire); }
    // The UI's command channel (commands and acks only; the worker never touches them).
    shm::LiveMapWriter& commands() { return publisher_->writer(); }

private:
    struct Request {
        ScanControl control;
        std::promise<Result<std::string>> done;
        std::shared_ptr<const EarlierScan> earlier;  // kContinue
        std::optional<Eigen::Isometry3d> initial_pose;
    };
    Result<std::string> submit(Request request, TimeNs timeout);
    Result<std::string> continueOn(const Request& r);
    // A new scan's worker: a new world frame and an empty map, localized on `prior` (null: a
    // scan of its own), with the calibration installed since the last scan if there is one.
    void beginScan(std::shared_ptr<const localize::PriorMap> prior,
                   std::optional<Eigen::Isometry3d> initial_pose);
    void useNewCalibration();
    class Sink;
    void run();
    void handle(Request& r);
    // Everything the drivers queued, into the worker; the live source's clock.
    TimeNs pull();
    // The scan's feature map beside its journal (feature_map.hsf), for a later "continue scan".
    void writeFeatureMap();
    // The scans that can be continued, into the shared memory; can_continue_.
    void listScans();
    void check(const Status& s);
    void syncScanState();
    void publishStatus();

    const DeviceConfig& device_;
    std::unique_ptr<live_output::LivePublisher> publisher_;
    std::unique_ptr<ScanSession> session_;
    SampleQueues& queues_;
    WorkerInputs inputs_;
    sources::LiveSource source_;
    std::unique_ptr<Sink> sink_;
    std::unique_ptr<worker::PipelineWorker> worker_;
    std::vector<sources::Sample> samples_;
    TimeNs last_status_ = 0;
    std::uint64_t dropped_reported_ = 0;
    TimeNs dropped_logged_ = 0;

    mutable std::mutex mutex_;
    std::deque<Request> requests_;
    std::string journal_path_;
    const std::string journal_root_;
    bool can_continue_ = false;  // pipeline thread: an earlier scan can be continued
    std::atomic<shm::ScanState> scan_state_{shm::ScanState::kIdle};
    std::atomic<TimeNs> last_loop_{0};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace handscan::pipeline_daemon
