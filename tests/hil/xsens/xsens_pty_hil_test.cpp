// Hardware-in-the-loop: the fake MTi-20 plays the device on a real pseudo-terminal; the real
// SerialStream (termios, poll, read) and the real XsensDevice state machine drive it. The samples
// must be exactly the packets the device streamed; with faults injected on the wire the driver
// reports them, keeps going and loses only the damaged packets.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

#include "handscan/transport/serial_stream.hpp"
#include "handscan/xsens/xsens_device.hpp"
#include "handscan/xsens_fake/pty_xsens.hpp"

namespace handscan::xsens {
namespace {

struct PtyRig {
    PtyRig(FakeXsensConfig fc, FakeXsensFaults faults, PtyXsensOptions options)
        : fake(fc, std::move(faults)) {
        try {
            pty = std::make_unique<PtyXsens>(fake, options);
        } catch (const std::exception& e) {
            skip_reason = e.what();
            return;
        }
        serial = std::make_unique<transport::SerialStream>(
            transport::SerialConfig{pty->slavePath(), 921600});
        host = std::make_unique<PtyXsensHostStream>(*serial, *pty);
        device = std::make_unique<XsensDevice>(*host, deviceConfig());
    }
    // The host stamps receptions with the fake's device time: as fast as the host reads, that
    // runs far ahead of the real clock, and it is what SampleTimeFine says (see PtyXsens).
    XsensDeviceConfig deviceConfig() {
        XsensDeviceConfig dc;
        dc.clock = [p = pty.get()] { return p->deviceNow(); };
        return dc;
    }
    std::vector<ImuSample> collect(std::size_t n, TimeNs budget = 20 * kNsPerSec) {
        std::vector<ImuSample> out;
        const TimeNs end = monotonicNow() + budget;
        while (out.size() < n && monotonicNow() < end) {
            Status s = device->poll(out, 50 * kNsPerMs);
            EXPECT_TRUE(s.isOk()) << s.message();
            if (!s) break;
        }
        return out;
    }
    // Stops the device producing and reads until everything it sent has arrived.
    void drainInto(std::vector<ImuSample>& out) {
        pty->pauseStreaming();
        int quiet = 0;
        const TimeNs end = monotonicNow() + 5 * kNsPerSec;
        while (quiet < 3 && monotonicNow() < end) {
            const std::size_t before = out.size();
            const std::uint64_t bytes_before = device->stats().bytes;
            ASSERT_TRUE(device->poll(out, 30 * kNsPerMs).isOk());
            quiet =
                (pty->drained() && out.size() == before && device->stats().bytes == bytes_before)
                    ? quiet + 1
                    : 0;
        }
    }
    // The packets of the current measurement period that reached the wire undamaged.
    std::vector<StreamedPacket> truth() {
        return pty->inspect([](const FakeXsens& d) {
            std::vector<StreamedPacket> t;
            for (const auto& p : d.streamed()) {
                if (p.epoch == d.epoch() && !p.damaged) t.push_back(p);
            }
            return t;
        });
    }
    template <typename F>
    auto fakeState(F&& f) {
        return pty->inspect(std::forward<F>(f));
    }
    FakeXsens fake;
    std::unique_ptr<PtyXsens> pty;
    std::unique_ptr<transport::SerialStream> serial;
    std::unique_ptr<PtyXsensHostStream> host;
    std::unique_ptr<XsensDevice> device;
    std::string skip_reason;
};

void expectExactly(const std::vector<ImuSample>& samples,
                   const std::vector<StreamedPacket>& truth) {
    ASSERT_EQ(samples.size(), truth.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        SCOPED_TRACE("sample " + std::to_string(i));
        ASSERT_EQ(samples[i].packet_counter, truth[i].packet_counter);
        ASSERT_EQ(static_cast<std::uint32_t>(samples[i].t_device_ticks), truth[i].sample_time_fine);
        // float32 on the wire
        ASSERT_EQ(samples[i].accel_mps2_imu.cast<float>(), truth[i].accel_mps2.cast<float>());
        ASSERT_EQ(samples[i].gyro_radps_imu.cast<float>(), truth[i].gyro_radps.cast<float>());
        ASSERT_EQ(samples[i].status_word, truth[i].status_word);
    }
}

TEST(XsensPtyHil, StreamingDeviceIsConfiguredAndEverySampleArrives) {
    PtyRig rig({}, {}, PtyXsensOptions{.real_time = false, .recorded_measurement = {}});
    if (!rig.pty) GTEST_SKIP() << rig.skip_reason;
    Status s = rig.device->configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(rig.device->productCode(), "MTi-20-2A5G4");
    EXPECT_EQ(rig.fakeState([](const FakeXsens& d) { return d.rateHz(); }), 200);
    auto samples = rig.collect(2000);
    ASSERT_GE(samples.size(), 2000u);
    rig.drainInto(samples);
    expectExactly(samples, rig.truth());
    EXPECT_EQ(rig.device->stats().gaps, 0u);
    EXPECT_EQ(rig.device->stats().checksum_failures, 0u);
    // Both the 16-bit counter and the 32-bit SampleTimeFine wrapped on the way, and the time
    // mapping held all through: SampleTimeFine and the (device-time) receptions agree.
    EXPECT_EQ(rig.device->clock().wraps(), 1);
    EXPECT_EQ(rig.device->clock().resets(), 0);
    EXPECT_EQ(rig.device->clock().outliers(), 0);
    // Every mapped time lies on the 200 Hz line through the last one, within the receive latency
    // the fake allows (kFastLeadBytes: ~5 packets) plus one packet of chunking.
    EXPECT_NEAR(rig.device->clock().driftPpm(), 0.0, 100.0);
    const TimeNs last = samples.back().t_host;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const TimeNs on_line = last - static_cast<TimeNs>(samples.size() - 1 - i) * 5 * kNsPerMs;
        ASSERT_NEAR(static_cast<double>(samples[i].t_host - on_line), 0.0, 35e6) << "sample " << i;
    }
}

TEST(XsensPtyHil, RealTimeSamplesGetHostTimesFiveMillisecondsApart) {
    PtyRig rig({}, {}, PtyXsensOptions{.real_time = true, .recorded_measurement = {}});
    if (!rig.pty) GTEST_SKIP() << rig.skip_reason;
    ASSERT_TRUE(rig.device->configure().isOk());
    const auto samples = rig.collect(100, 5 * kNsPerSec);
    ASSERT_GE(samples.size(), 100u);
    std::vector<double> steps;
    for (std::size_t i = 1; i < samples.size(); ++i) {
        steps.push_back(static_cast<double>(samples[i].t_host - samples[i - 1].t_host));
    }
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    EXPECT_NEAR(steps[steps.size() / 2], 5e6, 0.5e6);  // median step: 200 Hz
    // The mapped time of the newest sample is in the recent past.
    const TimeNs age = monotonicNow() - samples.back().t_host;
    EXPECT_GT(age, -5 * kNsPerMs);
    EXPECT_LT(age, 500 * kNsPerMs);
}

TEST(XsensPtyHil, FaultsAreReportedAndCostOnlyTheDamagedPackets) {
    FakeXsensConfig fc;
    fc.streaming_at_start = false;  // packet indices then count from GoToMeasurement
    FakeXsensFaults faults;
    faults.drop_byte_in_packet = {100, 500, 501};
    faults.corrupt_checksum_in_packet = {250};
    faults.error_after_packet = {300};
    faults.error_code = ErrorCode::kDataOverflow;
    faults.error_replies[0xC0] = 1;  // the first SetOutputConfiguration is refused
    PtyRig rig(fc, faults, PtyXsensOptions{.real_time = false, .recorded_measurement = {}});
    if (!rig.pty) GTEST_SKIP() << rig.skip_reason;
    Status s = rig.device->configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    auto samples = rig.collect(800);
    rig.drainInto(samples);
    const auto truth = rig.truth();
    ASSERT_EQ(rig.pty->streamed().size() - truth.size(), 4u);  // all in one measurement period
    expectExactly(samples, truth);
    const auto& st = rig.device->stats();
    EXPECT_EQ(st.gaps, 3u);
    EXPECT_EQ(st.lost_packets, 4u);
    EXPECT_GE(st.checksum_failures, 1u);
    EXPECT_GE(st.resyncs, 3u);
    EXPECT_EQ(st.device_errors, 2u);  // the refused configuration and the overflow mid-stream
    std::string all;
    for (const auto& p : rig.device->problems()) all += p + "\n";
    EXPECT_NE(all.find("DataOverflow"), std::string::npos) << all;
    EXPECT_NE(all.find("setting the outputs: device answered SetOutputConfiguration with Error"),
              std::string::npos)
        << all;
    EXPECT_NE(all.find("packet counter jumped"), std::string::npos) << all;
}

TEST(XsensPtyHil, FactoryDefaultDeviceAt115200IsFoundAndMovedTo921600) {
    FakeXsensConfig fc;
    fc.baudrate = 115200;  // as shipped
    PtyRig rig(fc, {}, PtyXsensOptions{.real_time = false, .recorded_measurement = {}});
    if (!rig.pty) GTEST_SKIP() << rig.skip_reason;
    XsensDeviceConfig dc = rig.deviceConfig();
    dc.reply_timeout = 100 * kNsPerMs;
    dc.set_link_baudrate = [&rig](int baud) { return rig.serial->setBaudrate(baud); };
    rig.device = std::make_unique<XsensDevice>(*rig.host, dc);
    Status s = rig.device->configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(rig.fakeState([](const FakeXsens& d) { return d.baudrate(); }), 921600);
    EXPECT_EQ(rig.serial->describe(), "serial " + rig.pty->slavePath() + " 921600");
    auto samples = rig.collect(300);
    rig.drainInto(samples);
    expectExactly(samples, rig.truth());
    EXPECT_EQ(rig.device->stats().gaps, 0u);
}

TEST(XsensPtyHil, HangUpMidStreamIsReportedAsADisconnect) {
    PtyRig rig({}, {}, PtyXsensOptions{.real_time = false, .recorded_measurement = {}});
    if (!rig.pty) GTEST_SKIP() << rig.skip_reason;
    ASSERT_TRUE(rig.device->configure().isOk());
    ASSERT_GE(rig.collect(50).size(), 50u);
    rig.pty->hangUp();
    std::vector<ImuSample> out;
    Status s;
    for (int i = 0; i < 200 && s.isOk(); ++i) s = rig.device->poll(out, 10 * kNsPerMs);
    EXPECT_EQ(s.code(), StatusCode::kDisconnected) << s.message();
    EXPECT_FALSE(rig.device->measuring());
}

}  // namespace
}  // namespace handscan::xsens
