// SensorHealth: measured rate over one-second windows, "lost" with its error text, and a device
// that stops delivering shown as not connected even before its driver notices.
#include "handscan/pipeline_daemon/sensor_health.hpp"

#include <gtest/gtest.h>

namespace handscan::pipeline_daemon {
namespace {

TEST(SensorHealth, RateConnectedAndLost) {
    SensorHealth h("xsens", 200.0f);
    const TimeNs t0 = 100 * kNsPerSec;
    auto s = h.snapshot(t0);
    EXPECT_FALSE(s.connected);  // nothing delivered yet
    EXPECT_EQ(s.name, "xsens");
    EXPECT_EQ(s.expected_rate_hz, 200.0f);
    h.setConnected();
    for (int i = 0; i < 200; ++i) h.addSample(t0 + i * 5 * kNsPerMs);
    s = h.snapshot(t0 + kNsPerSec);
    EXPECT_TRUE(s.connected);
    EXPECT_NEAR(s.rate_hz, 200.0f, 1e-3f);
    EXPECT_TRUE(s.last_error.empty());
    // Silent for 3 s: not connected, no rate, whatever the driver says.
    s = h.snapshot(t0 + 4 * kNsPerSec);
    EXPECT_FALSE(s.connected);
    EXPECT_EQ(s.rate_hz, 0.0f);
    h.setLost("xsens serial /dev/ttyUSB0: no reply to GoToConfig");
    s = h.snapshot(t0 + 5 * kNsPerSec);
    EXPECT_FALSE(s.connected);
    EXPECT_EQ(s.last_error, "xsens serial /dev/ttyUSB0: no reply to GoToConfig");
    EXPECT_FALSE(h.attempted());
    h.markAttempted();
    EXPECT_TRUE(h.attempted());
}

TEST(SensorHealth, EventDrivenDeviceIsConnectedWithoutSamples) {
    SensorHealth h("buttons", 0.0f);
    h.setConnected();
    EXPECT_TRUE(h.snapshot(kNsPerSec).connected);
}

TEST(Backoff, DoublesUpToTheMaximumAndResets) {
    Backoff b(100 * kNsPerMs, 350 * kNsPerMs);
    EXPECT_EQ(b.next(), 100 * kNsPerMs);
    EXPECT_EQ(b.next(), 200 * kNsPerMs);
    EXPECT_EQ(b.next(), 350 * kNsPerMs);
    EXPECT_EQ(b.next(), 350 * kNsPerMs);
    b.reset();
    EXPECT_EQ(b.next(), 100 * kNsPerMs);
}

}  // namespace
}  // namespace handscan::pipeline_daemon
