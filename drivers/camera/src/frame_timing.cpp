#include "handscan/camera/frame_timing.hpp"

#include "handscan/core/v4l2_types.hpp"

namespace handscan::camera {

const char* toString(TimestampSource s) {
    switch (s) {
        case TimestampSource::kStartOfExposure:
            return "start_of_exposure";
        case TimestampSource::kEndOfFrame:
            return "end_of_frame";
        case TimestampSource::kHostDequeue:
            return "host_dequeue";
    }
    return "?";
}

FrameTime midExposureTime(std::uint32_t flags, TimeNs ts, TimeNs exposure, TimeNs readout,
                          TimeNs t_dequeue) {
    const std::uint32_t clock = flags & kV4l2BufFlagTimestampMask;
    if (clock != kV4l2BufFlagTimestampMonotonic) {
        return {t_dequeue - readout - exposure / 2, TimestampSource::kHostDequeue};
    }
    if ((flags & kV4l2BufFlagTstampSrcMask) == kV4l2BufFlagTstampSrcSoe) {
        return {ts + exposure / 2, TimestampSource::kStartOfExposure};
    }
    return {ts - readout - exposure / 2, TimestampSource::kEndOfFrame};
}

std::uint32_t SequenceTracker::update(std::uint32_t seq) {
    if (!have_) {
        have_ = true;
        last_ = seq;
        return 0;
    }
    const std::uint32_t d = seq - last_;  // modulo 2^32: wraps are gaps, not restarts
    last_ = seq;
    if (d == 0 || d >= 0x80000000u) {
        ++restarts_;
        return 0;
    }
    dropped_ += d - 1;
    return d - 1;
}

}  // namespace handscan::camera
