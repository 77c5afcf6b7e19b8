// What a device stream decoder has seen: samples out, and the faults it survived. Every driver's
// stream decoder (hokuyo, xsens, motor) reports these, whether it decodes a live transport or a
// recording, so replay's stats.json and the daemon's sensor status count the same things.
#pragma once

#include <cstdint>
#include <string>

namespace handscan {

struct StreamCounters {
    std::uint64_t messages = 0;  // samples decoded
    std::uint64_t checksum_failures = 0;
    std::uint64_t resyncs = 0;
    std::uint64_t gaps = 0;    // lost messages (counter / sequence gaps)
    std::uint64_t errors = 0;  // other faults (device errors, unusable frames)
    std::string last_error;    // the newest fault, for status displays
};

}  // namespace handscan
