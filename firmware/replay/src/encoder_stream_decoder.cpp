#include <cmath>
#include <string_view>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/replay/stream_decoders.hpp"

namespace handscan::replay {
namespace {

ClockMapperConfig tpdoClock(TimeNs period_ns) {
    ClockMapperConfig c;
    c.counter_bits = 64;
    c.tick_ns = static_cast<double>(period_ns);
    c.outlier_ns = period_ns / 2;  // a miscounted period shows as a point far below the envelope
    // Short buckets: the encoder's crystal drifts slowly, but the fit must settle within seconds.
    c.window_ns = 20 * kNsPerSec;
    c.buckets = 100;
    return c;
}

}  // namespace

EncoderStreamDecoder::EncoderStreamDecoder(EncoderStreamConfig config)
    : cfg_(config), unwrapper_(config.unwrapper), tpdo_clock_(tpdoClock(config.tpdo_period_ns)) {}

void EncoderStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> line,
                                std::vector<EncoderSample>& out) {
    std::string_view text(reinterpret_cast<const char*>(line.data()), line.size());
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
    auto record = motor::parseCandumpAnyLine(text);
    if (!record) {
        ++c_.errors;
        c_.last_error = "CAN: " + record.status().message();
        return;
    }
    const auto& frame = record->frame;
    if (frame.extended || frame.remote || frame.error ||
        frame.id != motor::cobTpdo(1, cfg_.node_id))
        return;
    auto position = motor::decodeEncoderPositionTpdo(frame);
    if (!position) {
        ++c_.errors;
        c_.last_error = "CAN: TPDO1 of node " + std::to_string(cfg_.node_id) + ": " +
                        position.status().message();
        return;
    }
    const std::uint32_t raw = *position;
    // Count TPDOs on the encoder's cyclic timer: n periods after the previous one's (fitted)
    // transmit time, as many as fit before this receive time (latency is never negative). A
    // latency beyond one period miscounts; the clock fit then sees points below its envelope
    // and restarts, so the error heals.
    if (last_rx_) {
        const double since = static_cast<double>(t_rx - tpdo_clock_.toHostUnwrapped(tpdo_index_));
        const std::int64_t step = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(
                   std::floor(since / static_cast<double>(cfg_.tpdo_period_ns))));
        if (step > 1) c_.gaps += static_cast<std::uint64_t>(step - 1);
        tpdo_index_ += step;
    }
    last_rx_ = t_rx;
    tpdo_clock_.observe(static_cast<std::uint64_t>(tpdo_index_), t_rx);
    // Never later than received, never before the previous sample (the fit moves while it
    // learns the envelope; a step back would make the unwrapper reject the sample).
    // The fit gives the fastest delivery; the position was sampled the fixed latency before it.
    TimeNs t_sent = std::min(tpdo_clock_.toHostUnwrapped(tpdo_index_), t_rx) - cfg_.tpdo_latency_ns;
    if (last_sample_t_) t_sent = std::max(t_sent, *last_sample_t_ + 1);
    last_sample_t_ = t_sent;
    auto sample = unwrapper_.update(t_sent, raw);
    if (!sample) {
        ++c_.errors;
        c_.last_error = "encoder: " + sample.status().message();
        return;
    }
    out.push_back(*sample);
    ++c_.messages;
}

}  // namespace handscan::replay
