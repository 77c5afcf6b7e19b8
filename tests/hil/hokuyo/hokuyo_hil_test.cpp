// Hardware-in-the-loop: a recorded /hokuyo/raw-style stream (here simulated with the codec: no
// public raw UTM-30LX capture exists) served by the fake Hokuyo over real loopback TCP, read by the
// real TcpStream and the real driver. Clean, the driver yields exactly the recorded scans; with a
// socket closed mid-scan, a corrupted block and a dropped byte it reports each fault, reconnects
// or resynchronises, and loses only the damaged scans.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "handscan/hokuyo/hokuyo_device.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_server.hpp"
#include "handscan/transport/tcp_stream.hpp"

namespace handscan::hokuyo {
namespace {

const ScanRequest kMe{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};

// A recording's raw stream: the handshake replies, the ME acknowledgement and `n` scans 25 ms
// apart.
std::string recordedStream(int n, std::uint32_t start_ms = 16'000'000u) {
    const FakeHokuyoIdentity id;
    std::string raw = encodeReply("SCIP2.0", "0E") + encodeKeyValueReply("VV", "00", id.vv) +
                      encodeKeyValueReply("PP", "00", id.pp) + encodeReply("BM", "00") +
                      encodeScanAck(kMe);
    for (int k = 0; k < n; ++k) {
        ScanPayload p;
        p.timestamp_ms = (start_ms + static_cast<std::uint32_t>(k) * 25u) & 0xFFFFFFu;
        for (int i = 0; i < 1081; ++i) {
            const auto v = static_cast<std::uint32_t>((i * 7919 + k * 104729) % 40000);
            p.ranges.push_back(v);  // includes error codes below DMIN = 23
            p.intensities.push_back(static_cast<std::uint32_t>((i + k) % 5000));
        }
        raw += encodeScanFrame(kMe, p);
    }
    return raw;
}

void expectSameScan(const LaserScan& got, const SourceScanFrame& want) {
    ASSERT_EQ(got.t_device_ms, want.scan.timestamp_ms);
    ASSERT_EQ(got.size(), want.scan.ranges.size());
    for (std::size_t i = 0; i < got.size(); ++i) {
        const std::uint32_t v = want.scan.ranges[i];
        if (v < 23 || v > 60000) {
            ASSERT_TRUE(std::isnan(got.ranges_m[i])) << i;
            ASSERT_EQ(got.error_codes[i], v) << i;
        } else {
            ASSERT_EQ(std::lround(got.ranges_m[i] * 1000.0f), v) << i;
        }
        ASSERT_EQ(got.intensities[i], want.scan.intensities[i]) << i;
    }
}

struct StreamRun {
    std::vector<LaserScan> scans;
    std::vector<std::string> faults;
};

StreamRun stream(FakeHokuyoServer& server, HokuyoDevice& dev, std::size_t want, TimeNs limit) {
    StreamRun run;
    const TimeNs deadline = monotonicNow() + limit;
    while (run.scans.size() < want && monotonicNow() < deadline) {
        Status s = dev.poll(run.scans);
        if (!s) run.faults.push_back(s.message());
        if (server.sourceExhausted() && dev.state() == HokuyoDevice::State::kStreaming &&
            run.scans.size() >= want) {
            break;
        }
    }
    return run;
}

HokuyoDeviceConfig fastConfig() {
    HokuyoDeviceConfig cfg;
    cfg.backoff_initial_ns = 50 * kNsPerMs;
    cfg.read_slice_ns = 20 * kNsPerMs;
    return cfg;
}

TEST(HokuyoHil, CleanStreamYieldsExactlyTheRecordedScans) {
    const auto source = splitScanFrames(recordedStream(200));
    ASSERT_EQ(source.size(), 200u);
    FakeHokuyoServer server(source);
    ASSERT_TRUE(server.start());
    transport::TcpStream tcp("127.0.0.1", server.port());
    HokuyoDevice dev(tcp, fastConfig());
    StreamRun run = stream(server, dev, 200, 20 * kNsPerSec);
    ASSERT_EQ(run.scans.size(), 200u) << (run.faults.empty() ? "" : run.faults[0]);
    for (std::size_t k = 0; k < 200; ++k) expectSameScan(run.scans[k], source[k]);
    EXPECT_TRUE(run.faults.empty());
    ASSERT_TRUE(dev.stop());
    server.stop();
    const auto log = server.commandLog();
    const std::vector<std::string> want = {"SCIP2.0",         "VV", "PP", "II", "BM",
                                           "ME0000108001000", "QT"};
    EXPECT_EQ(log, want);
    const HokuyoDeviceStats st = dev.stats();
    EXPECT_EQ(st.connects, 1u);
    EXPECT_EQ(st.faults, 0u);
    EXPECT_EQ(st.missed_scans, 0u);
    EXPECT_EQ(st.parser.checksum_failures, 0u);
}

TEST(HokuyoHil, FaultsLoseOnlyTheDamagedScans) {
    const auto source = splitScanFrames(recordedStream(200));
    const std::size_t first_block =
        source[0].bytes.find('\n', source[0].bytes.find('\n', 16) + 1) + 1;
    FakeServerOptions opt;
    opt.faults = {{FakeLinkFault::Kind::kCloseMidFrame, 50, 3000},
                  {FakeLinkFault::Kind::kCorruptByte, 100, first_block + 66 * 30 + 17},
                  {FakeLinkFault::Kind::kDropByte, 150, first_block + 66 * 80 + 5}};
    FakeHokuyoServer server(source, opt);
    ASSERT_TRUE(server.start());
    transport::TcpStream tcp("127.0.0.1", server.port());
    HokuyoDevice dev(tcp, fastConfig());
    StreamRun run = stream(server, dev, 197, 20 * kNsPerSec);
    ASSERT_EQ(run.scans.size(), 197u);
    const std::set<std::size_t> damaged = {50, 100, 150};
    std::size_t k = 0;
    for (std::size_t i = 0; i < source.size(); ++i) {
        if (damaged.count(i)) continue;
        expectSameScan(run.scans[k++], source[i]);
    }
    (void)dev.stop();
    server.stop();
    const HokuyoDeviceStats st = dev.stats();
    EXPECT_EQ(server.connections(), 2u);
    EXPECT_EQ(st.connects, 2u);
    EXPECT_EQ(st.disconnects, 1u);
    EXPECT_EQ(st.missed_scans, 3u);
    // The corrupted block, and the block that lost a byte (its last data character now stands
    // where the sum was); each costs one resync.
    EXPECT_EQ(st.parser.checksum_failures, 2u);
    EXPECT_EQ(st.parser.resyncs, 2u);
    EXPECT_GE(st.faults, 3u);
    ASSERT_GE(run.faults.size(), 3u);
    bool saw_close = false, saw_sum = false;
    for (const auto& f : run.faults) {
        saw_close |= f.find("127.0.0.1:" + std::to_string(server.port())) != std::string::npos &&
                     f.find("closed") != std::string::npos;
        saw_sum |= f.find("sum") != std::string::npos;
    }
    EXPECT_TRUE(saw_close) << run.faults[0];
    EXPECT_TRUE(saw_sum);
}

TEST(HokuyoHil, RealPaceStreamKeepsTheRecordingsSpacing) {
    const auto source = splitScanFrames(recordedStream(24, (1u << 24) - 300));  // wraps mid-way
    FakeServerOptions opt;
    opt.real_pace = true;
    FakeHokuyoServer server(source, opt);
    ASSERT_TRUE(server.start());
    transport::TcpStream tcp("127.0.0.1", server.port());
    HokuyoDevice dev(tcp, fastConfig());
    const TimeNs t0 = monotonicNow();
    StreamRun run = stream(server, dev, 24, 10 * kNsPerSec);
    const TimeNs elapsed = monotonicNow() - t0;
    ASSERT_EQ(run.scans.size(), 24u);
    EXPECT_GE(elapsed, 23 * 25 * kNsPerMs - 5 * kNsPerMs);  // 23 gaps of 25 ms
    // Host times of consecutive scans are 25 ms apart (within scheduling jitter).
    const double span_ms = toSeconds(run.scans.back().t_host - run.scans.front().t_host) * 1e3;
    EXPECT_NEAR(span_ms, 23 * 25.0, 10.0);
    EXPECT_EQ(dev.clock().wraps(), 1);
    EXPECT_EQ(dev.clock().resets(), 0);
    // Step times run forward through each scan and across scans (25 ms scans, 18.75 ms of steps).
    for (std::size_t k = 1; k < run.scans.size(); ++k) {
        EXPECT_GT(run.scans[k].t_host, run.scans[k - 1].stepTime(run.scans[k - 1].size() - 1));
    }
    server.stop();
}

TEST(HokuyoHil, TcpErrorsNameHostAndPort) {
    transport::TcpListener l;
    ASSERT_TRUE(l.listen());
    const int port = l.port();
    l.close();  // nothing listens there now
    transport::TcpStream tcp("127.0.0.1", port, 500 * kNsPerMs);
    Status s = tcp.open();
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("127.0.0.1:" + std::to_string(port)), std::string::npos)
        << s.message();
    transport::TcpStream bad("no-such-host.invalid", 10940, 500 * kNsPerMs);
    Status b = bad.open();
    ASSERT_FALSE(b);
    EXPECT_NE(b.message().find("no-such-host.invalid:10940"), std::string::npos) << b.message();
    transport::TcpStream port0("127.0.0.1", 0);
    EXPECT_EQ(port0.open().code(), StatusCode::kInvalidArgument);
}

TEST(HokuyoHil, BacksOffWhileNoSensorListens) {
    // Nothing listens: every attempt fails fast with a clear error and the driver backs off.
    const auto source = splitScanFrames(recordedStream(10));
    FakeHokuyoServer server(source);
    ASSERT_TRUE(server.start());
    const int port = server.port();
    server.stop();
    transport::TcpStream tcp("127.0.0.1", port, 200 * kNsPerMs);
    HokuyoDevice dev(tcp, fastConfig());
    std::vector<LaserScan> scans;
    for (int i = 0; i < 8; ++i) (void)dev.poll(scans);
    EXPECT_GE(dev.stats().connect_failures, 1u);
    EXPECT_EQ(dev.state(), HokuyoDevice::State::kDisconnected);
}

}  // namespace
}  // namespace handscan::hokuyo
