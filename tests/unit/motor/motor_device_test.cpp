// The motor state machine against emulated CiA 406 / CiA 402 nodes on a virtual-time bus.
#include "handscan/motor/motor_device.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "handscan/motor/virtual_can_buses.hpp"

namespace handscan::motor {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Rig {
    explicit Rig(EncoderEmulatorConfig ec = defaultEncoder(), MotorConfig mc = MotorConfig{})
        : enc(ec), bus(0), cfg(mc) {
        bus.addNode(&enc);
    }
    static EncoderEmulatorConfig defaultEncoder() {
        EncoderEmulatorConfig c;
        c.units_per_revolution = 4096;
        c.total_range = 4096;  // single-turn: the counter wraps every revolution
        c.speed_radps = 5 * kTwoPi;
        return c;
    }
    MotorDevice& device() {
        if (!dev) dev = std::make_unique<MotorDevice>(bus, cfg, [this] { return bus.now(); });
        return *dev;
    }
    // Polls until `until` (virtual time) or an error; collects samples.
    Status run(TimeNs until, std::vector<EncoderSample>& out) {
        while (bus.now() < until) {
            auto r = device().poll(5 * kNsPerMs);
            if (!r) return r.status();
            if (*r) out.push_back(**r);
        }
        return Status::ok();
    }
    std::vector<std::string> sentText() const {
        std::vector<std::string> s;
        for (const auto& f : bus.sent()) s.push_back(formatCanFrameText(f.frame));
        return s;
    }

