// Every simulated byte stream decodes back through the drivers' codecs to exactly the values the
// simulator meant to send; chunking, rates and device clocks are the configured ones.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "handscan/hokuyo/scip_stream_parser.hpp"
#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/sim/can_stream.hpp"
#include "handscan/sim/hokuyo_stream.hpp"
#include "handscan/sim/xsens_stream.hpp"
#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_parser.hpp"
#include "handscan/xsens/xdi.hpp"

namespace handscan::sim {
namespace {

constexpr TimeNs kHost0 = 1000 * kNsPerSec;

LaserScanTruth syntheticScan(double t0, Rng& rng) {
    LaserScanTruth s;
    s.t_first_step = t0;
    for (int k = 0; k < 1081; ++k) {
        s.ranges_mm.push_back(rng.chance(0.05) ? 2u
                                               : static_cast<std::uint32_t>(23 + rng.below(59977)));
        s.intensities.push_back(static_cast<std::uint32_t>(rng.below(16000)));
    }
    return s;
}

TEST(HokuyoStreamTest, TcpChunksDecodeToTheScansSent) {
    HokuyoStreamConfig cfg;
    LaserConfig laser;
    HokuyoStream stream(cfg, laser, kHost0, Rng(1, "tcp"));
    std::vector<StreamMessage> msgs;
    stream.handshake(0.02, msgs);
    Rng rng(2, "scans");
    std::vector<LaserScanTruth> sent;
    for (int i = 0; i < 80; ++i) {
        sent.push_back(syntheticScan(0.1 + 0.025 * i, rng));
        stream.scan(sent.back(), false, msgs);
    }
    hokuyo::ScipStreamParser parser;
    std::vector<hokuyo::ScipEvent> events;
    std::size_t mid_frame_chunks = 0;
    TimeNs prev = 0;
    for (const auto& m : msgs) {
        EXPECT_EQ(m.channel, SimChannel::kHokuyo);
        EXPECT_GT(m.t_host_rx, prev);
        prev = m.t_host_rx;
        EXPECT_LE(m.bytes.size(), 8u * 1448u);
        parser.feed(m.bytes, events);
        mid_frame_chunks += !parser.idle();
    }
    EXPECT_GT(mid_frame_chunks,
              sent.size() / 4);  // frames are split across reads, as a socket delivers them
    std::vector<std::string> commands;
    std::size_t scans = 0;
    for (const auto& e : events) {
        ASSERT_TRUE(std::holds_alternative<hokuyo::ScipFrame>(e))
            << std::get<hokuyo::ScipFault>(e).message;
        const auto& f = std::get<hokuyo::ScipFrame>(e);
        EXPECT_TRUE(f.ok()) << f.echo << " " << f.status;
        if (!f.scan) {
            commands.push_back(f.command);
            continue;
        }
        ASSERT_LT(scans, sent.size());
        const LaserScanTruth& truth = sent[scans++];
        EXPECT_EQ(f.scan->ranges, truth.ranges_mm);
        EXPECT_EQ(f.scan->intensities, truth.intensities);
        EXPECT_EQ(f.scan->timestamp_ms, stream.timestampMs(truth.t_first_step));
    }
    EXPECT_EQ(scans, sent.size());
    EXPECT_EQ(commands, (std::vector<std::string>{"SCIP2.0", "VV", "PP", "II", "BM", "ME"}));
    EXPECT_EQ(parser.stats().checksum_failures, 0u);
}

TEST(HokuyoStreamTest, TimestampsRunOnTheSensorClockAndWrapAt24Bits) {
    HokuyoStreamConfig cfg;
    cfg.clock.offset_s = 16777.0;  // 2^24 ms = 16777.216 s: wraps 0.216 s into the recording
    cfg.clock.drift_ppm = 100.0;
    HokuyoStream stream(cfg, LaserConfig{}, kHost0, Rng(1, "tcp"));
    EXPECT_EQ(stream.timestampMs(0.0), 16777000u);
    EXPECT_EQ(stream.timestampMs(0.3),
              static_cast<std::uint32_t>(std::floor((16777.0 + 0.3 * 1.0001) * 1000)) - (1u << 24));
    // 1000 s of host time are 1000.1 s of sensor time.
    const std::uint32_t a = stream.timestampMs(10.0), b = stream.timestampMs(1010.0);
    EXPECT_EQ((b - a) & 0xFFFFFFu, 1000100u);
}

TEST(HokuyoStreamTest, CorruptedBlockFailsItsChecksumAndOnlyThatScanIsLost) {
    HokuyoStream stream(HokuyoStreamConfig{}, LaserConfig{}, kHost0, Rng(1, "tcp"));
    std::vector<StreamMessage> msgs;
    Rng rng(3, "scans");
    for (int i = 0; i < 5; ++i) stream.scan(syntheticScan(0.025 * i, rng), i == 2, msgs);
    hokuyo::ScipStreamParser parser;
    std::vector<hokuyo::ScipEvent> events;
    for (const auto& m : msgs) parser.feed(m.bytes, events);
    int scans = 0, faults = 0;
    for (const auto& e : events) {
        if (std::holds_alternative<hokuyo::ScipFault>(e))
            ++faults;
        else if (std::get<hokuyo::ScipFrame>(e).scan)
            ++scans;
    }
    EXPECT_EQ(scans, 4);
    EXPECT_GE(faults, 1);
    EXPECT_GE(parser.stats().checksum_failures, 1u);
}

TEST(XsensStreamTest, SerialChunksDecodeToTheSamplesSentOnTheImuClock) {
    XsensStreamConfig cfg;
    cfg.delta_q_v = true;
    XsensStream stream(cfg, kHost0, Rng(1, "serial"));
    std::vector<StreamMessage> msgs;
    stream.handshake(0.01, msgs);
    Rng rng(4, "imu");
    std::vector<ImuMeasurement> sent;
    const int n = 200 * 30;
    for (int k = 0; k < n; ++k) {
        ImuMeasurement m;
        m.t = stream.sampleTime(k);
        m.accel = Eigen::Vector3d(rng.gauss(), rng.gauss(), 9.8 + rng.gauss());
        m.gyro = Eigen::Vector3d(rng.gauss(), rng.gauss(), rng.gauss());
        sent.push_back(m);
        stream.sample(k, m, false, msgs);
    }
    xsens::XbusParser parser;
    std::vector<std::uint8_t> mids;
    std::vector<std::pair<std::uint32_t, TimeNs>> stamps;  // SampleTimeFine, host receive time
    std::size_t k = 0;
    for (const auto& m : msgs) {
        parser.feed(m.bytes);
        while (auto f = parser.next()) {
            mids.push_back(f->mid);
            if (f->mid != 0x36) continue;
            auto p = xsens::decodeMtData2(f->payload);
            ASSERT_TRUE(p.isOk()) << p.status().message();
            ASSERT_LT(k, sent.size());
            EXPECT_EQ(*p->integer(xsens::xdi::kPacketCounter), k & 0xFFFF);
            EXPECT_EQ(*p->integer(xsens::xdi::kSampleTimeFine),
                      stream.sampleTimeFine(static_cast<std::int64_t>(k)));
            // float32 on the wire: equal to the float-rounded values.
            const Eigen::Vector3d a = *p->vector3(xsens::xdi::kAcceleration),
                                  w = *p->vector3(xsens::xdi::kRateOfTurn);
            for (int i = 0; i < 3; ++i) {
                EXPECT_EQ(a[i], static_cast<double>(static_cast<float>(sent[k].accel[i])));
                EXPECT_EQ(w[i], static_cast<double>(static_cast<float>(sent[k].gyro[i])));
            }
            EXPECT_NEAR((*p->vector3(xsens::xdi::kDeltaV) - sent[k].accel * 0.005).norm(), 0.0,
                        1e-6);
            EXPECT_TRUE(p->vector4(xsens::xdi::kDeltaQ).has_value());
            EXPECT_EQ(*p->integer(xsens::xdi::kStatusWord), 3u);
            stamps.emplace_back(
                static_cast<std::uint32_t>(*p->integer(xsens::xdi::kSampleTimeFine)), m.t_host_rx);
            ++k;
        }
    }
    EXPECT_EQ(k, sent.size());
    EXPECT_EQ(parser.stats().checksum_failures, 0u);
    ASSERT_GE(mids.size(), 5u);
    EXPECT_EQ(std::vector<std::uint8_t>(mids.begin(), mids.begin() + 5),
              (std::vector<std::uint8_t>{0x31, 0x01, 0x1D, 0xC1, 0x11}));
    // Rate and drift from the stream alone: SampleTimeFine advances 50 ticks per sample, and its
    // lower envelope against host receive times has slope 1 + drift.
    for (std::size_t i = 1; i < stamps.size(); ++i)
        EXPECT_EQ(stamps[i].first - stamps[i - 1].first, 50u);
    auto lowest = [&](std::size_t from,
                      std::size_t to) {  // smallest (host - device) over a stretch
        double best = 1e300;
        for (std::size_t i = from; i < to; ++i)
            best = std::min(best, toSeconds(stamps[i].second) - stamps[i].first * 1e-4);
        return best;
    };
    const double dev_span = (stamps[stamps.size() - 500].first - stamps[500].first) * 1e-4;
    const double host_minus_dev_change =
        lowest(stamps.size() - 1000, stamps.size()) - lowest(0, 1000);
    const double drift_ppm = -host_minus_dev_change / dev_span * 1e6;
    EXPECT_NEAR(drift_ppm, cfg.clock.drift_ppm, 3.0);
}

TEST(XsensStreamTest, DroppedByteCostsOneFrame) {
    XsensStream stream(XsensStreamConfig{}, kHost0, Rng(1, "serial"));
    std::vector<StreamMessage> msgs;
    for (int k = 0; k < 50; ++k) {
        ImuMeasurement m;
        m.accel = Eigen::Vector3d(0, 0, 9.81);
        stream.sample(k, m, k == 20, msgs);
    }
    xsens::XbusParser parser;
    int frames = 0;
    for (const auto& m : msgs) {
        parser.feed(m.bytes);
        while (parser.next()) ++frames;
    }
    EXPECT_EQ(frames, 49);
}

TEST(CanStreamTest, CandumpLinesDecodeToTheEncoderPositionsAtTheConfiguredPeriod) {
    ShaftModel shaft(ShaftConfig{});
    CanStreamConfig cfg;
    cfg.tpdo_period_s = 0.002;
    CanStream can(cfg, shaft, kHost0, Rng(1, "can"));
    std::vector<StreamMessage> msgs;
    for (double t = 0; t < 20.0; t += 0.25) can.generate(t, t + 0.25, msgs);
    std::vector<std::uint32_t> positions;
    std::vector<TimeNs> tpdo_rx;
    int heartbeats_op = 0, bootups = 0, sdo_acks = 0;
    for (std::size_t i = 0; i < msgs.size(); ++i) {
        const std::string line(msgs[i].bytes.begin(), msgs[i].bytes.end());
        auto rec = motor::parseCandumpLogLine(line);
        ASSERT_TRUE(rec.isOk()) << line << ": " << rec.status().message();
        EXPECT_EQ(rec->interface, "can0");
        EXPECT_EQ(rec->timeNs() / 1000,
                  msgs[i].t_host_rx / 1000);  // the line carries the receive time
        const auto info = motor::classifyCobId(rec->frame);
        if (info.function == motor::CanOpenFunction::kTpdo) {
            auto pos = motor::decodeEncoderPositionTpdo(rec->frame);
            ASSERT_TRUE(pos.isOk());
            positions.push_back(*pos);
            tpdo_rx.push_back(msgs[i].t_host_rx);
        } else if (info.function == motor::CanOpenFunction::kHeartbeat) {
            auto hb = motor::decodeHeartbeat(rec->frame);
            ASSERT_TRUE(hb.isOk());
            if (hb->state == motor::NmtState::kBootUp) {
                ++bootups;
                EXPECT_TRUE(positions.empty()) << "boot-up after the first TPDO";
            }
            heartbeats_op += hb->state == motor::NmtState::kOperational;
        } else if (info.function == motor::CanOpenFunction::kSdoResponse) {
            ++sdo_acks;
        }
    }
    EXPECT_EQ(bootups, 2);
    EXPECT_EQ(sdo_acks, 3);
    EXPECT_NEAR(heartbeats_op, 2 * 20 / 0.1, 4);
    ASSERT_EQ(positions.size(), can.readings().size());
    for (std::size_t i = 0; i < positions.size(); ++i) {
        EXPECT_EQ(positions[i], can.readings()[i].position);
        EXPECT_LT(positions[i], cfg.counts_per_rev);
    }
    // Period on the host clock: the encoder's 2 ms on a crystal 42 ppm slow.
    const double period =
        toSeconds(tpdo_rx.back() - tpdo_rx.front()) / static_cast<double>(tpdo_rx.size() - 1);
    EXPECT_NEAR(period, 0.002 / (1 + cfg.clock.drift_ppm * 1e-6), 2e-8);
    // Positions advance ~1 rev/s: 16384 counts/s, 32.8 counts per TPDO, wrapping once a turn.
    int wraps = 0;
    for (std::size_t i = 1; i < positions.size(); ++i) wraps += positions[i] < positions[i - 1];
    EXPECT_NEAR(wraps, 20, 1);
}

}  // namespace
}  // namespace handscan::sim
