#include "handscan/camera/frame_timing.hpp"

#include <gtest/gtest.h>

#include "handscan/transport/v4l2_device.hpp"

namespace handscan::camera {
namespace {

using namespace transport;

TEST(FrameTiming, ShiftsToMidExposure) {
    const TimeNs t = 10 * kNsPerSec, exp = 8 * kNsPerMs, readout = 20 * kNsPerMs,
                 deq = t + 50 * kNsPerMs;
    auto soe = midExposureTime(kV4l2BufFlagTimestampMonotonic | kV4l2BufFlagTstampSrcSoe, t, exp,
                               readout, deq);
    EXPECT_EQ(soe.t_mid_exposure, t + 4 * kNsPerMs);
    EXPECT_EQ(soe.source, TimestampSource::kStartOfExposure);
    auto eof = midExposureTime(kV4l2BufFlagTimestampMonotonic | kV4l2BufFlagTstampSrcEof, t, exp,
                               readout, deq);
    EXPECT_EQ(eof.t_mid_exposure, t - 20 * kNsPerMs - 4 * kNsPerMs);
    EXPECT_EQ(eof.source, TimestampSource::kEndOfFrame);
    auto copy = midExposureTime(kV4l2BufFlagTimestampCopy, t, exp, readout, deq);
    EXPECT_EQ(copy.t_mid_exposure, deq - 24 * kNsPerMs);
    EXPECT_EQ(copy.source, TimestampSource::kHostDequeue);
    auto unknown =
        midExposureTime(kV4l2BufFlagTimestampUnknown | kV4l2BufFlagTstampSrcSoe, t, exp, 0, deq);
    EXPECT_EQ(unknown.source, TimestampSource::kHostDequeue);
}

TEST(SequenceTracker, CountsGapsAcrossTheWrapAndRestarts) {
    SequenceTracker s;
    EXPECT_EQ(s.update(10), 0u);
    EXPECT_EQ(s.update(11), 0u);
    EXPECT_EQ(s.update(14), 2u);
    EXPECT_EQ(s.dropped(), 2u);
    SequenceTracker w;
    EXPECT_EQ(w.update(0xFFFFFFFEu), 0u);
    EXPECT_EQ(w.update(1), 2u);  // FFFFFFFF and 0 lost
    EXPECT_EQ(w.update(0), 0u);  // backwards: restart
    EXPECT_EQ(w.restarts(), 1u);
    EXPECT_EQ(w.update(1), 0u);
    EXPECT_EQ(w.dropped(), 2u);
}

}  // namespace
}  // namespace handscan::camera
