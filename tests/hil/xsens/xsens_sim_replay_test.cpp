// Simulator output replayed through the real XsensDevice: the digital twin's MTi-20 byte stream
// (handshake replies, then one MTData2 frame per IMU sample, split into read() chunks as a tty
// delivers them, with receive times) must give back exactly the IMU samples the simulator put
// in, in every number format, minus only the frames whose bytes were dropped on the wire; host
// times must land on the simulator's host clock.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "handscan/sim/xsens_stream.hpp"
#include "handscan/xsens/xsens_device.hpp"
#include "handscan/xsens_fake/recorded_byte_stream.hpp"

namespace handscan::xsens {
namespace {

class XsensSimReplay : public ::testing::TestWithParam<int> {};

TEST_P(XsensSimReplay, SamplesAreExactlyWhatTheSimulatorSent) {
    const int precision = GetParam();
    sim::XsensStreamConfig xc;
    xc.precision = precision;
    const TimeNs host_start = 1000 * kNsPerSec;
    sim::XsensStream stream(xc, host_start, sim::Rng(7, "xsens"));
    std::vector<sim::StreamMessage> msgs;
    stream.handshake(0.0, msgs);
    const std::set<std::int64_t> dropped{100, 101, 555};
    std::vector<std::pair<std::int64_t, sim::ImuMeasurement>> sent;
    for (std::int64_t k = 0; k < 1000; ++k) {
        sim::ImuMeasurement m;
        m.t = stream.sampleTime(k);
        m.accel = {0.4 * std::sin(3.0 * m.t), -0.3 * std::cos(2.0 * m.t),
                   9.81 + 0.1 * std::sin(m.t)};
        m.gyro = {2.0 * std::sin(1.3 * m.t), -6.4 * std::cos(0.7 * m.t),
                  0.01 * m.t};  // up to 370 deg/s
        stream.sample(k, m, dropped.count(k) != 0, msgs);
        if (dropped.count(k) == 0) sent.emplace_back(k, m);
    }
    std::vector<RecordedChunk> chunks;
    for (auto& m : msgs) chunks.push_back({m.t_host_rx, std::move(m.bytes)});
    VirtualClock clock;
    clock.now = chunks.front().t_host_rx - kNsPerMs;
    RecordedByteStream replay(std::move(chunks), clock);
    XsensDeviceConfig cfg;
    cfg.clock = [&clock] { return clock.now; };
    cfg.precision = static_cast<Precision>(precision);
    XsensDevice device(replay, cfg);
    Status s = device.configure();
    ASSERT_TRUE(s.isOk()) << s.message();
    EXPECT_EQ(device.deviceId(), xc.device_id);
    std::vector<ImuSample> samples;
    while (!replay.finished()) ASSERT_TRUE(device.poll(samples, 10 * kNsPerMs).isOk());
    ASSERT_EQ(samples.size(), sent.size());
    // Resolution of the wire format.
    const double tol = precision == 0 ? 1e-6 : precision == 1 ? 1.0 / (1 << 20) : 1e-9;
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const auto& [k, m] = sent[i];
        SCOPED_TRACE("sample " + std::to_string(k));
        ASSERT_EQ(static_cast<std::uint32_t>(samples[i].t_device_ticks), stream.sampleTimeFine(k));
        ASSERT_LT((samples[i].accel_mps2_imu - m.accel).cwiseAbs().maxCoeff(), tol * 16);
        ASSERT_LT((samples[i].gyro_radps_imu - m.gyro).cwiseAbs().maxCoeff(), tol * 8);
        // The host clock of the simulation: sample instant + the link's minimum latency.
        const double host_truth = static_cast<double>(host_start) + m.t * 1e9;
        if (i > 50) {  // once the time mapping has a few points
            ASSERT_NEAR(static_cast<double>(samples[i].t_host), host_truth, 3e6);
        }
    }
    EXPECT_EQ(device.stats().gaps, 2u);  // 100-101 and 555
    EXPECT_EQ(device.stats().lost_packets, 3u);
    EXPECT_GE(device.stats().resyncs, 2u);
}

INSTANTIATE_TEST_SUITE_P(Formats, XsensSimReplay, ::testing::Values(0, 1, 2, 3));

}  // namespace
}  // namespace handscan::xsens
