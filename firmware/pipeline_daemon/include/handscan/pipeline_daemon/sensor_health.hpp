// SensorHealth: what the status bar shows of one device, written by its driver thread and read
// by the pipeline thread (a mutex: a few hundred updates a second, never held across I/O).
// Backoff: the retry delays of a device that is absent or vanished (doubling up to a maximum).
#pragma once

#include <atomic>
#include <mutex>
#include <string>

#include "handscan/core/time.hpp"
#include "handscan/live_output/live_publisher.hpp"

namespace handscan::pipeline_daemon {

class SensorHealth {
public:
    SensorHealth(std::string name, float expected_rate_hz)
        : name_(std::move(name)), expected_hz_(expected_rate_hz) {}

    // The device answers and streams (clears the error).
    void setConnected();
    // The device is absent, vanished or failed: `error` says what, where and what to do.
    void setLost(const std::string& error);
    // A problem that does not interrupt the stream (checksum failure, gap): shown, not fatal.
    void setWarning(const std::string& warning);
    void addSample(TimeNs t);
    // The first attempt to open the device has ended (either way); the daemon reports READY
    // once every device got this far.
    void markAttempted() { attempted_.store(true, std::memory_order_release); }
    bool attempted() const { return attempted_.load(std::memory_order_acquire); }

    // The status with the sample rate measured over the last second.
    live_output::LiveSensor snapshot(TimeNs now);
    const std::string& name() const { return name_; }

private:
    const std::string name_;
    const float expected_hz_;
    std::mutex mutex_;
    bool connected_ = false;
    std::string error_;
    TimeNs last_sample_ = 0;
    std::uint64_t samples_ = 0;
    std::uint64_t window_samples_ = 0;
    TimeNs window_start_ = 0;
    float rate_hz_ = 0;
    std::atomic<bool> attempted_{false};
};

class Backoff {
public:
    Backoff(TimeNs initial, TimeNs max) : initial_(initial), max_(max), next_(initial) {}
    TimeNs next() {
        const TimeNs d = next_;
        next_ = next_ * 2 < max_ ? next_ * 2 : max_;
        return d;
    }
    void reset() { next_ = initial_; }

private:
    TimeNs initial_, max_, next_;
};

}  // namespace handscan::pipeline_daemon
