#include <chrono>

#include "handscan/core/realtime.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {

SensorSource::~SensorSource() { stop(); }

void SensorSource::start(int fifo_priority) {
    stop_.store(false, std::memory_order_release);
    fifo_priority_ = fifo_priority;
    thread_ = std::thread([this, fifo_priority] {
        (void)enterRealtimeThread("hs-" + health_.name(), fifo_priority);  // warns once if denied
        run();
    });
}

void SensorSource::stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
}

bool SensorSource::sleepFor(TimeNs t) {
    // Short slices so stop() is prompt; device back-off is seconds at most.
    const TimeNs until = monotonicNow() + t;
    while (!stopping()) {
        const TimeNs left = until - monotonicNow();
        if (left <= 0) return true;
        std::this_thread::sleep_for(
            std::chrono::nanoseconds(std::min<TimeNs>(left, 20 * kNsPerMs)));
    }
    return false;
}

void SensorSource::runSessions(TimeNs first_wait, TimeNs max_wait, const std::string& what,
                               const char* hint, const std::function<Status()>& session) {
    Backoff backoff(first_wait, max_wait);
    while (!stopping()) {
        const Status end = session();
        if (stopping()) return;  // a clean stop, not a lost device
        health_.setLost(what + ": " + end.message() + hint);
        health_.markAttempted();
        if (!sleepFor(backoff.next())) return;
    }
}

}  // namespace handscan::pipeline_daemon
