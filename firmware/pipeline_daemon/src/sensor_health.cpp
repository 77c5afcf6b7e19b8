#include "handscan/pipeline_daemon/sensor_health.hpp"

#include "handscan/core/log.hpp"

namespace handscan::pipeline_daemon {

void SensorHealth::setConnected() {
    std::lock_guard lock(mutex_);
    if (!connected_) log().info("{}: connected", name_);
    connected_ = true;
    error_.clear();
}

void SensorHealth::setLost(const std::string& error) {
    std::lock_guard lock(mutex_);
    // Logged on the transition only: a device that stays absent is retried quietly.
    if (connected_ || error_.empty()) log().warn("{}: lost: {}", name_, error);
    connected_ = false;
    error_ = error;
}

void SensorHealth::setWarning(const std::string& warning) {
    std::lock_guard lock(mutex_);
    error_ = warning;
}

void SensorHealth::addSample(TimeNs t) {
    std::lock_guard lock(mutex_);
    last_sample_ = t;
    ++samples_;
}

live_output::LiveSensor SensorHealth::snapshot(TimeNs now) {
    std::lock_guard lock(mutex_);
    if (window_start_ == 0) {
        window_start_ = now;
        window_samples_ = samples_;
    } else if (now - window_start_ >= kNsPerSec) {
        rate_hz_ = static_cast<float>(static_cast<double>(samples_ - window_samples_) /
                                      toSeconds(now - window_start_));
        window_start_ = now;
        window_samples_ = samples_;
    }
    // A device that stopped delivering for 2 s is not streaming, whatever its driver believes.
    const bool fresh = last_sample_ != 0 && now - last_sample_ < 2 * kNsPerSec;
    return {name_,
            connected_ && (fresh || expected_hz_ == 0),
            fresh ? rate_hz_ : 0.0f,
            expected_hz_,
            last_sample_,
            error_};
}

}  // namespace handscan::pipeline_daemon
