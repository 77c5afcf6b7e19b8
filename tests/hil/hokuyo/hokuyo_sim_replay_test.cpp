// A simulated recording's /hokuyo/raw (the digital twin's HokuyoStream: handshake replies, ME
// frames cut into TCP-sized reads with realistic host receive times, a drifting sensor clock, one
// corrupted block) replayed chunk by chunk, at its recorded host times, through the real driver.
// The driver must give back exactly the scans the simulator sent (all but the corrupted one) and
// put each scan's step 0 at the simulator's true host time within the 1 ms timestamp resolution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <deque>

#include "handscan/hokuyo/hokuyo_device.hpp"
#include "handscan/sim/hokuyo_stream.hpp"

namespace handscan::hokuyo {
namespace {

// Plays recorded chunks back as a ByteStream; the host clock is the chunk's receive time.
class RecordedChunks : public transport::ByteStream {
public:
    explicit RecordedChunks(std::vector<sim::StreamMessage> chunks)
        : chunks_(chunks.begin(), chunks.end()) {}
    Status open() override {
        open_ = true;
        return Status::ok();
    }
    void close() override { open_ = false; }
    bool isOpen() const override { return open_; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override {
        if (chunks_.empty()) {
            now += timeout;
            return std::size_t{0};
        }
        auto& c = chunks_.front();
        now = std::max(now, c.t_host_rx);
        const std::size_t n = std::min(buffer.size(), c.bytes.size() - used_);
        std::copy_n(c.bytes.begin() + static_cast<long>(used_), n, buffer.begin());
        used_ += n;
        if (used_ == c.bytes.size()) {
            chunks_.pop_front();
            used_ = 0;
        }
        return n;
    }
    // The recording already holds the sensor's replies, in order.
    Status writeAll(std::span<const std::uint8_t>, TimeNs) override { return Status::ok(); }
    std::string describe() const override { return "recording /hokuyo/raw"; }
    bool done() const { return chunks_.empty(); }

    TimeNs now = 0;

private:
    std::deque<sim::StreamMessage> chunks_;
    std::size_t used_ = 0;
    bool open_ = false;
};

TEST(HokuyoSimReplay, DriverReturnsTheSimulatorsScansAtTheirTrueTimes) {
    const sim::LaserConfig laser;
    const sim::HokuyoStreamConfig cfg;
    const TimeNs host_start = 1000 * kNsPerSec;
    sim::HokuyoStream hs(cfg, laser, host_start, sim::Rng(3, "hokuyo"));
    std::vector<sim::StreamMessage> chunks;
    hs.handshake(0.0, chunks);
    const int n = 2400;  // 60 s
    const int corrupted = 1234;
    std::vector<sim::LaserScanTruth> truth;
    for (int k = 0; k < n; ++k) {
        sim::LaserScanTruth s;
        s.t_first_step = 0.05 + k * laser.scan_period_s;
        for (int i = 0; i < laser.steps; ++i) {
            s.ranges_mm.push_back(
                static_cast<std::uint32_t>(i % 97 == 0 ? 1 : 300 + (i * 13 + k * 7) % 29000));
            s.intensities.push_back(static_cast<std::uint32_t>((i + k) % 4000));
        }
        hs.scan(s, k == corrupted, chunks);
        truth.push_back(std::move(s));
    }
    RecordedChunks link(std::move(chunks));
    link.now = host_start - kNsPerSec;
    HokuyoDeviceConfig dc;
    // The simulator's constant part of the delay (unobservable from timestamps alone; on a real
    // rig it comes from calibration): processing after the last step plus the fixed link latency.
    dc.timing.extra_latency_ns = fromSeconds(cfg.processing_s + cfg.clock.latency_s);
    HokuyoDevice dev(
        link, dc, nullptr, [&] { return link.now; }, [&](TimeNs dt) { link.now += dt; });
    std::vector<LaserScan> scans;
    while (!link.done()) (void)dev.poll(scans);
    ASSERT_EQ(scans.size(), static_cast<std::size_t>(n - 1));
    const HokuyoDeviceStats st = dev.stats();
    EXPECT_EQ(st.parser.checksum_failures, 1u);
    EXPECT_EQ(st.missed_scans, 1u);
    double sum = 0.0, worst = 0.0;
    int counted = 0;
    for (int k = 0, j = 0; k < n; ++k) {
        if (k == corrupted) continue;
        const LaserScan& got = scans[static_cast<std::size_t>(j++)];
        ASSERT_EQ(got.t_device_ms, hs.timestampMs(truth[k].t_first_step));
        for (std::size_t i = 0; i < got.size(); ++i) {
            const std::uint32_t v = truth[k].ranges_mm[i];
            if (v < laser.dmin_mm) {
                ASSERT_EQ(got.error_codes[i], v);
            } else {
                ASSERT_EQ(std::lround(got.ranges_m[i] * 1000.0f), v);
            }
            ASSERT_EQ(got.intensities[i], truth[k].intensities[i]);
        }
        if (k < 400) continue;  // 10 s to learn the clock
        const double err =
            static_cast<double>(got.t_host - sim::hostNs(host_start, truth[k].t_first_step));
        sum += std::abs(err);
        worst = std::max(worst, std::abs(err));
        ++counted;
    }
    std::printf(
        "sim replay: drift %.1f ppm (simulated %.1f), step-0 time error mean %.3f ms, max %.3f "
        "ms\n",
        dev.clock().driftPpm(), -cfg.clock.drift_ppm, sum / counted * 1e-6, worst * 1e-6);
    EXPECT_NEAR(dev.clock().driftPpm(), -cfg.clock.drift_ppm, 10.0);
    EXPECT_LT(sum / counted, 0.8e6);
    EXPECT_LT(worst, 1.6e6);
}

}  // namespace
}  // namespace handscan::hokuyo
