#include "handscan/transport/gpio_lines.hpp"

namespace handscan::transport {

TimeNs eventTimeToMonotonic(TimeNs event_ns, TimeNs monotonic_now, TimeNs realtime_now) {
    const auto dist = [](TimeNs a, TimeNs b) { return a > b ? a - b : b - a; };
    if (dist(event_ns, monotonic_now) <= dist(event_ns, realtime_now)) return event_ns;
    return event_ns - (realtime_now - monotonic_now);  // pre-5.7 kernel: REALTIME stamp
}

}  // namespace handscan::transport
