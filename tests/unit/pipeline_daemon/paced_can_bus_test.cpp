// PacedCanBus: the emulated CiA 406 encoder delivered at wall-clock pace on the host clock, so
// the live motor driver runs on it exactly as on SocketCAN.
#include "handscan/motor/paced_can_bus.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/virtual_can_buses.hpp"

namespace handscan::motor {
namespace {

TEST(PacedCanBus, EmulatedEncoderStreamsInRealTimeOnTheHostClock) {
    EmulatedCanBus bus;
    EncoderEmulatorConfig ec;
    ec.units_per_revolution = 16384;
    ec.total_range = 16384;
    ec.speed_radps = 2.0 * std::numbers::pi;
    Cia406EncoderEmulator encoder(ec);
    bus.addNode(&encoder);
    PacedCanBus paced(bus, [&] { return bus.now(); });

    MotorConfig mc;
    mc.unwrap.units_per_revolution = 16384;
    mc.unwrap.total_range = 16384;
    mc.cyclic_timer_ms = 5;
    MotorDevice device(paced, mc, [&] { return paced.now(); });
    const TimeNs wall_start = monotonicNow();
    ASSERT_TRUE(device.start().isOk());
    std::vector<EncoderSample> samples;
    while (monotonicNow() - wall_start < 300 * kNsPerMs) {
        auto r = device.poll(20 * kNsPerMs);
        ASSERT_TRUE(r.isOk()) << r.status().message();
        if (*r) samples.push_back(**r);
    }
    const TimeNs wall = monotonicNow() - wall_start;
    ASSERT_GT(samples.size(), 30u);
    // About one TPDO per 5 ms of wall time: paced, neither bunched nor starved.
    EXPECT_NEAR(static_cast<double>(samples.size()), toSeconds(wall) / 0.005, 15.0);
    for (std::size_t i = 1; i < samples.size(); ++i) {
        ASSERT_GT(samples[i].t_host, samples[i - 1].t_host);
        EXPECT_NEAR(toSeconds(samples[i].t_host - samples[i - 1].t_host), 0.005, 0.001);
    }
    // Stamped on the host clock: never in the future, never older than the run.
    EXPECT_LE(samples.back().t_host, monotonicNow());
    EXPECT_GE(samples.front().t_host, wall_start);
    // The shaft turns at 1 rev/s.
    const double rate = (samples.back().angle_rad - samples.front().angle_rad) /
                        toSeconds(samples.back().t_host - samples.front().t_host);
    EXPECT_NEAR(rate, 2.0 * std::numbers::pi, 0.05);
}

}  // namespace
}  // namespace handscan::motor
