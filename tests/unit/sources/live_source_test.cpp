// The live source hands the worker what the device threads queued, with its clock read before
// the queues are drained (so nothing it returns later was received before that clock).
#include "handscan/sources/live_source.hpp"

#include <gtest/gtest.h>

namespace handscan::sources {
namespace {

TEST(LiveSource, DrainsEveryQueueAndAnswersWithItsClock) {
    SampleQueues queues;
    TimeNs now = 5 * kNsPerSec;
    LiveSource source(queues, [&] { return now; });
    ImuSample imu;
    imu.t_host = 4 * kNsPerSec;
    ASSERT_TRUE(queues.imu.tryPush(imu));
    EncoderSample enc;
    enc.t_host = 4 * kNsPerSec + 1;
    ASSERT_TRUE(queues.encoder.tryPush(enc));
    LaserScan scan;
    scan.t_host = 3 * kNsPerSec;
    ASSERT_TRUE(queues.scans.tryPush(scan));
    std::vector<Sample> out;
    auto clock = source.next(out);
    ASSERT_TRUE(clock.isOk());
    ASSERT_TRUE(clock->has_value());
    EXPECT_EQ(**clock, 5 * kNsPerSec);
    ASSERT_EQ(out.size(), 3u);
    EXPECT_EQ(sampleTime(out[0]), 4 * kNsPerSec);
    EXPECT_TRUE(std::holds_alternative<EncoderSample>(out[1]));
    EXPECT_EQ(sampleTime(out[2]), 3 * kNsPerSec);
    out.clear();
    now += kNsPerSec;
    clock = source.next(out);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(**clock, 6 * kNsPerSec);
}

}  // namespace
}  // namespace handscan::sources
