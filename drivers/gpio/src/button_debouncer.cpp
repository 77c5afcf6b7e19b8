#include "handscan/gpio/button_debouncer.hpp"

namespace handscan::gpio {

std::vector<ButtonChange> ButtonDebouncer::onEdge(TimeNs t, GpioEdgeType edge) {
    std::vector<ButtonChange> out;
    if (auto settled = onTime(t)) out.push_back(*settled);
    const bool level = edge == GpioEdgeType::kRising;
    last_level_ = level;
    last_edge_t_ = t;
    if (t < lockout_until_) {
        ++bounces_;
        pending_ = true;
        return out;
    }
    if (level == stable_) return out;
    stable_ = level;
    lockout_until_ = t + debounce_;
    pending_ = true;
    out.push_back({t, level});
    return out;
}

std::optional<ButtonChange> ButtonDebouncer::onTime(TimeNs now) {
    if (!pending_ || now < lockout_until_) return std::nullopt;
    pending_ = false;
    if (last_level_ == stable_) return std::nullopt;
    // Bounced and settled on the other level: a real change, at the time of its last edge.
    stable_ = last_level_;
    lockout_until_ = last_edge_t_ + debounce_;
    pending_ = lockout_until_ > now;
    return ButtonChange{last_edge_t_, stable_};
}

}  // namespace handscan::gpio
