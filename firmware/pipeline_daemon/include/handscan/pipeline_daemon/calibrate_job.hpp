// CalibrateJob: `handscan calibrate` (calibrate::selfCalibrate, the same code) on the last scan's
// raw recording (scan_recorder.hpp), on a thread of its own at idle priority (SCHED_IDLE: it
// takes only CPU time the pipeline and the devices leave), one at a time. Progress (the step
// running) and the outcome (every value with its standard deviation, which were written) are kept
// as the status block's CalibrationStatus for the UI.
//
// The factory calibration (/etc/handscan/calibration.yaml, read-only on the device: the unit's
// ProtectSystem=strict) is never written: the result goes to the field calibration
// (/var/lib/handscan/calibration/calibration.yaml), which the daemon reads instead of the
// factory's once it exists, and which the next calibration starts from. It is installed only
// when the run succeeded, and a previous field calibration is kept as calibration.yaml.prev:
// the new file is written beside it under a temporary name, the old one hard-linked to .prev
// (atomic rename), then the new one renamed over it - at every moment calibration.yaml is one
// whole file. Deleting the field calibration goes back to the factory's. A scan in progress
// keeps the calibration it started with; the new one applies from the next scan
// (takeInstalled, PipelineThread), and from every later start of the daemon.
#pragma once

#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "handscan/core/status.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::pipeline_daemon {

class CalibrateJob {
public:
    // The daemon's device.yaml, the factory calibration and the field calibration to write
    // (the same path: the factory file itself is replaced, as on a development machine).
    CalibrateJob(std::string device_yaml, std::string factory_yaml, std::string field_yaml)
        : device_yaml_(std::move(device_yaml)),
          factory_yaml_(std::move(factory_yaml)),
          calibration_yaml_(std::move(field_yaml)) {}
    ~CalibrateJob();
    CalibrateJob(const CalibrateJob&) = delete;
    CalibrateJob& operator=(const CalibrateJob&) = delete;

    // Starts the calibration on `recording` with at most `rounds` replay-and-solve rounds.
    // Refused (kInvalidArgument) while another runs.
    Status start(const std::string& recording, int rounds = 4);
    bool running() const;
    shm::CalibrationStatus status() const;
    // The outcome of a finished run, once: the message for the operator, or the error.
    std::optional<Result<std::string>> takeResult();
    // The path of a calibration installed since the last call (once; none otherwise).
    std::optional<std::string> takeInstalled();

private:
    void run(std::string recording, int rounds);
    void step(const std::string& line, int rounds);

    const std::string device_yaml_, factory_yaml_, calibration_yaml_;
    mutable std::mutex mutex_;
    shm::CalibrationStatus status_{};
    bool running_ = false;
    std::optional<Result<std::string>> result_;
    bool installed_ = false;  // a new calibration.yaml since the last takeInstalled()
    std::thread thread_;
};

// The calibration the daemon runs with: the field calibration once one was written, else the
// factory's (`field` empty: the factory's).
std::string calibrationInUse(const std::string& factory, const std::string& field);

// Replaces `target` with `fresh` (a complete file beside it), keeping the old one as
// `target`.prev; each step an atomic rename, the directory synced.
Status installKeepingPrevious(const std::string& fresh, const std::string& target);

}  // namespace handscan::pipeline_daemon
