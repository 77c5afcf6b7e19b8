#include "handscan/replay/stream_decoders.hpp"
#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xdi.hpp"

namespace handscan::replay {
namespace {

ClockMapperConfig sampleTimeFineClock() {
    ClockMapperConfig c;
    c.counter_bits = 32;  // SampleTimeFine: 10 kHz, wraps after 4.97 days
    c.tick_ns = 1e5;
    return c;
}

}  // namespace

XsensStreamDecoder::XsensStreamDecoder() : clock_(sampleTimeFineClock()) {}

void XsensStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes, std::vector<ImuSample>& out) {
    parser_.feed(bytes);
    while (auto frame = parser_.next()) {
        if (frame->mid == xsens::toByte(xsens::MessageId::kError)) {
            ++c_.errors;
            auto e = xsens::decodeError(frame->payload);
            c_.last_error = "Xsens reported Error " + (e.isOk() ? xsens::errorText(e->code) : e.status().message());
            continue;
        }
        if (frame->mid != xsens::toByte(xsens::MessageId::kMtData2)) continue;
        auto packet = xsens::decodeMtData2(frame->payload);
        if (!packet) {
            ++c_.errors;
            c_.last_error = packet.status().message();
            continue;
        }
        if (auto pc = packet->integer(xsens::xdi::kPacketCounter)) {
            const auto counter = static_cast<std::uint16_t>(*pc);
            if (last_counter_) c_.gaps += static_cast<std::uint16_t>(counter - *last_counter_ - 1);
            last_counter_ = counter;
        }
        const auto stf = packet->integer(xsens::xdi::kSampleTimeFine);
        const auto acc = packet->vector3(xsens::xdi::kAcceleration);
        const auto gyro = packet->vector3(xsens::xdi::kRateOfTurn);
        if (!stf || !acc || !gyro) {
            ++c_.errors;
            c_.last_error = "Xsens MTData2 without SampleTimeFine, Acceleration or RateOfTurn";
            continue;
        }
        clock_.observe(*stf, t_rx);
        ImuSample s;
        s.t_host = *clock_.toHost(*stf);
        s.t_device_ticks = clock_.unwrap(*stf);
        s.accel_mps2_imu = *acc;
        s.gyro_radps_imu = *gyro;
        if (auto sw = packet->integer(xsens::xdi::kStatusWord)) s.status_word = static_cast<std::uint32_t>(*sw);
        s.packet_counter = last_counter_.value_or(0);
        out.push_back(s);
        ++c_.messages;
    }
}

StreamCounters XsensStreamDecoder::counters() const {
    StreamCounters c = c_;
    c.checksum_failures = parser_.stats().checksum_failures;
    c.resyncs = parser_.stats().resyncs;
    return c;
}

}  // namespace handscan::replay
