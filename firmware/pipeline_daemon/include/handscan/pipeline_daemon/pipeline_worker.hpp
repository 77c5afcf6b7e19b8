// PipelineWorker: the daemon's pipeline thread. It drains the drivers' SPSC queues, feeds the
// samples to the laser-inertial odometry in time order (held back 100 ms so that a scan, which
// arrives ~30 ms after its first step, is not overtaken by the IMU and encoder samples it needs),
// colours each registered sweep from the colour camera, and writes every output: poses, display
// map and status to shared memory (live_output::LivePublisher, the same code as replay --live),
// poses and full-resolution points to the scan's journal while scanning (ScanSession). Scan
// control runs on this thread too, so the journal and the map epoch have a single owner.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <mutex>
#include <thread>

#include "handscan/colour/colouriser.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/live_output/live_publisher.hpp"
#include "handscan/pipeline_daemon/scan_session.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {

enum class ScanControl { kStart, kStop, kNewScan, kFinish };

struct WorkerInputs {
    // Status of every device (thread-safe snapshots), for the status block.
    std::function<std::vector<live_output::LiveSensor>()> sensors;
    std::function<shm::ExportStatus()> export_status;
};

class PipelineWorker {
public:
    PipelineWorker(const DeviceConfig& device, const Calibration& calibration,
                   std::unique_ptr<live_output::LivePublisher> publisher,
                   std::unique_ptr<ScanSession> session, SampleQueues& queues, WorkerInputs inputs);
    ~PipelineWorker();
    PipelineWorker(const PipelineWorker&) = delete;
    PipelineWorker& operator=(const PipelineWorker&) = delete;

    // Starts the pipeline thread, SCHED_FIFO at `fifo_priority` when permitted (0: normal).
    void start(int fifo_priority = 0);
    void stop();
    // Runs `control` on the pipeline thread; the operator's message or why it was refused.
    Result<std::string> control(ScanControl control, TimeNs timeout = 5 * kNsPerSec);

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
    };
    void run();
    void handle(Request& r);
    void drainQueues();
    void feed(TimeNs horizon, TimeNs deadline = std::numeric_limits<TimeNs>::max());
    void consume();
    void publishStatus();
    void resetPipeline();

    const DeviceConfig& device_;
    const Calibration& calibration_;
    std::unique_ptr<live_output::LivePublisher> publisher_;
    std::unique_ptr<ScanSession> session_;
    SampleQueues& queues_;
    WorkerInputs inputs_;
    std::unique_ptr<lio::LaserInertialOdometry> lio_;
    std::unique_ptr<colour::Colouriser> colouriser_;
    std::deque<ImuSample> imu_;
    std::deque<EncoderSample> encoder_;
    std::deque<LaserScan> scans_;
    std::deque<Image> images_;
    TimeNs last_status_ = 0;
    std::uint64_t dropped_reported_ = 0;
    TimeNs dropped_logged_ = 0;

    mutable std::mutex mutex_;
    std::deque<Request> requests_;
    std::string journal_path_;
    std::atomic<shm::ScanState> scan_state_{shm::ScanState::kIdle};
    std::atomic<TimeNs> last_loop_{0};
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace handscan::pipeline_daemon