    Cia406EncoderEmulator enc;
    EmulatedCanBus bus;
    MotorConfig cfg;
    std::unique_ptr<MotorDevice> dev;
};

TEST(MotorDevice, BringsTheEncoderUpWithTheCiA406Sequence) {
    Rig rig;
    Status s = rig.device().start();
    ASSERT_TRUE(s) << s.message();
    EXPECT_EQ(rig.device().state(), MotorState::kStreaming);
    EXPECT_EQ(rig.sentText(), (std::vector<std::string>{
                                  "601#4001600000000000",  // read 6001h units/rev
                                  "601#4002600000000000",  // read 6002h total range
                                  "601#2B17100064000000",  // heartbeat 100 ms
                                  "601#2F001802FE000000",  // TPDO1 transmission type FE
                                  "601#2B00620001000000",  // cyclic timer 1 ms
                                  "000#0101",              // NMT start node 1
                              }));
    EXPECT_EQ(rig.device().resolution().units_per_revolution, 4096u);
    EXPECT_EQ(rig.device().resolution().total_range, 4096u);
    EXPECT_EQ(rig.enc.nmtState(), NmtState::kOperational);
}

TEST(MotorDevice, StreamsAContinuousAngleThroughCounterWraps) {
    Rig rig;
    ASSERT_TRUE(rig.device().start());
    std::vector<EncoderSample> samples;
    ASSERT_TRUE(rig.run(rig.bus.now() + kNsPerSec, samples));
    ASSERT_GE(samples.size(), 990u);
    const double count = kTwoPi / 4096;
    // The unwrapped angle equals the emulated shaft angle up to whole turns of the counter
    // (fixed at the first sample) and the one-count quantisation of the encoder.
    const double offset = samples.front().angle_rad - rig.enc.angleAt(samples.front().t_host);
    EXPECT_NEAR(std::remainder(offset, kTwoPi), 0.0, count);
    for (const auto& s : samples) {
        const double err = s.angle_rad - rig.enc.angleAt(s.t_host) - offset;
        ASSERT_LE(std::abs(err), 1.01 * count) << "at " << s.t_host;
    }
    EXPECT_NEAR(samples.back().speed_radps, 5 * kTwoPi, 0.01 * kTwoPi);
    EXPECT_GE(rig.device().stats().wraps, 4u);
    EXPECT_EQ(rig.device().stats().late_positions, 0u);
    EXPECT_GE(rig.device().stats().heartbeats, 9u);
}

TEST(MotorDevice, UnwrapsTheFull32BitPositionCounter) {
    EncoderEmulatorConfig ec = Rig::defaultEncoder();
    ec.total_range = 0;  // 2^32 counts
    ec.initial_angle_rad = (4294967296.0 - 3000.0) * kTwoPi / 4096;
    Rig rig(ec);
    ASSERT_TRUE(rig.device().start());
    std::vector<EncoderSample> samples;
    ASSERT_TRUE(rig.run(rig.bus.now() + 300 * kNsPerMs, samples));
    ASSERT_GT(samples.size(), 200u);
    bool wrapped = false;
    for (std::size_t i = 1; i < samples.size(); ++i) {
        wrapped = wrapped || samples[i].raw_position < samples[i - 1].raw_position;
        ASSERT_GT(samples[i].angle_rad, samples[i - 1].angle_rad);
        ASSERT_LT(samples[i].angle_rad - samples[i - 1].angle_rad, 25 * kTwoPi / 4096);
    }
    EXPECT_TRUE(wrapped);
    EXPECT_EQ(rig.device().stats().wraps, 1u);
}

TEST(MotorDevice, ALostHeartbeatIsAFaultThatStopsTheScan) {
    Rig rig;
    ASSERT_TRUE(rig.device().start());
    std::vector<EncoderSample> samples;
    ASSERT_TRUE(rig.run(rig.bus.now() + 200 * kNsPerMs, samples));
    const TimeNs lost_at = rig.bus.now();
    rig.enc.setHeartbeatLost(true);
    Status s = rig.run(lost_at + kNsPerSec, samples);
    ASSERT_FALSE(s);
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_NE(s.message().find("silent: no heartbeat (701)"), std::string::npos) << s.message();
    EXPECT_EQ(rig.device().state(), MotorState::kFault);
    // Detected within the timeout plus one heartbeat period of the last heartbeat.
    EXPECT_LE(rig.bus.now() - lost_at, 350 * kNsPerMs + 100 * kNsPerMs + 5 * kNsPerMs);
    EXPECT_GE(rig.bus.now() - lost_at, 250 * kNsPerMs);
    // Positions up to the fault were all handed out; later polls repeat the fault.
    EXPECT_GE(samples.size(), static_cast<std::size_t>((rig.bus.now() - lost_at) / kNsPerMs) + 150);
    auto again = rig.device().poll(kNsPerMs);
    ASSERT_FALSE(again);
    EXPECT_EQ(again.status().message(), s.message());
}

TEST(MotorDevice, ASilentEncoderStopsTheDrive) {
    MotorConfig mc;
    mc.drive = DriveConfig{};
    Rig rig(Rig::defaultEncoder(), mc);
    Cia402DriveEmulator drive({2});
    rig.bus.addNode(&drive);
    ASSERT_TRUE(rig.device().start());
    ASSERT_TRUE(rig.device().setMotorSpeed(kTwoPi));
    EXPECT_EQ(drive.targetVelocity(), 60);  // rpm
    std::vector<EncoderSample> samples;
    ASSERT_TRUE(rig.run(rig.bus.now() + 50 * kNsPerMs, samples));
    rig.enc.setSilent(true);
    Status s = rig.run(rig.bus.now() + kNsPerSec, samples);
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("sends no position"), std::string::npos) << s.message();
    // The quick stop went out; let the drive take it.
    (void)rig.bus.receive(5 * kNsPerMs);
    EXPECT_EQ(drive.state(), Cia402State::kQuickStopActive);
}

TEST(MotorDevice, EnablesACiA402DriveInProfileVelocityModeBySdoAndByRpdo) {
    for (bool rpdo : {false, true}) {
        MotorConfig mc;
        mc.drive = DriveConfig{};
        mc.drive->use_rpdo = rpdo;
        Rig rig(Rig::defaultEncoder(), mc);
        Cia402DriveEmulator drive({2});
        drive.setFault();  // a drive left in fault needs a fault reset first
        rig.bus.addNode(&drive);
        Status st = rig.device().start();
        ASSERT_TRUE(st) << st.message();
        EXPECT_EQ(drive.state(), Cia402State::kOperationEnabled);
        EXPECT_EQ(drive.mode(), kModeProfileVelocity);
        EXPECT_EQ(rig.device().driveState(), Cia402State::kOperationEnabled);
        ASSERT_TRUE(rig.device().setMotorSpeed(-4 * kTwoPi));
        (void)rig.bus.receive(0);  // deliver the RPDO
        EXPECT_EQ(drive.targetVelocity(), -240);
        ASSERT_TRUE(rig.device().stop());
        EXPECT_EQ(drive.targetVelocity(), 0);
        EXPECT_EQ(drive.state(), Cia402State::kReadyToSwitchOn);
        EXPECT_EQ(rig.device().state(), MotorState::kStopped);
    }
}

