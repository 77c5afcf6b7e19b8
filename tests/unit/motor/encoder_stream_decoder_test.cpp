// The encoder's time stamps are decided once (EncoderSampleClock) for the live driver and for
// recordings: the recorded-stream decoder removes the bus's receive jitter with the cyclic-timer
// fit, and MotorDevice on a live bus gives exactly the samples the decoder gives for the bytes
// that bus delivered.
#include "handscan/motor/encoder_stream_decoder.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/virtual_can_buses.hpp"

namespace handscan::motor {
namespace {

std::span<const std::uint8_t> bytesOf(const std::string& s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

TEST(EncoderStreamDecoder, CyclicTimerRemovesReceiveJitter) {
    EncoderStreamConfig cfg;
    cfg.node_id = 1;
    cfg.unwrapper.units_per_revolution = 16384;
    cfg.unwrapper.total_range = 16384;
    cfg.tpdo_period_ns = 5 * kNsPerMs;
    EncoderStreamDecoder dec(cfg);
    // With the minimum latency calibrated (motor.tpdo_latency_ms) the times are the sampling's.
    EncoderStreamConfig calibrated = cfg;
    calibrated.tpdo_latency_ns = 200 * kNsPerUs;
    EncoderStreamDecoder dec_calibrated(calibrated);
    std::vector<EncoderSample> out_calibrated;
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> jitter_ms(0.0,
                                                     2.0);  // arbitration + USB adapter polling
    std::vector<EncoderSample> out;
    std::vector<TimeNs> sent;
    const double rev_per_s = 1.0;
    for (int k = 0; k < 4000; ++k) {
        if (k == 1000) continue;  // a lost frame
        const TimeNs t_sent = 50 * kNsPerSec + static_cast<TimeNs>(k) * 5 * kNsPerMs;
        const auto counts =
            static_cast<std::uint32_t>(std::llround(toSeconds(t_sent) * rev_per_s * 16384)) % 16384;
        CandumpRecord rec;
        rec.has_time = true;
        rec.interface = "can0";
        rec.frame = encodeEncoderPositionTpdo(1, counts);
        const TimeNs t_rx = t_sent + static_cast<TimeNs>((0.2 + jitter_ms(rng)) * 1e6);
        rec.setTimeNs(t_rx);
        const std::string line = formatCandumpLogLine(rec);
        dec.feed(t_rx, bytesOf(line), out);
        dec_calibrated.feed(t_rx, bytesOf(line), out_calibrated);
        sent.push_back(t_sent);
    }
    ASSERT_EQ(out.size(), sent.size()) << dec.counters().last_error;
    EXPECT_EQ(dec.counters().gaps, 1u);
    double max_err_ms = 0;
    std::size_t worst = 0;
    for (std::size_t i = 500; i < out.size(); ++i) {
        // The constant 0.2 ms of minimum latency is not observable; the jitter must be gone.
        const double err = std::abs(toSeconds(out[i].t_host - sent[i]) * 1e3 - 0.2);
        if (err > max_err_ms) worst = i;
        max_err_ms = std::max(max_err_ms, err);
    }
    SCOPED_TRACE("worst at sample " + std::to_string(worst));
    EXPECT_LT(max_err_ms, 0.1) << "receive jitter (0-2 ms) left in the encoder times";
    ASSERT_EQ(out_calibrated.size(), sent.size());
    for (std::size_t i = 500; i < out_calibrated.size(); ++i) {
        ASSERT_NEAR(toSeconds(out_calibrated[i].t_host - sent[i]) * 1e3, 0.0, 0.1)
            << "sample " << i;
    }
    EXPECT_NEAR(out.back().speed_radps, 2 * std::numbers::pi * rev_per_s, 0.05);
}

TEST(EncoderStreamDecoder, GarbageLinesAreCountedNotFatal) {
    EncoderStreamDecoder dec({});
    std::vector<EncoderSample> out;
    dec.feed(0, bytesOf("not a candump line\n"), out);
    EXPECT_TRUE(out.empty());
    EXPECT_EQ(dec.counters().errors, 1u);
}

// A live bus whose adapter delivers each TPDO1 0.2-1.7 ms after the encoder sent it (arbitration,
// USB polling), and a recorder tap that writes what the host received, as the daemon's recorder
// stores /motor/can.
class JitteryBus final : public transport::CanBus {
public:
    explicit JitteryBus(EmulatedCanBus& inner) : inner_(inner) {}
    Status open() override { return inner_.open(); }
    void close() override { inner_.close(); }
    bool isOpen() const override { return inner_.isOpen(); }
    Status setFilters(std::span<const transport::CanFilter> f) override {
        return inner_.setFilters(f);
    }
    Result<transport::TimedCanFrame> receive(TimeNs timeout) override {
        auto r = inner_.receive(timeout);
        if (!r) return r;
        if (classifyCobId(r->frame).function == CanOpenFunction::kTpdo) {
            sent_.push_back(r->t_host);
            // Whole microseconds: a candump -l line carries no more.
            r->t_host += static_cast<TimeNs>(200 + rng_() % 1500) * kNsPerUs;
        }
        CandumpRecord rec;
        rec.setTimeNs(r->t_host);
        rec.interface = "can0";
        rec.frame = r->frame;
        log_ << formatCandumpLogLine(rec) << '\n';
        return r;
    }
    Status send(const CanFrame& frame) override { return inner_.send(frame); }
    std::string describe() const override { return "jittery " + inner_.describe(); }

    std::string log() const { return log_.str(); }
    const std::vector<TimeNs>& tpdoSentTimes() const { return sent_; }

private:
    EmulatedCanBus& inner_;
    std::mt19937 rng_{17};
    std::ostringstream log_;
    std::vector<TimeNs> sent_;
};

TEST(EncoderStamping, LiveDeviceAndRecordedStreamGiveTheSameSamples) {
    EncoderEmulatorConfig ec;
    ec.units_per_revolution = 8192;
    ec.total_range = 8192;
    ec.speed_radps = 2.0 * std::numbers::pi;
    ec.power_on = 1'700'000'000 * kNsPerSec;
    Cia406EncoderEmulator enc(ec);
    EmulatedCanBus wire(ec.power_on);
    wire.addNode(&enc);
    JitteryBus bus(wire);
    MotorConfig cfg;
    cfg.cyclic_timer_ms = 2;
    cfg.tpdo_latency = 150 * kNsPerUs;
    MotorDevice device(bus, cfg, [&] { return wire.now(); });
    ASSERT_TRUE(device.start());
    std::vector<EncoderSample> live;
    while (wire.now() < ec.power_on + 8 * kNsPerSec) {
        auto r = device.poll(5 * kNsPerMs);
        ASSERT_TRUE(r) << r.status().message();
        if (*r) live.push_back(**r);
    }
    ASSERT_GT(live.size(), 3500u);

    // The recording of the same bus through the recorded-stream decoder: each line at its
    // receive time, as replay feeds MCAP messages at their log time.
    EncoderStreamConfig sc;
    sc.node_id = 1;
    sc.unwrapper.units_per_revolution = 8192;
    sc.unwrapper.total_range = 8192;
    sc.tpdo_period_ns = 2 * kNsPerMs;
    sc.tpdo_latency_ns = 150 * kNsPerUs;
    EncoderStreamDecoder decoder(sc);
    std::vector<EncoderSample> recorded;
    std::istringstream in(bus.log());
    for (std::string line; std::getline(in, line);) {
        auto rec = parseCandumpLogLine(line);
        ASSERT_TRUE(rec) << line;
        decoder.feed(rec->timeNs(), bytesOf(line), recorded);
    }
    EXPECT_EQ(decoder.counters().errors, 0u) << decoder.counters().last_error;
    // The live device keeps the TPDOs that arrived after its NMT start; the recording has the
    // same ones (the encoder sends none before it).
    ASSERT_EQ(recorded.size(), live.size());
    for (std::size_t i = 0; i < live.size(); ++i) {
        ASSERT_EQ(live[i].t_host, recorded[i].t_host) << "sample " << i;
        ASSERT_EQ(live[i].raw_position, recorded[i].raw_position) << "sample " << i;
        ASSERT_EQ(live[i].angle_rad, recorded[i].angle_rad) << "sample " << i;
        ASSERT_EQ(live[i].speed_radps, recorded[i].speed_radps) << "sample " << i;
    }
    // And both are the sampling times, not the receive times: the 0.2-1.7 ms jitter is gone
    // once the fit has a second of envelope (receive time minus latency would be off by up to
    // 1.5 ms).
    const std::vector<TimeNs>& sent = bus.tpdoSentTimes();
    ASSERT_GE(sent.size(), live.size());
    const std::size_t skipped = sent.size() - live.size();  // TPDOs before the device streamed
    for (std::size_t i = 500; i < live.size(); ++i) {
        ASSERT_NEAR(toSeconds(live[i].t_host - sent[i + skipped]) * 1e3, 0.05, 0.1)
            << "sample " << i;
    }
}

}  // namespace
}  // namespace handscan::motor
