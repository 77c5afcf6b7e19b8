// Merges the devices' samples into one stream in sample-time order. Each device's samples come
// in their own time order, but late: a scan arrives ~30 ms after its first step, an IMU frame a
// few ms after its sample, a camera frame after its exposure. A sample is released once the
// source's clock (no sample still to come was received before it) is a hold-back window past its
// time, so every sample received less than the window after it was taken is released in exact
// time order. The same rule on a recording (clock: log time) and on the live devices (clock:
// now) gives the same order for the same samples; only the end differs (a recording flushes).
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <optional>

#include "handscan/sources/sample_source.hpp"

namespace handscan::worker {

class SampleMerger {
public:
    void push(sources::Sample sample);
    // The earliest queued sample taken at or before `horizon` (equal times: IMU, encoder, scan,
    // image, then arrival order); nullopt when there is none.
    std::optional<sources::Sample> pop(TimeNs horizon);
    std::size_t size() const;
    void clear();

private:
    // One queue per device kind (the variant's index): each in its device's order.
    std::array<std::deque<sources::Sample>, std::variant_size_v<sources::Sample>> streams_;
};

}  // namespace handscan::worker
