// HokuyoDevice over an in-memory link on a simulated host clock: parameters read from PP, the
// clock mapping of a drifting sensor clock, back-off timing, raw tap.
#include "handscan/hokuyo/hokuyo_device.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>
#include <numbers>
#include <random>

#include "handscan/hokuyo_fake/fake_hokuyo_sensor.hpp"

namespace handscan::hokuyo {
namespace {

// A FakeHokuyoSensor behind a ByteStream whose bytes arrive at scripted host times.
class SimulatedLink : public transport::ByteStream {
public:
    SimulatedLink(std::vector<SourceScanFrame> frames, std::vector<TimeNs> arrival,
                  FakeHokuyoIdentity identity = {})
        : sensor_(std::move(frames), std::move(identity)), arrival_(std::move(arrival)) {}

    Status open() override {
        ++open_calls;
        open_times.push_back(now);
        if (fail_opens > 0) {
            --fail_opens;
            return Status(StatusCode::kDisconnected, "sim: connection refused");
        }
        open_ = true;
        return Status::ok();
    }
    void close() override {
        open_ = false;
        sensor_.onDisconnect();
        out_.clear();
    }
    bool isOpen() const override { return open_; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override {
        if (!open_) return Status(StatusCode::kDisconnected, "sim: closed");
        if (out_.empty()) {
            std::uint32_t ts = 0;
            if (auto f = sensor_.nextStreamFrame(&ts)) {
                const std::size_t i = sensor_.lastFrameIndex();
                if (drop_at && i == *drop_at) {
                    drop_at.reset();
                    drop_time = now;
                    open_ = false;
                    sensor_.onDisconnect();
                    return Status(StatusCode::kDisconnected, "sim: peer closed");
                }
                now = std::max(now, arrival_[i]);
                out_.append(*f);
            } else {
                now += timeout;
                return std::size_t{0};
            }
        }
        const std::size_t n = std::min(buffer.size(), out_.size());
        std::copy_n(out_.begin(), n, buffer.begin());
        out_.erase(0, n);
        return n;
    }
    Status writeAll(std::span<const std::uint8_t> data, TimeNs) override {
        sensor_.onHostBytes(
            std::string_view(reinterpret_cast<const char*>(data.data()), data.size()));
        out_ += sensor_.takeReplies();
        now += 200 * kNsPerUs;  // a round trip
        return Status::ok();
    }
    std::string describe() const override { return "sim"; }

    TimeNs now = 1'000 * kNsPerSec;
    int open_calls = 0;
    int fail_opens = 0;
    std::vector<TimeNs> open_times;
    std::optional<std::size_t> drop_at;
    TimeNs drop_time = 0;

private:
    FakeHokuyoSensor sensor_;
    std::vector<TimeNs> arrival_;
    std::string out_;
    bool open_ = false;
};

struct SimScans {
    std::vector<SourceScanFrame> frames;
    std::vector<TimeNs> arrival;     // host time the frame's last byte arrives
    std::vector<TimeNs> true_first;  // host time of the first value
};

// A UTM-30LX-EW whose clock runs `drift_ppm` fast: the scan timestamp is latched when the last
// step is measured, the frame then takes its transmit time plus a random latency >= 0.
SimScans simulate(int n, double drift_ppm, TimeNs t0, std::uint32_t clock_start_ms,
                  const ScanRequest& req, double step_ns) {
    SimScans s;
    std::mt19937 rng(7);
    std::exponential_distribution<double> jitter(1.0 / 0.4e6);  // mean 0.4 ms
    const double span = (req.valuesPerScan() - 1) * step_ns * std::max(req.cluster, 1);
    for (int k = 0; k < n; ++k) {
        const TimeNs first = t0 + static_cast<TimeNs>(k) * 25 * kNsPerMs;
        const double last = static_cast<double>(first) + span;
        const double sensor_ms = static_cast<double>(clock_start_ms) +
                                 (last - static_cast<double>(t0)) * 1e-6 * (1.0 + drift_ppm * 1e-6);
        ScanPayload p;
        p.timestamp_ms = static_cast<std::uint32_t>(std::floor(sensor_ms)) & 0xFFFFFFu;
        for (int i = 0; i < req.valuesPerScan(); ++i) {
            p.ranges.push_back(static_cast<std::uint32_t>(500 + (i * 37 + k) % 20000));
            p.intensities.push_back(static_cast<std::uint32_t>(i));
        }
        std::string bytes = encodeScanFrame(req, p);
        const double tx = static_cast<double>(bytes.size()) * 8e9 / 100e6;
        s.arrival.push_back(static_cast<TimeNs>(last + tx + jitter(rng)));
        s.true_first.push_back(first);
        s.frames.push_back({std::move(bytes), req, std::move(p)});
    }
    return s;
}

const ScanRequest kFullMe{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};

TEST(HokuyoDevice, TracksADriftingSensorClockAcrossTheWrap) {
    const double step_ns = 60e9 / 2400 / 1440;
    // 120 s of scans; the 24-bit ms counter wraps 20 s in.
    const std::uint32_t start_ms = (1u << 24) - 20'000;
    SimScans sim = simulate(4800, 100.0, 2'000 * kNsPerSec, start_ms, kFullMe, step_ns);
    SimulatedLink link(sim.frames, sim.arrival);
    link.now = 2'000 * kNsPerSec - kNsPerSec;
    HokuyoDevice dev(
        link, {}, nullptr, [&] { return link.now; }, [&](TimeNs dt) { link.now += dt; });
    std::vector<LaserScan> scans;
    for (int i = 0; i < 20000 && scans.size() < sim.frames.size(); ++i) {
        (void)dev.poll(scans);
    }
    ASSERT_EQ(scans.size(), sim.frames.size());
    EXPECT_EQ(dev.clock().wraps(), 1);
    EXPECT_EQ(dev.clock().resets(), 0);
    EXPECT_NEAR(dev.clock().driftPpm(), -100.0, 15.0);  // host = (1 + drift) * device
    // After a 10 s warm-up, every scan's first-step time is within the 1 ms timestamp resolution.
    double max_err = 0.0;
    double sum_err = 0.0;
    int counted = 0;
    for (std::size_t k = 400; k < scans.size(); ++k) {
        const double err = std::abs(static_cast<double>(scans[k].t_host - sim.true_first[k]));
        max_err = std::max(max_err, err);
        sum_err += err;
        ++counted;
    }
    std::printf(
        "clock mapping: drift %.1f ppm (true -100), first-step error mean %.3f ms, max %.3f ms\n",
        dev.clock().driftPpm(), sum_err / counted * 1e-6, max_err * 1e-6);
    EXPECT_LT(max_err, 1.3e6) << "ns";
    EXPECT_LT(sum_err / counted, 0.7e6) << "ns";
    EXPECT_EQ(scans[10].step_period_ns, static_cast<TimeNs>(std::llround(step_ns)));
    EXPECT_EQ(dev.stats().missed_scans, 0u);
}

TEST(HokuyoDevice, UsesTheSensorsOwnParametersFromPp) {
    FakeHokuyoIdentity other;
    other.pp = {{"MODL", "UST-10LX"}, {"DMIN", "20"},   {"DMAX", "30000"}, {"ARES", "1440"},
                {"AMIN", "0"},        {"AMAX", "1080"}, {"AFRT", "540"},   {"SCAN", "2400"}};
    other.pp[4].second = "100";   // AMIN
    other.pp[5].second = "900";   // AMAX
    other.pp[7].second = "1800";  // SCAN rpm
    ScanRequest req = kFullMe;
    req.start_step = 100;
    req.end_step = 900;
    const double step_ns = 60e9 / 1800 / 1440;
    SimScans sim = simulate(5, 0.0, 10 * kNsPerSec, 1000, req, step_ns);
    sim.frames[2].scan.ranges[3] = 7;      // an error code (< DMIN)
    sim.frames[2].scan.ranges[4] = 30001;  // above DMAX
    sim.frames[2].bytes = encodeScanFrame(req, sim.frames[2].scan);
    SimulatedLink link(sim.frames, sim.arrival, other);
    HokuyoDevice dev(
        link, {}, nullptr, [&] { return link.now; }, [&](TimeNs dt) { link.now += dt; });
    std::vector<LaserScan> scans;
    for (int i = 0; i < 200 && scans.size() < 5; ++i) (void)dev.poll(scans);
    ASSERT_EQ(scans.size(), 5u);
    ASSERT_TRUE(dev.parameters());
    EXPECT_EQ(dev.parameters()->model, "UST-10LX");
    EXPECT_EQ(dev.request().start_step, 100);
    EXPECT_EQ(dev.request().end_step, 900);
    const LaserScan& s = scans[2];
    EXPECT_EQ(s.size(), 801u);
    EXPECT_EQ(s.first_step, 100);
    EXPECT_NEAR(s.angle_min_rad, (100 - 540) * 2 * std::numbers::pi / 1440, 1e-12);
    EXPECT_NEAR(s.angle_increment_rad, 2 * std::numbers::pi / 1440, 1e-15);
    EXPECT_EQ(s.step_period_ns, static_cast<TimeNs>(std::llround(step_ns)));
    EXPECT_TRUE(std::isnan(s.ranges_m[3]));
    EXPECT_EQ(s.error_codes[3], 7);
    EXPECT_TRUE(std::isnan(s.ranges_m[4]));
    EXPECT_EQ(s.error_codes[4], 30001);
    EXPECT_FLOAT_EQ(s.ranges_m[5], sim.frames[2].scan.ranges[5] * 1e-3f);
    EXPECT_EQ(s.error_codes[5], 0);
    EXPECT_EQ(s.intensities[6], 6);
    EXPECT_EQ(dev.identity().serial, "H0000000");
    EXPECT_EQ(dev.identity().status, "Sensor works well.");
}

TEST(HokuyoDevice, BacksOffExponentiallyAndResumesAfterADrop) {
    SimScans sim = simulate(30, 0.0, 10 * kNsPerSec, 1000, kFullMe, 60e9 / 2400 / 1440);
    SimulatedLink link(sim.frames, sim.arrival);
    link.fail_opens = 4;
    link.drop_at = 10;
    HokuyoDeviceConfig cfg;
    cfg.backoff_initial_ns = 100 * kNsPerMs;
    cfg.backoff_max_ns = 500 * kNsPerMs;
    HokuyoDevice dev(
        link, cfg, nullptr, [&] { return link.now; }, [&](TimeNs dt) { link.now += dt; });
    std::vector<LaserScan> scans;
    for (int i = 0; i < 2000 && scans.size() < 29; ++i) (void)dev.poll(scans);
    ASSERT_EQ(scans.size(), 29u);  // all but the frame the link dropped in
    ASSERT_GE(link.open_times.size(), 6u);
    // Failed opens at t, t+100, t+300, t+700, t+1200 ms (doubling, capped at 500 ms).
    const std::vector<TimeNs> gaps_ms = {100, 200, 400, 500};
    for (std::size_t i = 0; i < gaps_ms.size(); ++i) {
        const TimeNs gap = link.open_times[i + 1] - link.open_times[i];
        EXPECT_NEAR(static_cast<double>(gap), static_cast<double>(gaps_ms[i] * kNsPerMs), 2e6) << i;
    }
    // After streaming, a drop reconnects after the initial back-off again.
    EXPECT_NEAR(static_cast<double>(link.open_times[5] - link.drop_time), 100e6, 2e6);
    const HokuyoDeviceStats st = dev.stats();
    EXPECT_EQ(st.connects, 2u);
    EXPECT_EQ(st.connect_failures, 4u);
    EXPECT_EQ(st.disconnects, 1u);
    EXPECT_EQ(st.missed_scans, 1u);
    EXPECT_EQ(scans[9].t_device_ms, sim.frames[9].scan.timestamp_ms);
    EXPECT_EQ(scans[10].t_device_ms, sim.frames[11].scan.timestamp_ms);
}

class CountingTap : public RawTap {
public:
    void onRaw(TimeNs t, std::span<const std::uint8_t> bytes) override {
        EXPECT_GE(t, last);
        last = t;
        data.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
    }
    TimeNs last = 0;
    std::string data;
};

TEST(HokuyoDevice, RawTapSeesEveryByteTheSensorSent) {
    SimScans sim = simulate(6, 0.0, 10 * kNsPerSec, 1000, kFullMe, 60e9 / 2400 / 1440);
    SimulatedLink link(sim.frames, sim.arrival);
    CountingTap tap;
    HokuyoDevice dev(
        link, {}, &tap, [&] { return link.now; }, [&](TimeNs dt) { link.now += dt; });
    std::vector<LaserScan> scans;
    for (int i = 0; i < 200 && scans.size() < 6; ++i) (void)dev.poll(scans);
    ASSERT_EQ(scans.size(), 6u);
    // The tap holds the handshake replies and every frame, byte for byte.
    std::string frames;
    for (const auto& f : sim.frames) frames += f.bytes;
    ASSERT_GT(tap.data.size(), frames.size());
    EXPECT_EQ(tap.data.substr(tap.data.size() - frames.size()), frames);
    EXPECT_EQ(tap.data.rfind("SCIP2.0\n0Ee\n\nVV\n00P\n", 0), 0u);
    // Re-parsing the tapped bytes yields the same scans (what `handscan decode` does).
    auto again = splitScanFrames(tap.data);
    ASSERT_EQ(again.size(), 6u);
    EXPECT_EQ(again[5].scan.ranges, sim.frames[5].scan.ranges);
}

}  // namespace
}  // namespace handscan::hokuyo
