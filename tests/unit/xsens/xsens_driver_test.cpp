// The driver thread: configures, streams to the sink, and after the link drops reconnects and
// resumes; bad device.yaml values fail naming the key.
#include "handscan/xsens/xsens_driver.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "handscan/xsens_fake/fake_xsens_stream.hpp"

namespace handscan::xsens {
namespace {

// The in-memory stream, owned by the driver, reporting to the test's fake and clock.
class SharedFakeStream : public transport::ByteStream {
public:
    explicit SharedFakeStream(FakeXsensStream& s) : s_(s) {}
    Status open() override { return s_.open(); }
    void close() override { s_.close(); }
    bool isOpen() const override { return s_.isOpen(); }
    Result<std::size_t> read(std::span<std::uint8_t> b, TimeNs t) override { return s_.read(b, t); }
    Status writeAll(std::span<const std::uint8_t> d, TimeNs t) override {
        return s_.writeAll(d, t);
    }
    std::string describe() const override { return s_.describe(); }

private:
    FakeXsensStream& s_;
};

TEST(XsensDriver, StreamsAndReconnectsAfterTheLinkDrops) {
    VirtualClock clock;
    FakeXsens fake;
    FakeXsensStream stream(fake, clock);
    stream.disconnectAfter(5000);  // drops once, ~80 packets in; open() clears it
    XsensLink link;
    link.stream = std::make_unique<SharedFakeStream>(stream);
    link.device.clock = [&clock] { return clock.now; };
    std::mutex m;
    std::vector<ImuSample> got;
    XsensDriverOptions options;
    options.backoff_min = kNsPerMs;
    XsensDriver driver(
        std::move(link),
        [&](const ImuSample& s) {
            std::lock_guard lock(m);
            got.push_back(s);
        },
        nullptr, options);
    driver.start();
    for (int i = 0; i < 500; ++i) {
        {
            std::lock_guard lock(m);
            if (got.size() >= 300) break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    driver.stop();
    const XsensHealth h = driver.health();
    EXPECT_EQ(h.state, XsensDriverState::kStopped);
    EXPECT_EQ(h.reconnects, 1);
    EXPECT_GE(h.samples, 300u);
    EXPECT_EQ(h.samples, got.size());
    EXPECT_FALSE(stream.isOpen());
    // After the reconnect the samples are those of the new measurement period, in order.
    std::vector<StreamedPacket> truth;
    for (const auto& p : fake.streamed()) {
        if (p.epoch == fake.epoch()) truth.push_back(p);
    }
    const std::size_t after = std::min(truth.size(), got.size());
    ASSERT_GT(after, 100u);
    for (std::size_t i = 0; i < after; ++i) {
        const ImuSample& s = got[got.size() - after + i];
        const StreamedPacket& p = truth[truth.size() - after + i];
        ASSERT_EQ(s.packet_counter, p.packet_counter) << i;
        ASSERT_LT((s.accel_mps2_imu - p.accel_mps2).cwiseAbs().maxCoeff(), 1e-5);
    }
}

TEST(XsensDriver, UnreachableDeviceIsRetriedWithBackoffAndReported) {
    FakeXsensConfig fc;
    fc.ignore_first_goto_configs = 1000000;
    VirtualClock clock;
    FakeXsens fake(fc);
    FakeXsensStream stream(fake, clock);
    XsensLink link;
    link.stream = std::make_unique<SharedFakeStream>(stream);
    link.device.clock = [&clock] { return clock.now; };
    XsensDriverOptions options;
    options.backoff_min = kNsPerMs;
    options.backoff_max = 4 * kNsPerMs;
    XsensDriver driver(
        std::move(link), [](const ImuSample&) {}, nullptr, options);
    driver.start();
    std::this_thread::sleep_for(std::chrono::milliseconds(60));
    const XsensHealth h = driver.health();
    driver.stop();
    EXPECT_EQ(h.state, XsensDriverState::kConnecting);
    EXPECT_GE(h.reconnects, 2);
    EXPECT_NE(h.last_problem.find("no GoToConfigAck"), std::string::npos) << h.last_problem;
    EXPECT_NE(h.last_problem.find("retrying"), std::string::npos) << h.last_problem;
}

TEST(XsensDriver, LinkFromDeviceYaml) {
    XsensConfig c;
    auto ok = makeXsensLink(c);
    ASSERT_TRUE(ok.isOk()) << ok.status().message();
    EXPECT_EQ(ok->stream->describe(), "serial /dev/ttyUSB0 921600");
    EXPECT_EQ(ok->device.output_rate_hz, 200);
    EXPECT_TRUE(static_cast<bool>(ok->device.set_link_baudrate));
    EXPECT_EQ(ok->device.frame_latency, 0);
    c.frame_latency_ms = 1.25;  // the sample -> host delay the clock fit takes out (ImuFrameTiming)
    EXPECT_EQ(makeXsensLink(c)->device.frame_latency, 1'250'000);
    c.rate_hz = 150;
    EXPECT_NE(makeXsensLink(c).status().message().find("xsens.rate_hz"), std::string::npos);
    c.rate_hz = 200;
    c.baud = 1000000;
    EXPECT_NE(makeXsensLink(c).status().message().find("xsens.baud"), std::string::npos);
    c.transport = "bluetooth";
    EXPECT_NE(makeXsensLink(c).status().message().find("xsens.transport"), std::string::npos);
    c.transport = "usb";
    c.baud = 921600;
    auto usb = makeXsensLink(c);
#if defined(HANDSCAN_WITH_LIBUSB) && HANDSCAN_WITH_LIBUSB
    ASSERT_TRUE(usb.isOk());
    EXPECT_EQ(usb->stream->describe(), "usb 2639:*");
#else
    EXPECT_EQ(usb.status().code(), StatusCode::kUnsupported);
#endif
}

}  // namespace
}  // namespace handscan::xsens
