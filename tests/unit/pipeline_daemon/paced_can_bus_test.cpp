// PacedCanBus: the emulated CiA 406 encoder delivered at wall-clock pace on the host clock, so
// the live motor driver runs on it exactly as on SocketCAN.
#include "handscan/motor/paced_can_bus.hpp"

#include <gtest/gtest.h>

#include <numbers>
#include <sstream>

#include "handscan/motor/candump_format.hpp"
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

// A candump -l log carries wall-clock epoch seconds: paced, its first frame comes at once and the
// next ones at their spacing, stamped on the host clock (it used to wait out the epoch seconds).
TEST(PacedCanBus, CandumpLogPlaysFromItsFirstFrame) {
    const std::string log =
        "(1700000000.000000) can0 701#00\n"
        "(1700000000.050000) can0 181#CE050000\n"
        "(1700000000.100000) can0 181#20060000\n";
    CandumpLogBus bus(std::make_unique<std::istringstream>(log), nullptr, "epoch");
    EXPECT_EQ(bus.now(), 1700000000LL * kNsPerSec);  // the log's clock starts at its first frame
    PacedCanBus paced(bus, [&] { return bus.now(); });
    const TimeNs start = monotonicNow();
    std::vector<TimeNs> got;
    for (int i = 0; i < 3; ++i) {
        auto f = paced.receive(kNsPerSec);
        ASSERT_TRUE(f.isOk()) << f.status().message();
        got.push_back(f->t_host);
    }
    EXPECT_LT(got[0] - start, 20 * kNsPerMs);
    EXPECT_NEAR(toSeconds(got[2] - got[0]), 0.100, 0.002);
    EXPECT_GE(monotonicNow() - start, 95 * kNsPerMs);  // paced, not as fast as read
}

// A log already on the host clock (`handscan hil`): each frame at its own time, late ones at once.
TEST(PacedCanBus, HostClockLogDeliversEachFrameAtItsTime) {
    const TimeNs t0 = monotonicNow();
    const auto line = [](TimeNs t, const char* frame) {
        CandumpRecord r = *parseCandumpAnyLine(std::string("(0.000000) can0 ") + frame);
        r.setTimeNs(t);
        return formatCandumpLogLine(r) + "\n";
    };
    const std::string log =
        line(t0 - 500 * kNsPerMs, "701#00") + line(t0 + 80 * kNsPerMs, "181#CE050000");
    CandumpLogBus bus(std::make_unique<std::istringstream>(log), nullptr, "host");
    PacedCanBus paced(bus, [&] { return bus.now(); });
    paced.setOffset(0);
    auto late = paced.receive(kNsPerSec);
    ASSERT_TRUE(late.isOk());
    EXPECT_LT(monotonicNow() - t0, 20 * kNsPerMs);  // already due: at once
    EXPECT_EQ(late->t_host, (t0 - 500 * kNsPerMs) / 1000 * 1000);
    auto due = paced.receive(kNsPerSec);
    ASSERT_TRUE(due.isOk());
    EXPECT_GE(monotonicNow(), t0 + 79 * kNsPerMs);
    EXPECT_EQ(due->t_host, (t0 + 80 * kNsPerMs) / 1000 * 1000);

    // Opened again (the daemon retries after the end of the log): what was sent is gone.
    CandumpLogBus again(std::make_unique<std::istringstream>(log), nullptr, "host");
    again.skipBefore(monotonicNow());
    EXPECT_FALSE(again.receive(kNsPerSec).isOk());
}

}  // namespace
}  // namespace handscan::motor
