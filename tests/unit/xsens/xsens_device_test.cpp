// The device state machine against the fake MTi-20 over an in-memory stream with a virtual
// clock: handshake, retries, Error replies, samples equal to what was streamed, counter and
// SampleTimeFine wrap, faults costing only the damaged packet, disconnect and recovery, raw tap.
#include "handscan/xsens/xsens_device.hpp"

#include <gtest/gtest.h>

#include "handscan/xsens_fake/fake_xsens_stream.hpp"

namespace handscan::xsens {
namespace {

struct TapRecorder : RawTap {
    void onRaw(TimeNs t, std::span<const std::uint8_t> bytes) override {
        times.push_back(t);
        data.insert(data.end(), bytes.begin(), bytes.end());
    }
    std::vector<TimeNs> times;
    std::vector<std::uint8_t> data;
};

struct Rig {
    explicit Rig(FakeXsensConfig fc = {}, FakeXsensFaults faults = {}, XsensDeviceConfig dc = {})
        : fake(fc, std::move(faults)),
          stream(fake, clock),
          device(stream, withClock(std::move(dc)), &tap) {}
    XsensDeviceConfig withClock(XsensDeviceConfig dc) {
        dc.clock = [this] { return clock.now; };
        return dc;
    }
    std::vector<ImuSample> collect(std::size_t n) {
        std::vector<ImuSample> out;
        for (int i = 0; i < 100000 && out.size() < n; ++i) {
            Status s = device.poll(out, 10 * kNsPerMs);
            EXPECT_TRUE(s.isOk()) << s.message();
            if (!s) break;
        }
        return out;
    }
    VirtualClock clock;
    FakeXsens fake;
    FakeXsensStream stream;
    TapRecorder tap;
    XsensDevice device;
};

// Streamed packets that were not damaged, from the first one after `first_index`.
std::vector<StreamedPacket> intact(const FakeXsens& fake, std::uint64_t first_index = 0) {
    std::vector<StreamedPacket> out;
    for (const auto& p : fake.streamed()) {
        if (!p.damaged && p.index >= first_index) out.push_back(p);
    }
    return out;
}

void expectSamplesMatch(const std::vector<ImuSample>& samples,
                        const std::vector<StreamedPacket>& truth) {
    ASSERT_LE(samples.size(), truth.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        SCOPED_TRACE("sample " + std::to_string(i));
        EXPECT_EQ(samples[i].packet_counter, truth[i].packet_counter);
        EXPECT_EQ(static_cast<std::uint32_t>(samples[i].t_device_ticks), truth[i].sample_time_fine);
        EXPECT_LT((samples[i].accel_mps2_imu - truth[i].accel_mps2).cwiseAbs().maxCoeff(), 1e-5);
        EXPECT_LT((samples[i].gyro_radps_imu - truth[i].gyro_radps).cwiseAbs().maxCoeff(), 1e-6);
        EXPECT_EQ(samples[i].status_word, truth[i].status_word);
    }
}

TEST(XsensDevice, HandshakeFromAStreamingDevice) {
    Rig rig;
    ASSERT_TRUE(rig.fake.measuring());
    for (int i = 0; i < 5; ++i) rig.fake.emitPacket();  // bytes already in flight before GoToConfig
    Status s = rig.device.configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(rig.fake.requestsSeen(), (std::vector<std::uint8_t>{0x30, 0x00, 0x1C, 0xC0, 0x10}));
    EXPECT_EQ(rig.device.deviceId(), 0x01A00E3Fu);
    EXPECT_EQ(rig.device.productCode(), "MTi-20-2A5G4");
    EXPECT_EQ(rig.fake.rateHz(), 200);
    const std::vector<OutputConfigEntry> expected{
        {0x1020, 0xFFFF}, {0x1060, 0xFFFF}, {0x4020, 200}, {0x8020, 200}, {0xE020, 0xFFFF}};
    EXPECT_EQ(rig.fake.outputConfiguration(), expected);
    EXPECT_EQ(rig.device.outputConfiguration(), expected);
    EXPECT_TRUE(rig.device.measuring());
}

TEST(XsensDevice, SamplesEqualWhatWasStreamedAcrossBothWraps) {
    Rig rig;  // counter starts at 65530, SampleTimeFine 4096 ticks before 2^32
    ASSERT_TRUE(rig.device.configure().isOk());
    const std::size_t already = rig.fake.streamed().size();
    const auto samples = rig.collect(400);  // 2 s at 200 Hz
    ASSERT_EQ(samples.size(), 400u);
    expectSamplesMatch(samples, intact(rig.fake, already));
    for (std::size_t i = 1; i < samples.size(); ++i) {
        EXPECT_EQ(
            static_cast<std::uint16_t>(samples[i].packet_counter - samples[i - 1].packet_counter),
            1);
        EXPECT_EQ(samples[i].t_device_ticks - samples[i - 1].t_device_ticks,
                  50);  // unwrapped past 2^32
        EXPECT_NEAR(static_cast<double>(samples[i].t_host - samples[i - 1].t_host), 5e6, 1e4);
    }
    EXPECT_GT(samples.back().t_device_ticks, std::int64_t{1} << 32);
    EXPECT_EQ(rig.device.stats().gaps, 0u);
    EXPECT_EQ(rig.device.stats().samples, 400u);
    EXPECT_EQ(rig.device.clock().wraps(), 1);
}

TEST(XsensDevice, HostTimeIsTheSampleInstantPlusTheLinkLatency) {
    Rig rig;
    rig.stream.setLatency(3 * kNsPerMs);
    ASSERT_TRUE(rig.device.configure().isOk());
    const auto samples = rig.collect(200);
    ASSERT_EQ(samples.size(), 200u);
    // The fake's packets are due every 5 ms of virtual time and arrive `latency` later; the
    // mapping keeps the lower envelope, so host times step by exactly 5 ms.
    const TimeNs step = samples[199].t_host - samples[198].t_host;
    EXPECT_NEAR(static_cast<double>(step), 5e6, 1e3);
    EXPECT_LE(samples.back().t_host, rig.clock.now);
}

TEST(XsensDevice, GoToConfigIsResentUntilAcknowledged) {
    FakeXsensConfig fc;
    fc.ignore_first_goto_configs = 3;
    Rig rig(fc);
    Status s = rig.device.configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(std::count(rig.fake.requestsSeen().begin(), rig.fake.requestsSeen().end(), 0x30), 4);
}

TEST(XsensDevice, SilentDeviceTimesOutWithAClearMessage) {
    FakeXsensConfig fc;
    fc.ignore_first_goto_configs = 100;
    Rig rig(fc);
    Status s = rig.device.configure();
    ASSERT_FALSE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_NE(s.message().find("no GoToConfigAck"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("baud"), std::string::npos) << s.message();
}

TEST(XsensDevice, ErrorReplyIsReportedAndTheRequestRetried) {
    FakeXsensFaults faults;
    faults.error_replies[0xC0] = 1;
    faults.error_code = ErrorCode::kInvalidPeriod;
    Rig rig({}, faults);
    Status s = rig.device.configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(rig.device.stats().device_errors, 1u);
    ASSERT_FALSE(rig.device.problems().empty());
    EXPECT_NE(rig.device.problems().back().find("InvalidPeriod"), std::string::npos);
    EXPECT_EQ(rig.collect(10).size(), 10u);
}

TEST(XsensDevice, PersistentErrorFailsConfigureNamingTheStepAndTheCode) {
    FakeXsensFaults faults;
    faults.error_replies[0xC0] = 100;
    faults.error_code = ErrorCode::kInvalidParameter;
    Rig rig({}, faults);
    Status s = rig.device.configure();
    ASSERT_FALSE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::kDeviceError);
    EXPECT_NE(s.message().find("setting the outputs"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("InvalidParameter"), std::string::npos) << s.message();
}

TEST(XsensDevice, DamagedPacketsCostOnlyThemselvesAndAreReportedAsGaps) {
    FakeXsensFaults faults;
    // Packet indices count every packet the fake streamed, including before configure().
    faults.drop_byte_in_packet = {30, 31, 90};
    faults.corrupt_checksum_in_packet = {50};
    faults.error_after_packet = {70};
    faults.error_code = ErrorCode::kBufferOverflow;
    Rig rig({}, faults);
    ASSERT_TRUE(rig.device.configure().isOk());
    const auto samples = rig.collect(150);
    ASSERT_EQ(samples.size(), 150u);
    expectSamplesMatch(samples, intact(rig.fake));
    const auto& st = rig.device.stats();
    EXPECT_EQ(st.gaps, 3u);  // 30-31 together, 50, 90
    EXPECT_EQ(st.lost_packets, 4u);
    EXPECT_GE(st.checksum_failures, 1u);
    EXPECT_GE(st.resyncs, 3u);  // 30 and 31 may fall in one garbage run
    EXPECT_EQ(st.device_errors, 1u);
    bool saw_overflow = false;
    for (const auto& p : rig.device.problems())
        saw_overflow |= p.find("BufferOverflow") != std::string::npos;
    EXPECT_TRUE(saw_overflow);
}

TEST(XsensDevice, ArbitraryChunkingGivesTheSameSamples) {
    for (std::size_t chunk : {std::size_t{1}, std::size_t{3}, std::size_t{17}, std::size_t{64}}) {
        Rig rig;
        rig.stream.setMaxChunk(chunk);
        ASSERT_TRUE(rig.device.configure().isOk()) << chunk;
        const auto samples = rig.collect(50);
        ASSERT_EQ(samples.size(), 50u) << chunk;
        expectSamplesMatch(samples, intact(rig.fake));
        EXPECT_EQ(rig.device.stats().resyncs, 0u);
    }
}

TEST(XsensDevice, DisconnectIsReportedAndConfigureRecovers) {
    Rig rig;
    ASSERT_TRUE(rig.device.configure().isOk());
    ASSERT_EQ(rig.collect(20).size(), 20u);
    rig.stream.disconnectAfter(30);  // mid-packet
    std::vector<ImuSample> out;
    Status s;
    for (int i = 0; i < 10 && s.isOk(); ++i) s = rig.device.poll(out, 10 * kNsPerMs);
    ASSERT_EQ(s.code(), StatusCode::kDisconnected);
    EXPECT_NE(s.message().find("configure()"), std::string::npos);
    rig.stream.close();
    ASSERT_TRUE(rig.device.configure().isOk());
    const std::size_t before = rig.fake.streamed().size();
    const auto samples = rig.collect(20);
    ASSERT_EQ(samples.size(), 20u);
    expectSamplesMatch(samples, intact(rig.fake, before));
}

TEST(XsensDevice, RestartMidStreamIsReportedAndMeasurementResumes) {
    Rig rig;
    ASSERT_TRUE(rig.device.configure().isOk());
    auto samples = rig.collect(50);
    ASSERT_GE(samples.size(), 50u);
    const std::uint32_t epoch_before = rig.fake.epoch();
    rig.fake.powerCycle();
    const auto after = rig.collect(50);
    ASSERT_GE(after.size(), 50u);
    EXPECT_EQ(rig.fake.epoch(), epoch_before + 1);
    EXPECT_EQ(rig.device.stats().restarts, 1u);
    EXPECT_EQ(rig.device.stats().gaps, 0u);  // a restart is not a loss
    std::vector<StreamedPacket> truth;
    for (const auto& p : rig.fake.streamed()) {
        if (p.epoch == rig.fake.epoch()) truth.push_back(p);
    }
    expectSamplesMatch(after, truth);
    EXPECT_EQ(after.front().packet_counter, 0);
    // Host time keeps going forward across the restart.
    EXPECT_GT(after.front().t_host, samples.back().t_host);
    EXPECT_LT(after.front().t_host - samples.back().t_host, 50 * kNsPerMs);
    EXPECT_NE(rig.device.problems().back().find("WakeUp"), std::string::npos);
}

TEST(XsensDevice, ConfigureRightAfterPowerUpAcksTheWakeUp) {
    FakeXsensConfig fc;
    fc.streaming_at_start = false;
    Rig rig(fc);
    rig.fake.powerCycle();
    Status s = rig.device.configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(rig.fake.requestsSeen().front(), 0x30);  // GoToConfig caught it before it measured
    EXPECT_EQ(rig.collect(10).size(), 10u);
}

TEST(XsensDevice, FindsAFactoryDefaultDeviceAndMovesItTo921600) {
    for (int device_baud : {115200, 460800}) {
        FakeXsensConfig fc;
        fc.baudrate = device_baud;
        XsensDeviceConfig dc;
        Rig rig(fc, {}, dc);
        // The host side of the link starts at the configured 921600.
        XsensDeviceConfig with_link = rig.withClock(dc);
        with_link.set_link_baudrate = [&rig](int baud) { return rig.stream.setLinkBaudrate(baud); };
        XsensDevice device(rig.stream, with_link);
        Status s = device.configure();
        ASSERT_TRUE(s.isOk()) << device_baud << ": " << s.message();
        EXPECT_EQ(rig.fake.baudrate(), 921600);
        EXPECT_EQ(rig.stream.linkBaudrate(), 921600);
        EXPECT_EQ(device.linkBaudrate(), 921600);
        const auto& seen = rig.fake.requestsSeen();
        EXPECT_NE(std::find(seen.begin(), seen.end(), 0x18), seen.end());  // SetBaudrate
        EXPECT_NE(std::find(seen.begin(), seen.end(), 0x40), seen.end());  // Reset
        bool noted = false;
        for (const auto& p : device.problems())
            noted |= p.find("found at " + std::to_string(device_baud)) != std::string::npos;
        EXPECT_TRUE(noted);
        std::vector<ImuSample> out;
        for (int i = 0; i < 1000 && out.size() < 20; ++i)
            ASSERT_TRUE(device.poll(out, 10 * kNsPerMs).isOk());
        ASSERT_GE(out.size(), 20u);
        std::vector<StreamedPacket> truth;
        for (const auto& p : rig.fake.streamed()) {
            if (p.epoch == rig.fake.epoch()) truth.push_back(p);
        }
        expectSamplesMatch(out, truth);
        EXPECT_EQ(device.stats().gaps, 0u);
    }
}

TEST(XsensDevice, WrongRateWithoutProbingFailsClearly) {
    FakeXsensConfig fc;
    fc.baudrate = 115200;
    Rig rig(fc);
    Status s = rig.device.configure();
    ASSERT_FALSE(s.isOk());
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_NE(s.message().find("baud"), std::string::npos) << s.message();
}

TEST(XsensDevice, RawTapSeesEveryByteWithItsReceiveTime) {
    Rig rig;
    ASSERT_TRUE(rig.device.configure().isOk());
    (void)rig.collect(30);
    EXPECT_EQ(rig.tap.data.size(), rig.device.stats().bytes);
    EXPECT_TRUE(std::is_sorted(rig.tap.times.begin(), rig.tap.times.end()));
    XbusParser offline;
    offline.feed(rig.tap.data);
    int mtdata2 = 0;
    while (auto f = offline.next()) mtdata2 += f->mid == 0x36 ? 1 : 0;
    EXPECT_GE(mtdata2, 30);
}

TEST(XsensDevice, DeltaOutputsAndFixedPointFormats) {
    for (Precision p : {Precision::kFp1220, Precision::kFp1632, Precision::kFloat64}) {
        XsensDeviceConfig dc;
        dc.delta_q_delta_v = true;
        dc.precision = p;
        Rig rig({}, {}, dc);
        ASSERT_TRUE(rig.device.configure().isOk());
        ASSERT_EQ(rig.fake.outputConfiguration().size(), 7u);
        EXPECT_EQ(rig.fake.outputConfiguration()[2].xdi, withFormat(xdi::kAcceleration, p));
        EXPECT_EQ(rig.fake.outputConfiguration()[4].xdi, withFormat(xdi::kDeltaQ, p));
        const auto samples = rig.collect(20);
        ASSERT_EQ(samples.size(), 20u);
        expectSamplesMatch(samples, intact(rig.fake));
    }
}

}  // namespace
}  // namespace handscan::xsens
