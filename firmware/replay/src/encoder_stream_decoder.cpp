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
    c.outlier_ns = 20 * kNsPerMs;
    return c;
}

}  // namespace

EncoderStreamDecoder::EncoderStreamDecoder(EncoderStreamConfig config)
    : cfg_(config), unwrapper_(config.unwrapper), tpdo_clock_(tpdoClock(config.tpdo_period_ns)) {}

void EncoderStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> line, std::vector<EncoderSample>& out) {
    std::string_view text(reinterpret_cast<const char*>(line.data()), line.size());
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
    auto record = motor::parseCandumpAnyLine(text);
    if (!record) {
        ++c_.errors;
        c_.last_error = "CAN: " + record.status().message();
        return;
    }
    const auto& frame = record->frame;
    if (frame.extended || frame.remote || frame.error || frame.id != motor::cobTpdo(1, cfg_.node_id)) return;
    if (frame.len < 4) {
        ++c_.errors;
        c_.last_error = "CAN: TPDO1 of node " + std::to_string(cfg_.node_id) + " with " + std::to_string(frame.len) + " bytes";
        return;
    }
    const std::uint32_t raw = static_cast<std::uint32_t>(frame.data[0]) | (static_cast<std::uint32_t>(frame.data[1]) << 8) |
                              (static_cast<std::uint32_t>(frame.data[2]) << 16) | (static_cast<std::uint32_t>(frame.data[3]) << 24);
    // Count TPDOs on the encoder's cyclic timer; a longer silence means lost frames.
    if (last_rx_) {
        const double periods = static_cast<double>(t_rx - *last_rx_) / static_cast<double>(cfg_.tpdo_period_ns);
        const std::int64_t step = std::max<std::int64_t>(1, std::llround(periods));
        if (step > 1) c_.gaps += static_cast<std::uint64_t>(step - 1);
        tpdo_index_ += step;
    }
    last_rx_ = t_rx;
    tpdo_clock_.observe(static_cast<std::uint64_t>(tpdo_index_), t_rx);
    const TimeNs t_sent = tpdo_clock_.toHostUnwrapped(tpdo_index_);
    auto sample = unwrapper_.update(std::min(t_sent, t_rx), raw);
    if (!sample) {
        ++c_.errors;
        c_.last_error = "encoder: " + sample.status().message();
        return;
    }
    out.push_back(*sample);
    ++c_.messages;
}

}  // namespace handscan::replay