TEST(MotorDevice, ResetsAnEncoderThatBootedBeforeWeListened) {
    Rig rig;
    // Consume the boot-up before the driver starts (it was powered first).
    ASSERT_TRUE(rig.bus.receive(kNsPerSec));
    Status s = rig.device().start();
    ASSERT_TRUE(s) << s.message();
    ASSERT_FALSE(rig.sentText().empty());
    EXPECT_EQ(rig.sentText().front(), "000#8101");
}

TEST(MotorDevice, NoEncoderOnTheBusFailsWithAClearMessage) {
    Rig rig;
    rig.enc.setSilent(true);
    Status s = rig.device().start();
    ASSERT_FALSE(s);
    EXPECT_EQ(s.code(), StatusCode::kTimeout);
    EXPECT_NE(s.message().find("encoder node 1 boot-up (701#00)"), std::string::npos)
        << s.message();
    EXPECT_NE(s.message().find("node id"), std::string::npos) << s.message();
}

TEST(MotorDevice, ReportsAnSdoAbortInPlainWords) {
    MotorConfig mc;
    mc.tpdo1_transmission_type = 0xF5;  // reserved value: the encoder aborts
    Rig rig(Rig::defaultEncoder(), mc);
    Status s = rig.device().start();
    ASSERT_FALSE(s);
    EXPECT_EQ(s.code(), StatusCode::kDeviceError);
    EXPECT_NE(s.message().find("SDO write node 1 object 1800h:02 aborted by the device: 0x06090030 "
                               "(invalid value for parameter)"),
              std::string::npos)
        << s.message();
}

TEST(MotorDevice, ARebootOrAnEmergencyDuringTheScanIsAFault) {
    {
        Rig rig;
        ASSERT_TRUE(rig.device().start());
        std::vector<EncoderSample> samples;
        rig.enc.reboot(rig.bus.now() + 20 * kNsPerMs);
        Status s = rig.run(rig.bus.now() + kNsPerSec, samples);
        ASSERT_FALSE(s);
        EXPECT_NE(s.message().find("rebooted"), std::string::npos) << s.message();
    }
    {
        Rig rig;
        ASSERT_TRUE(rig.device().start());
        std::vector<EncoderSample> samples;
        rig.enc.sendEmergency(rig.bus.now() + 10 * kNsPerMs, 0x5530, 0x81);
        Status s = rig.run(rig.bus.now() + kNsPerSec, samples);
        ASSERT_FALSE(s);
        EXPECT_NE(s.message().find("error code 0x5530, error register 0x81"), std::string::npos)
            << s.message();
        EXPECT_EQ(rig.device().stats().emergencies, 1u);
    }
}

TEST(MotorDevice, ATransportFailureIsReported) {
    Rig rig;
    ASSERT_TRUE(rig.device().start());
    rig.bus.setDown(true);
    // Positions already received are handed out first, then the failure.
    auto r = rig.device().poll(kNsPerMs);
    for (int i = 0; i < 100 && r; ++i) {
        ASSERT_TRUE(r->has_value());
        r = rig.device().poll(kNsPerMs);
    }
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::kDisconnected);
    EXPECT_NE(r.status().message().find("emulated can0"), std::string::npos);
}

TEST(MotorDevice, HandsRawCandumpLinesToTheRecordingTap) {
    struct Tap : RawTap {
        void onRaw(TimeNs, std::span<const std::uint8_t> b) override {
            lines.emplace_back(b.begin(), b.end());
        }
        std::vector<std::string> lines;
    } tap;
    Rig rig;
    MotorDevice dev(
        rig.bus, rig.cfg, [&] { return rig.bus.now(); }, &tap);
    ASSERT_TRUE(dev.start());
    ASSERT_GE(tap.lines.size(), 10u);
    auto first = parseCandumpLogLine(tap.lines.front());
    ASSERT_TRUE(first) << tap.lines.front();
    EXPECT_EQ(formatCanFrameText(first->frame), "701#00");
    EXPECT_NE(std::find(tap.lines.begin(), tap.lines.end(),
                        "(0000000000.020000) can0 601#4001600000000000"),
              tap.lines.end());
}

}  // namespace
}  // namespace handscan::motor
