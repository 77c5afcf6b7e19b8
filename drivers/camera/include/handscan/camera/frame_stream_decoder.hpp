// A camera's recorded buffers (frame records, as /camera/colour holds them) back into Images,
// stamped at mid-exposure by the same rule the live CameraDevice applies to the buffer it
// dequeues (midExposureTime with the record's V4L2 flags, timestamp and exposure, the message's
// receive time standing in for the dequeue time), so a recording replays with the live times.
#pragma once

#include <cstdint>
#include <span>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/stream_counters.hpp"

namespace handscan::camera {

class FrameStreamDecoder {
public:
    // `readout`: end of exposure to end of frame, as CameraConfig::readout of the live device.
    explicit FrameStreamDecoder(TimeNs readout = 0) : readout_(readout) {}
    // The image of one record received (dequeued) at `t_rx`; errors are counted and returned.
    Result<Image> decode(TimeNs t_rx, std::span<const std::uint8_t> record);
    StreamCounters counters() const { return c_; }

private:
    TimeNs readout_;
    StreamCounters c_;
};

}  // namespace handscan::camera
