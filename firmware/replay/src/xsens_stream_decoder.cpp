#include "handscan/replay/stream_decoders.hpp"

namespace handscan::replay {

StreamCounters XsensStreamDecoder::counters() const {
    const xsens::ImuStreamStats s = decoder_.stats();
    StreamCounters c;
    c.messages = s.samples;
    c.checksum_failures = s.checksum_failures;
    c.resyncs = s.resyncs;
    c.gaps = s.lost_packets;
    c.errors = s.device_errors + s.malformed + s.incomplete;
    c.last_error = decoder_.lastProblem();
    return c;
}

}  // namespace handscan::replay
