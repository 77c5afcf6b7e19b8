#include "handscan/xsens/imu_stream_decoder.hpp"

#include "handscan/xsens/mtdata2.hpp"
#include "handscan/xsens/xbus_messages.hpp"
#include "handscan/xsens/xdi.hpp"

namespace handscan::xsens {
namespace {

ClockMapperConfig sampleTimeFineClock() {
    ClockMapperConfig c;
    c.counter_bits = 32;  // SampleTimeFine wraps after 2^32 ticks = 4.97 days
    c.tick_ns = 1e5;      // 10 kHz
    return c;
}

}  // namespace

TimeNs ImuFrameTiming::delayOf(std::size_t frame_bytes) const {
    // 10 bits per byte on the wire (start, 8 data, stop).
    const TimeNs wire =
        baud > 0 ? static_cast<TimeNs>(static_cast<double>(frame_bytes) * 10.0 * 1e9 / baud) : 0;
    return frame_latency_ns + wire;
}

ImuStreamDecoder::ImuStreamDecoder(std::string source, ImuFrameTiming timing)
    : source_(std::move(source)), timing_(timing), clock_(sampleTimeFineClock()) {}

StreamCounters ImuStreamDecoder::counters() const {
    const ImuStreamStats s = stats();
    StreamCounters c;
    c.messages = s.samples;
    c.checksum_failures = s.checksum_failures;
    c.resyncs = s.resyncs;
    c.gaps = s.lost_packets;
    c.errors = s.device_errors + s.malformed + s.incomplete;
    c.last_error = lastProblem();
    return c;
}

ImuStreamStats ImuStreamDecoder::stats() const {
    ImuStreamStats s = stats_;
    s.checksum_failures = parser_.stats().checksum_failures;
    s.resyncs = parser_.stats().resyncs;
    return s;
}

void ImuStreamDecoder::problem(std::string text) {
    if (on_problem_) on_problem_(text);
    last_problem_ = std::move(text);
}

void ImuStreamDecoder::resetLink() {
    parser_.reset();
    counter_.reset();
}

void ImuStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> bytes,
                            std::vector<ImuSample>& out) {
    parser_.feed(bytes);
    decodePending(t_rx, out);
}

void ImuStreamDecoder::decodePending(TimeNs t_rx, std::vector<ImuSample>& out) {
    while (auto f = parser_.next()) decode(*f, t_rx, out);
}

void ImuStreamDecoder::decode(const XbusFrameView& frame, TimeNs t_rx,
                              std::vector<ImuSample>& out) {
    if (frame.mid == toByte(MessageId::kError)) {
        ++stats_.device_errors;
        auto e = decodeError(frame.payload);
        problem(source_ + " reported Error " +
                (e.isOk() ? errorText(e->code) : e.status().message()));
        return;
    }
    if (frame.mid == toByte(MessageId::kWakeUp)) {
        // Restarted (power glitch, watchdog): without a WakeUpAck it measures again with the
        // stored output configuration, counters and SampleTimeFine from 0. Start the time
        // mapping afresh instead of treating the jump as a clock fault.
        ++stats_.restarts;
        clock_ = ClockMapper(sampleTimeFineClock());
        counter_.reset();
        problem(source_ +
                " restarted (WakeUp) while measuring; resuming with its stored configuration. "
                "Check the "
                "supply if this repeats.");
        return;
    }
    if (frame.mid != toByte(MessageId::kMtData2)) return;
    ++stats_.packets;
    auto packet = decodeMtData2(frame.payload);
    if (!packet) {
        ++stats_.malformed;
        problem(packet.status().message());
        return;
    }
    if (auto pc = packet->integer(xdi::kPacketCounter)) {
        const auto counter = static_cast<std::uint16_t>(*pc);
        const std::optional<std::uint16_t> previous = counter_.last();
        if (const std::uint16_t missing = counter_.missingBefore(counter); missing != 0) {
            ++stats_.gaps;
            stats_.lost_packets += missing;
            problem(source_ + " packet counter jumped from " + std::to_string(*previous) + " to " +
                    std::to_string(counter) + ": " + std::to_string(missing) +
                    " packet(s) lost (damaged on the wire or a serial overrun)");
        }
    }
    const auto stf = packet->integer(xdi::kSampleTimeFine);
    const auto acc = packet->vector3(xdi::kAcceleration);
    const auto gyro = packet->vector3(xdi::kRateOfTurn);
    if (!stf || !acc || !gyro) {
        ++stats_.incomplete;
        problem(source_ +
                " MTData2 without SampleTimeFine, Acceleration or RateOfTurn (packet counter " +
                std::to_string(counter_.last().value_or(0)) +
                "): no sample; is the output configuration ours?");
        return;
    }
    // The frame's last byte came in at t_rx: the sample was taken at least the fixed latency and
    // the frame's wire time (preamble, BID, MID, length, payload, checksum) before.
    const std::size_t frame_bytes = 5 + frame.payload.size() + (frame.payload.size() > 254 ? 2 : 0);
    clock_.observe(*stf, t_rx - timing_.delayOf(frame_bytes));
    ImuSample s;
    s.t_host = *clock_.toHost(*stf);
    s.t_device_ticks = clock_.unwrap(*stf);
    s.accel_mps2_imu = *acc;
    s.gyro_radps_imu = *gyro;
    if (auto sw = packet->integer(xdi::kStatusWord)) {
        s.status_word = static_cast<std::uint32_t>(*sw);
    } else if (auto sb = packet->integer(xdi::kStatusByte)) {
        s.status_word = static_cast<std::uint32_t>(*sb);  // bits 0-7 of the status word
    }
    s.packet_counter = counter_.last().value_or(0);
    ++stats_.samples;
    out.push_back(s);
}

}  // namespace handscan::xsens
