#include "handscan/sim/can_stream.hpp"

#include <cmath>
#include <numbers>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"

namespace handscan::sim {

namespace mo = handscan::motor;

CanStream::CanStream(const CanStreamConfig& config, const ShaftModel& shaft, TimeNs host_start_ns,
                     Rng rng)
    : cfg_(config), shaft_(shaft), host_start_(host_start_ns), rng_(rng) {}

std::uint32_t CanStream::positionAt(double t) const {
    const double turns =
        (shaft_.angle(t) + cfg_.encoder_zero_offset_rad) / (2.0 * std::numbers::pi);
    const double counts = std::floor(turns * cfg_.counts_per_rev);
    const double wrapped = counts - std::floor(counts / cfg_.counts_per_rev) * cfg_.counts_per_rev;
    return static_cast<std::uint32_t>(wrapped);
}

void CanStream::emit(double t_send, const CanFrame& frame, std::vector<StreamMessage>& out) {
    mo::CandumpRecord rec;
    rec.has_time = true;
    rec.interface = cfg_.interface;
    rec.frame = frame;
    const TimeNs rx = hostNs(host_start_, t_send + cfg_.clock.delay(rng_));
    rec.setTimeNs(rx);
    const std::string line = mo::formatCandumpLogLine(rec);
    out.push_back(
        StreamMessage{rx, SimChannel::kCan, std::vector<std::uint8_t>(line.begin(), line.end())});
}

void CanStream::generate(double t0, double t1, std::vector<StreamMessage>& out) {
    const std::uint8_t enc = cfg_.encoder_node, drv = cfg_.drive_node;
    if (!started_) {
        started_ = true;
        // Power-up and configuration (host requests are on the bus too: candump shows them).
        double t = std::max(t0, 0.01);
        emit(t, mo::encodeHeartbeat(enc, mo::NmtState::kBootUp), out);
        emit(t + 0.002, mo::encodeHeartbeat(drv, mo::NmtState::kBootUp), out);
        t += 0.02;
        const auto sdo = [&](std::uint16_t index, std::uint8_t sub, std::uint32_t value,
                             std::uint8_t size) {
            emit(t, mo::encodeSdoWrite(enc, index, sub, value, size), out);
            emit(t + 0.0006, mo::encodeSdoWriteAck(enc, index, sub), out);
            t += 0.003;
        };
        sdo(mo::od::kProducerHeartbeatTime, 0,
            static_cast<std::uint32_t>(std::lround(cfg_.heartbeat_period_s * 1000)), 2);
        sdo(mo::od::kEncoderCyclicTimer, 0,
            static_cast<std::uint32_t>(std::lround(cfg_.tpdo_period_s * 1000)), 2);
        sdo(mo::od::kTpdo1Communication, 2, mo::kTransmissionEventManufacturer, 1);
        emit(t, mo::encodeNmt(mo::NmtCommand::kStart, 0), out);
        operational_at_ = t + 0.001;
        // The encoder's cyclic timer starts at NMT start, on its own clock.
        next_tpdo_ = 0;
        next_hb_ = 0;
    }
    const double dev0 = cfg_.clock.deviceSeconds(operational_at_);
    // TPDO1 every cyclic-timer period of the encoder's clock.
    for (;;) {
        const double t =
            cfg_.clock.trueSeconds(dev0 + static_cast<double>(next_tpdo_) * cfg_.tpdo_period_s);
        if (t >= t1) break;
        ++next_tpdo_;
        if (t < t0) continue;
        const std::uint32_t pos = positionAt(t);
        readings_.push_back({t, pos});
        emit(t, mo::encodeEncoderPositionTpdo(enc, pos), out);
    }
    for (;;) {
        const double t = cfg_.clock.trueSeconds(
            dev0 + static_cast<double>(next_hb_) * cfg_.heartbeat_period_s + 0.0005);
        if (t >= t1) break;
        ++next_hb_;
        if (t < t0) continue;
        emit(t, mo::encodeHeartbeat(enc, mo::NmtState::kOperational), out);
        emit(t + 0.0013, mo::encodeHeartbeat(drv, mo::NmtState::kOperational), out);
    }
}

}  // namespace handscan::sim
