// One recorded chunk of a device's byte stream: what a driver's read() returned, when.
#pragma once

#include <cstdint>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan::sim {

enum class SimChannel : std::uint8_t {
    kHokuyo,
    kXsens,
    kCan,
    kTrackingCamera,
    kColourCamera,
    kGroundTruth,
    kCount
};

struct StreamMessage {
    TimeNs t_host_rx = 0;  // host CLOCK_MONOTONIC receive time
    SimChannel channel = SimChannel::kHokuyo;
    std::vector<std::uint8_t> bytes;
};

}  // namespace handscan::sim
