#include "handscan/core/clock_mapper.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace handscan {
namespace {

// A simulated device clock: tau = d0 + t (1 + drift), reported as an N-bit integer tick count,
// received by the host after a random transport delay.
struct SimulatedDevice {
    double d0_ticks;
    double drift;
    double tick_s;
    int bits;
    std::uint64_t rawAt(double t) const {
        const double tau = d0_ticks + t * (1.0 + drift) / tick_s;
        return static_cast<std::uint64_t>(std::floor(tau)) & ((std::uint64_t{1} << bits) - 1);
    }
    // Host time of the instant the (unwrapped) counter reads `ticks`.
    double hostOf(double unwrapped_ticks) const {
        return (unwrapped_ticks - d0_ticks) * tick_s / (1.0 + drift);
    }
};

TEST(ClockMapper, Hokuyo24BitMillisecondsWrapTwiceWithDriftAndJitter) {
    // 24-bit ms counter wraps every 4.66 h; 10 h covers two wraps. 200 ppm drift, 5 ms jitter.
    const SimulatedDevice dev{1000.0, 200e-6, 1e-3, 24};  // wraps at 4.66 h and 9.32 h
    ClockMapperConfig cfg;
    cfg.counter_bits = 24;
    cfg.tick_ns = 1e6;
    ClockMapper mapper(cfg);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(0.0, 5e-3);
    const TimeNs host0 = 1'000 * kNsPerSec;
    double max_err_s = 0.0;
    std::int64_t unwrapped_base = 0;  // for the ground truth only
    std::uint64_t prev_raw = dev.rawAt(0.0);
    for (double t = 0.0; t < 10.0 * 3600.0; t += 0.1) {
        const std::uint64_t raw = dev.rawAt(t);
        if (raw < prev_raw) unwrapped_base += std::int64_t{1} << 24;
        prev_raw = raw;
        const double rx = t + jitter(rng);
        mapper.observe(raw, host0 + static_cast<TimeNs>(rx * 1e9));
        if (t > 120.0) {
            const double truth =
                dev.hostOf(static_cast<double>(unwrapped_base + static_cast<std::int64_t>(raw)));
            const double mapped = toSeconds(*mapper.toHost(raw) - host0);
            max_err_s = std::max(max_err_s, std::abs(mapped - truth));
        }
    }
    EXPECT_EQ(mapper.wraps(), 2);
    EXPECT_EQ(mapper.resets(), 0);
    EXPECT_LT(max_err_s, 0.5e-3) << "max mapping error " << max_err_s * 1e3 << " ms";
    EXPECT_NEAR(mapper.driftPpm(), -200.0, 5.0);  // host = (1 - 200ppm) * device
}

TEST(ClockMapper, XsensSampleTimeFineTenKilohertz) {
    const SimulatedDevice dev{123456.0, -50e-6, 1e-4, 32};
    ClockMapperConfig cfg;
    cfg.counter_bits = 32;
    cfg.tick_ns = 1e5;
    ClockMapper mapper(cfg);
    std::mt19937 rng(3);
    std::exponential_distribution<double> delay(1.0 / 1e-3);  // USB latency, long tail
    double max_err = 0;
    for (double t = 0.0; t < 600.0; t += 0.005) {
        const std::uint64_t raw = dev.rawAt(t);
        mapper.observe(raw, static_cast<TimeNs>((t + 2e-4 + delay(rng)) * 1e9));
        if (t > 30.0) {
            const double truth =
                dev.hostOf(static_cast<double>(raw)) + 2e-4;  // constant latency is unobservable
            max_err = std::max(max_err, std::abs(toSeconds(*mapper.toHost(raw)) - truth));
        }
    }
    EXPECT_LT(max_err, 0.2e-3);
}

TEST(ClockMapper, OutliersBelowTheEnvelopeAreRejected) {
    ClockMapperConfig cfg;
    cfg.counter_bits = 24;
    cfg.tick_ns = 1e6;
    ClockMapper mapper(cfg);
    for (int i = 0; i < 2000; ++i) {
        const TimeNs host = static_cast<TimeNs>(i) * 25 * kNsPerMs + 2 * kNsPerMs;
        TimeNs observed = host;
        if (i % 100 == 50) observed -= 400 * kNsPerMs;  // a host timestamp that cannot be true
        mapper.observe(static_cast<std::uint64_t>(i) * 25, observed);
    }
    EXPECT_EQ(mapper.outliers(), 20);  // i = 50, 150, ..., 1950
    EXPECT_EQ(mapper.resets(), 0);
    EXPECT_NEAR(toSeconds(*mapper.toHost(1000 * 25)), 25.0 + 2e-3, 0.2e-3);
}

TEST(ClockMapper, DeviceRestartResetsTheFit) {
    ClockMapperConfig cfg;
    cfg.counter_bits = 24;
    cfg.tick_ns = 1e6;
    ClockMapper mapper(cfg);
    // 60 s of scans, then the sensor reboots: its counter starts again from 0.
    for (int i = 0; i < 2400; ++i)
        mapper.observe(5'000'000 + i * 25, static_cast<TimeNs>(i) * 25 * kNsPerMs);
    const TimeNs reboot = 70 * kNsPerSec;
    int resets_seen = 0;
    for (int i = 0; i < 400; ++i) {
        if (mapper.observe(static_cast<std::uint64_t>(i) * 25,
                           reboot + static_cast<TimeNs>(i) * 25 * kNsPerMs) ==
            ClockMapper::Event::kReset) {
            ++resets_seen;
        }
    }
    EXPECT_EQ(resets_seen, 1);
    EXPECT_EQ(mapper.resets(), 1);
    EXPECT_NEAR(toSeconds(*mapper.toHost(300 * 25)), toSeconds(reboot) + 300 * 0.025, 1e-4);
}

TEST(ClockMapper, UnwrapAcceptsSmallStepsBackwards) {
    ClockMapperConfig cfg;
    cfg.counter_bits = 24;
    cfg.tick_ns = 1e6;
    ClockMapper mapper(cfg);
    const std::uint64_t top = (1u << 24) - 10;
    mapper.observe(top, 0);
    mapper.observe(5, 15 * kNsPerMs);  // wrapped forward
    EXPECT_EQ(mapper.unwrap(5), static_cast<std::int64_t>(top) + 15);
    EXPECT_EQ(mapper.unwrap(top - 2),
              static_cast<std::int64_t>(top) - 2);  // per-step times before the latest scan
    EXPECT_EQ(mapper.wraps(), 1);
}

}  // namespace
}  // namespace handscan
