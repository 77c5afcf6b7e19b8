// Hardware-in-the-loop without hardware: the motor driver runs against the emulated encoder
// while every frame on the wire is recorded as candump -l lines (what /motor/can holds); the
// recording is then replayed through the same driver via the candump-log transport and must
// yield exactly the same samples and the same faults; corrupted lines lose only themselves.
#include <gtest/gtest.h>

#include <numbers>
#include <sstream>
#include <vector>

#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/virtual_can_buses.hpp"

namespace handscan::motor {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

struct Outcome {
    std::vector<EncoderSample> samples;
    Status end;  // ok, or the fault that ended the run
    TimeNs end_time = 0;
};

bool same(const EncoderSample& a, const EncoderSample& b) {
    return a.t_host == b.t_host && a.raw_position == b.raw_position && a.angle_rad == b.angle_rad &&
           a.speed_radps == b.speed_radps;
}

template <typename Bus>
Outcome drive(Bus& bus, const MotorConfig& cfg, TimeNs duration,
              const std::function<void(TimeNs)>& at_each = {}) {
    Outcome o;
    MotorDevice dev(bus, cfg, [&] { return bus.now(); });
    o.end = dev.start();
    if (!o.end) return o;
    const TimeNs until = bus.now() + duration;
    while (bus.now() < until) {
        if (at_each) at_each(bus.now());
        auto r = dev.poll(5 * kNsPerMs);
        if (!r) {
            o.end = r.status();
            break;
        }
        if (*r) o.samples.push_back(**r);
    }
    o.end_time = bus.now();
    return o;
}

struct Recording {
    std::string log;
    Outcome live;
};

Recording recordLive(TimeNs duration, bool lose_heartbeat_at_200ms) {
    EncoderEmulatorConfig ec;
    ec.units_per_revolution = 8192;
    ec.total_range = 8192;
    ec.speed_radps = 3 * kTwoPi;
    ec.power_on = 1'700'000'000 * kNsPerSec;  // like a candump wall-clock log
    Cia406EncoderEmulator enc(ec);
    EmulatedCanBus bus(ec.power_on);
    bus.addNode(&enc);
    std::ostringstream log;
    bus.setRecorder(&log);
    MotorConfig cfg;
    cfg.cyclic_timer_ms = 2;
    TimeNs started = 0;
    Recording rec;
    rec.live = drive(bus, cfg, duration, [&](TimeNs now) {
        if (started == 0) started = now;
        if (lose_heartbeat_at_200ms && now - started >= 200 * kNsPerMs) enc.setHeartbeatLost(true);
    });
    rec.log = log.str();
    return rec;
}

Outcome replay(const std::string& log, std::ostringstream& sent) {
    CandumpLogBus bus(std::make_unique<std::istringstream>(log), &sent, "recording");
    MotorConfig cfg;
    cfg.cyclic_timer_ms = 2;
    return drive(bus, cfg, 10 * kNsPerSec);
}

TEST(MotorReplay, ARecordingReplaysToExactlyTheSameSamples) {
    const Recording rec = recordLive(500 * kNsPerMs, false);
    ASSERT_TRUE(rec.live.end) << rec.live.end.message();
    ASSERT_GT(rec.live.samples.size(), 240u);

    std::ostringstream sent;
    const Outcome again = replay(rec.log, sent);
    // The replay ends when the log does: the transport reports the end of the log.
    EXPECT_EQ(again.end.code(), StatusCode::kDisconnected) << again.end.message();
    ASSERT_EQ(again.samples.size(), rec.live.samples.size());
    for (std::size_t i = 0; i < again.samples.size(); ++i) {
        ASSERT_TRUE(same(again.samples[i], rec.live.samples[i])) << "sample " << i;
    }
    // The driver sent the same requests as in the recording, at the same times.
    std::vector<std::string> recorded_requests;
    std::istringstream in(rec.log);
    for (std::string line; std::getline(in, line);) {
        auto r = parseCandumpLogLine(line);
        ASSERT_TRUE(r);
        const auto fn = classifyCobId(r->frame).function;
        if (fn == CanOpenFunction::kSdoRequest || fn == CanOpenFunction::kNmt)
            recorded_requests.push_back(line);
    }
    std::vector<std::string> replay_requests;
    std::istringstream out(sent.str());
    for (std::string line; std::getline(out, line);) replay_requests.push_back(line);
    EXPECT_EQ(replay_requests, recorded_requests);
}

TEST(MotorReplay, AHeartbeatLossInTheRecordingIsTheSameFaultOnReplay) {
    const Recording rec = recordLive(kNsPerSec, true);
    ASSERT_FALSE(rec.live.end);
    EXPECT_NE(rec.live.end.message().find("silent"), std::string::npos) << rec.live.end.message();
    std::ostringstream sent;
    const Outcome again = replay(rec.log, sent);
    ASSERT_FALSE(again.end);
    const auto cause = [](const Status& st) {
        return st.message().substr(0, st.message().find(" on "));
    };
    EXPECT_EQ(cause(again.end), cause(rec.live.end));
    EXPECT_EQ(again.end.code(), rec.live.end.code());
    EXPECT_EQ(again.end_time, rec.live.end_time);
    EXPECT_EQ(again.samples.size(), rec.live.samples.size());
}

TEST(MotorReplay, ACorruptedLineLosesOnlyItsOwnSample) {
    const Recording rec = recordLive(300 * kNsPerMs, false);
    ASSERT_TRUE(rec.live.end);
    // Damage the 100th TPDO line and add a garbage line after it.
    std::istringstream in(rec.log);
    std::string damaged;
    int tpdos = 0;
    TimeNs lost_time = 0;
    for (std::string line; std::getline(in, line);) {
        auto r = parseCandumpLogLine(line);
        if (r && classifyCobId(r->frame).function == CanOpenFunction::kTpdo && ++tpdos == 100) {
            lost_time = r->timeNs();
            line.replace(line.size() - 8, 3, "ZZZ");
            line += "\n\x01\x02garbage (not a frame)";
        }
        damaged += line + "\n";
    }
    std::ostringstream sent;
    CandumpLogBus log_bus(std::make_unique<std::istringstream>(damaged), &sent, "damaged");
    MotorConfig cfg;
    cfg.cyclic_timer_ms = 2;
    const Outcome again = drive(log_bus, cfg, 10 * kNsPerSec);
    EXPECT_EQ(log_bus.badLines(), 2u);
    EXPECT_NE(log_bus.lastError().find("damaged:"), std::string::npos) << log_bus.lastError();
    ASSERT_EQ(again.samples.size() + 1, rec.live.samples.size());
    std::size_t j = 0;
    for (const auto& s : rec.live.samples) {
        if (s.t_host == lost_time) continue;
        ASSERT_EQ(s.raw_position, again.samples[j].raw_position);
        ASSERT_EQ(s.t_host, again.samples[j].t_host);
        ++j;
    }
}

}  // namespace
}  // namespace handscan::motor
