// CommandHandler: executes the operator's commands, from the touch screen (the shared-memory
// command channel, answered with acks) or from the panel's buttons (same actions, no ack):
//   start / stop scan, new scan (new journal, new map epoch) -> the pipeline thread's ScanSession
//   continue [scan=NAME] [pose=...] -> the earlier scan loaded on a thread of its own (EarlierScan;
//                        a long scan's journal takes seconds, longer than the watchdog allows
//                        this loop), acked kInProgress; then a new scan localized on it
//                        (PipelineThread::continueScan), acked kDone; while that scan searches
//                        for its place, continue pose=... places the operator again
//   export [DIR|usb]  -> ExportJob (the code path of `handscan export`), acked kInProgress with
//                        progress until it ends kDone ("safe to remove") or kFailed
//   calibrate [rounds=N] -> CalibrateJob on the last scan's raw recording, acked kInProgress with
//                        progress until kDone (calibration.yaml replaced, .prev kept) or kFailed
//   shutdown          -> acked, then the daemon ends the scan cleanly and exits
#pragma once

#include <cstdint>
#include <future>
#include <optional>
#include <string>

#include "handscan/pipeline_daemon/calibrate_job.hpp"
#include "handscan/pipeline_daemon/export_job.hpp"
#include "handscan/pipeline_daemon/pipeline_thread.hpp"
#include "handscan/shm/live_map_writer.hpp"

namespace handscan::pipeline_daemon {

class CommandHandler {
public:
    // `calibration` may be null (no calibrate command).
    CommandHandler(PipelineThread& worker, ExportJob& exports, shm::LiveMapWriter& channel,
                   CalibrateJob* calibration = nullptr)
        : worker_(worker), exports_(exports), channel_(channel), calibration_(calibration) {}

    // Takes and answers every pending command of the channel.
    void pollChannel();
    void onButton(ButtonAction action);
    // Progress acks of a running export, and its final answer.
    void tick();
    bool shutdownRequested() const { return shutdown_; }

private:
    struct Outcome {
        shm::CommandState state;
        std::string message;
    };
    Outcome execute(shm::CommandType type, const std::string& argument, std::uint64_t seq);
    // Starts loading the scan to continue; the message for the kInProgress ack.
    Result<std::string> continueScan(const std::string& argument, std::uint64_t seq);
    void finishContinue();
    // continue with a pose while scanning: where the operator stands now, for the continued
    // scan still searching for its place.
    Result<std::string> placeAgain(const std::string& argument);
    Outcome calibrate(const std::string& argument, std::uint64_t seq);
    void tickCalibration();

    PipelineThread& worker_;
    ExportJob& exports_;
    shm::LiveMapWriter& channel_;
    CalibrateJob* calibration_;
    std::uint64_t export_seq_ = 0;  // the command the running export answers (0: a button)
    std::uint64_t calibrate_seq_ = 0;
    TimeNs last_calibration_ack_ = 0;
    TimeNs last_progress_ack_ = 0;
    bool shutdown_ = false;
    struct Continuing {
        std::uint64_t seq = 0;
        std::optional<Eigen::Isometry3d> initial_pose;
        std::future<Result<std::shared_ptr<const EarlierScan>>> loaded;
    };
    std::optional<Continuing> continuing_;
};

}  // namespace handscan::pipeline_daemon
