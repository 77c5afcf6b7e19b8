// When was a frame exposed? V4L2 stamps a buffer at the start of exposure (SOE, e.g. uvcvideo)
// or at the end of the frame (EOF, the default), on CLOCK_MONOTONIC when the MONOTONIC flag is
// set. The pipeline wants the middle of the exposure (the frame's effective instant), so:
//   SOE:  t_mid = t + exposure/2
//   EOF:  t_mid = t - readout - exposure/2   (readout: exposure end to last line transferred)
//   other clocks (UNKNOWN, COPY): the host dequeue time stands in for EOF (late by the latency).
// Sequence gaps (v4l2_buffer.sequence) count frames the driver dropped.
#pragma once

#include <cstdint>

#include "handscan/core/time.hpp"

namespace handscan::camera {

enum class TimestampSource : std::uint8_t { kStartOfExposure, kEndOfFrame, kHostDequeue };
const char* toString(TimestampSource s);

struct FrameTime {
    TimeNs t_mid_exposure = 0;
    TimestampSource source = TimestampSource::kEndOfFrame;
};

FrameTime midExposureTime(std::uint32_t buffer_flags, TimeNs buffer_timestamp, TimeNs exposure,
                          TimeNs readout, TimeNs t_dequeue);

class SequenceTracker {
public:
    // Frames lost between the previous sequence number and this one (0 for consecutive ones).
    // A number that goes backwards (stream restarted) resets the tracker and counts a restart.
    std::uint32_t update(std::uint32_t sequence);
    std::uint64_t dropped() const { return dropped_; }
    std::uint64_t restarts() const { return restarts_; }
    void reset() { have_ = false; }

private:
    bool have_ = false;
    std::uint32_t last_ = 0;
    std::uint64_t dropped_ = 0;
    std::uint64_t restarts_ = 0;
};

}  // namespace handscan::camera
