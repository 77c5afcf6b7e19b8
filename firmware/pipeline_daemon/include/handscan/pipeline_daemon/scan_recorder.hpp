// ScanRecorder: the raw streams of the laser, the IMU and the encoder of each scan, recorded into
// the scan's directory (raw.mcap; raw-2.mcap ... for each resumed stretch) in the format
// `handscan replay` and `handscan calibrate` read - so a scan can be reprocessed, and the daemon
// can self-calibrate on the last one (calibrate_job.hpp).
//
// The drivers are made once and keep their RawTap for life; a scan's recording comes and goes.
// Each driver therefore gets a SwitchableTap, which forwards to the current recording's tap (the
// Recorder's lock-free SPSC queue: the driver thread never blocks, a full queue drops and counts)
// or to nothing between recordings. The Recorder's own writer thread does every write and fsync.
//
// Disk budget: a recording starts only while the storage has storage.min_free_gib beyond the
// journal's reserve, and stops (the scan goes on, the file is finished) when it falls below: the
// journal keeps its room. The cameras are not recorded (a tracking camera alone is ~0.5 GB a
// minute; calibration needs laser, IMU and encoder only).
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "handscan/core/raw_tap.hpp"
#include "handscan/core/status.hpp"
#include "handscan/recording/recorder.hpp"

namespace handscan::pipeline_daemon {

// A RawTap that forwards to a target that can change while drivers call it.
//
// A stream that only decodes after its start-up exchange (the Hokuyo's PP reply gives the scan
// geometry) keeps that exchange as a preamble: the bytes between beginPreamble() and
// endPreamble() (the driver's thread, when its device connects and when it streams), which
// attach() hands to the new target first, with their own receive times.
class SwitchableTap final : public RawTap {
public:
    void onRaw(TimeNs t_host_rx, std::span<const std::uint8_t> bytes) override;
    // Sends the preamble, then forwards every call to `target`.
    void attach(RawTap* target);
    // Forwards nothing more; returns once no call into the old target is still running.
    void detach();
    void beginPreamble();
    void endPreamble();

private:
    static constexpr std::size_t kMaxPreambleBytes = 64 * 1024;
    std::atomic<RawTap*> target_{nullptr};
    std::atomic<int> busy_{0};
    std::atomic<bool> capturing_{false};
    std::mutex preamble_mutex_;  // held only while capturing (start-up), never while streaming
    std::vector<std::pair<TimeNs, std::vector<std::uint8_t>>> preamble_;
    std::size_t preamble_bytes_ = 0;
};

struct ScanRecorderOptions {
    bool enabled = true;                        // device.yaml storage.record_scans
    std::uint64_t min_free_bytes = 1ull << 30;  // storage.min_free_gib (+ the journal's reserve)
};

class ScanRecorder {
public:
    explicit ScanRecorder(ScanRecorderOptions options) : options_(options) {}
    ~ScanRecorder();
    ScanRecorder(const ScanRecorder&) = delete;
    ScanRecorder& operator=(const ScanRecorder&) = delete;

    // The taps the drivers get (alive as long as the recorder).
    SwitchableTap* hokuyoTap() { return &hokuyo_; }
    RawTap* xsensTap() { return &xsens_; }
    RawTap* motorTap() { return &motor_; }

    // Starts recording into a new file in `scan_dir`; the message says where, or why not
    // (switched off, too little space, the file could not be made).
    std::string start(const std::string& scan_dir);
    // Detaches the taps, drains the queues, finishes the file (on the calling thread: the
    // writer thread is joined). Says what was written and dropped; ok when nothing records.
    Result<std::string> stop();
    // The disk budget, checked at most once a second: stops the recording when it is spent.
    void checkSpace();
    bool recording() const { return recorder_ != nullptr; }

private:
    ScanRecorderOptions options_;
    SwitchableTap hokuyo_, xsens_, motor_;
    std::unique_ptr<recording::Recorder> recorder_;
    std::string path_;
    TimeNs last_check_ = 0;
};

// The largest raw*.mcap in a scan directory (the longest stretch; "" when there is none).
std::string scanRecording(const std::string& scan_dir);

}  // namespace handscan::pipeline_daemon
