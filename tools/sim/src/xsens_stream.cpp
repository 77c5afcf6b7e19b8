#include "handscan/sim/xsens_stream.hpp"

#include <algorithm>
#include <cmath>

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_frame.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xdi.hpp"

namespace handscan::sim {

namespace xs = handscan::xsens;

XsensStream::XsensStream(const XsensStreamConfig& config, TimeNs host_start_ns, Rng rng)
    : cfg_(config), host_start_(host_start_ns), rng_(rng) {
    // Measurement starts after the handshake, on a whole tick of the IMU's sample clock.
    const double period = 1.0 / cfg_.rate_hz;
    first_sample_device_s_ = std::ceil((cfg_.clock.deviceSeconds(0.05)) / period) * period;
}

double XsensStream::sampleTime(std::int64_t k) const {
    return cfg_.clock.trueSeconds(first_sample_device_s_ + static_cast<double>(k) / cfg_.rate_hz);
}

std::uint32_t XsensStream::sampleTimeFine(std::int64_t k) const {
    const double device_s = first_sample_device_s_ + static_cast<double>(k) / cfg_.rate_hz;
    return static_cast<std::uint32_t>(static_cast<std::uint64_t>(std::llround(device_s * 1e4)) &
                                      0xFFFFFFFFu);
}

void XsensStream::deliver(double t_send, std::vector<std::uint8_t> bytes,
                          std::vector<StreamMessage>& out) {
    const double byte_s = 10.0 / cfg_.baud;  // 8N1
    const double start = std::max(t_send, line_free_at_);
    const double end = start + byte_s * static_cast<double>(bytes.size());
    line_free_at_ = end;
    const double delay = cfg_.clock.delay(rng_);
    if (bytes.size() > 8 && rng_.chance(cfg_.split_probability)) {
        // The USB-serial bridge flushed mid-frame.
        const std::size_t cut = 1 + static_cast<std::size_t>(rng_.below(bytes.size() - 1));
        const double t_cut = start + byte_s * static_cast<double>(cut);
        const TimeNs rx1 = hostNs(host_start_, t_cut + delay);
        const TimeNs rx2 = std::max(rx1 + 1, hostNs(host_start_, end + cfg_.clock.delay(rng_)));
        out.push_back(
            {rx1, SimChannel::kXsens,
             std::vector<std::uint8_t>(bytes.begin(), bytes.begin() + static_cast<long>(cut))});
        out.push_back(
            {rx2, SimChannel::kXsens,
             std::vector<std::uint8_t>(bytes.begin() + static_cast<long>(cut), bytes.end())});
        return;
    }
    out.push_back({hostNs(host_start_, end + delay), SimChannel::kXsens, std::move(bytes)});
}

void XsensStream::handshake(double t, std::vector<StreamMessage>& out) {
    const auto p = static_cast<xs::Precision>(cfg_.precision & 3);
    std::vector<xs::OutputConfigEntry> config = {
        {xs::xdi::kPacketCounter, xs::kEveryPacket},
        {xs::xdi::kSampleTimeFine, xs::kEveryPacket},
        {xs::withFormat(xs::xdi::kAcceleration, p), static_cast<std::uint16_t>(cfg_.rate_hz)},
        {xs::withFormat(xs::xdi::kRateOfTurn, p), static_cast<std::uint16_t>(cfg_.rate_hz)},
        {xs::xdi::kStatusWord, xs::kEveryPacket},
    };
    if (cfg_.delta_q_v) {
        config.push_back(
            {xs::withFormat(xs::xdi::kDeltaV, p), static_cast<std::uint16_t>(cfg_.rate_hz)});
        config.push_back(
            {xs::withFormat(xs::xdi::kDeltaQ, p), static_cast<std::uint16_t>(cfg_.rate_hz)});
    }
    const std::vector<std::vector<std::uint8_t>> replies = {
        xs::encodeFrame(xs::MessageId::kGoToConfigAck),
        xs::encodeFrame(xs::MessageId::kDeviceId, xs::encodeDeviceId(cfg_.device_id)),
        xs::encodeFrame(xs::MessageId::kProductCode, xs::encodeProductCode("MTi-20-2A5G4")),
        xs::encodeFrame(xs::MessageId::kSetOutputConfigurationAck,
                        xs::encodeOutputConfiguration(config)),
        xs::encodeFrame(xs::MessageId::kGoToMeasurementAck),
    };
    double at = t;
    for (const auto& r : replies) {
        deliver(at, r, out);
        at += 0.004;  // the host's next command after the ack
    }
}

void XsensStream::sample(std::int64_t k, const ImuMeasurement& m, bool drop_byte,
                         std::vector<StreamMessage>& out) {
    const auto p = static_cast<xs::Precision>(cfg_.precision & 3);
    const double dt = 1.0 / cfg_.rate_hz;
    std::uint32_t status = 0x3;  // self test ok, filter valid
    // Clipping flags (StatusWord bits 8..13: acc x y z, gyr x y z).
    for (int i = 0; i < 3; ++i) {
        if (std::abs(m.accel[i]) >= 199.999) status |= 1u << (8 + i);
        if (std::abs(m.gyro[i]) >= 7.853) status |= 1u << (11 + i);
    }
    xs::MtData2Builder b;
    b.packetCounter(static_cast<std::uint16_t>(k & 0xFFFF)).sampleTimeFine(sampleTimeFine(k));
    if (cfg_.delta_q_v) b.deltaV(m.accel * dt, p);
    b.acceleration(m.accel, p).rateOfTurn(m.gyro, p);
    if (cfg_.delta_q_v) {
        // Strapdown increment over one sample: q = exp(omega dt / 2), (q0, q1, q2, q3).
        const Eigen::Vector3d half = m.gyro * dt / 2.0;
        const double a = half.norm();
        const double s = a > 1e-12 ? std::sin(a) / a : 1.0;
        b.deltaQ(Eigen::Vector4d(std::cos(a), s * half.x(), s * half.y(), s * half.z()), p);
    }
    b.statusWord(status);
    std::vector<std::uint8_t> frame = b.frame();
    if (drop_byte) frame.erase(frame.begin() + 4 + static_cast<long>(rng_.below(frame.size() - 5)));
    deliver(sampleTime(k) + 0.0002, std::move(frame), out);
}

}  // namespace handscan::sim
