#include "handscan/motor/paced_can_bus.hpp"

#include <chrono>
#include <thread>

namespace handscan::motor {

void PacedCanBus::anchor() {
    if (anchored_) return;
    offset_ = monotonicNow() - inner_now_();
    anchored_ = true;
}

TimeNs PacedCanBus::now() const { return anchored_ ? inner_now_() + offset_ : monotonicNow(); }

Result<TimedCanFrame> PacedCanBus::receive(TimeNs timeout) {
    anchor();
    auto r = inner_.receive(timeout);
    // The inner bus jumps its clock to the next frame (or by the timeout); wait until the host
    // clock gets there, so nothing arrives before it was sent.
    const TimeNs due = (r.isOk() ? r->t_host : inner_now_()) + offset_;
    const TimeNs wait = due - monotonicNow();
    if (wait > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(wait));
    if (!r.isOk()) return r;
    TimedCanFrame f = *r;
    f.t_host = due;
    return f;
}

}  // namespace handscan::motor
