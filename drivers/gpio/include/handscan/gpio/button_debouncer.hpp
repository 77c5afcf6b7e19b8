// Debounce of a mechanical button from its kernel edge events. The first edge that changes the
// debounced level is taken at once (so a press keeps the time of its first contact); edges in
// the following `debounce` window are bounce and only remembered; if the line settled on the
// other level by the end of the window, that change is reported at its last edge's time.
// Pure: edges in, press/release events out.
#pragma once

#include <optional>
#include <vector>

#include "handscan/core/samples.hpp"

namespace handscan::gpio {

struct ButtonChange {
    TimeNs t_host = 0;
    bool pressed = false;
};

class ButtonDebouncer {
public:
    explicit ButtonDebouncer(TimeNs debounce = 20 * kNsPerMs, bool initially_pressed = false)
        : debounce_(debounce), stable_(initially_pressed), last_level_(initially_pressed) {}

    // 0, 1 or 2 changes (a window that ended before this edge may settle first).
    std::vector<ButtonChange> onEdge(TimeNs t, GpioEdgeType edge);
    // Call when time passes without edges (the end of a bounce window may change the level).
    std::optional<ButtonChange> onTime(TimeNs now);
    bool pressed() const { return stable_; }
    // When onTime() next needs to run (kNoDeadline when nothing is pending).
    TimeNs deadline() const { return pending_ ? lockout_until_ : kNoDeadline; }
    std::uint64_t bounces() const { return bounces_; }

    static constexpr TimeNs kNoDeadline = INT64_MAX;

private:
    TimeNs debounce_;
    bool stable_;
    bool last_level_;
    TimeNs last_edge_t_ = 0;
    TimeNs lockout_until_ = INT64_MIN;
    bool pending_ = false;
    std::uint64_t bounces_ = 0;
};

}  // namespace handscan::gpio
