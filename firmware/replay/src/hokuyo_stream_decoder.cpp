#include <variant>

#include "handscan/replay/stream_decoders.hpp"

namespace handscan::replay {

void HokuyoStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes,
                               std::vector<LaserScan>& out) {
    events_.clear();
    decoder_.feed(t_rx, bytes, out, events_);
    // Replies in the recorded stream are of no use here; faults are counted.
    for (const hokuyo::ScipEvent& ev : events_) {
        if (const auto* fault = std::get_if<hokuyo::ScipFault>(&ev)) {
            ++faults_;
            last_fault_ = fault->message;
        }
    }
}

StreamCounters HokuyoStreamDecoder::counters() const {
    const hokuyo::ScanStreamStats s = decoder_.stats();
    StreamCounters c;
    c.messages = s.scans;
    c.checksum_failures = s.parser.checksum_failures;
    c.resyncs = s.parser.resyncs;
    c.gaps = s.missed_scans;
    c.errors = faults_;
    c.last_error = last_fault_;
    return c;
}

}  // namespace handscan::replay
