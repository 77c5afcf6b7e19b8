#include "handscan/motor/encoder_stream_decoder.hpp"

#include <string>
#include <string_view>

#include "handscan/motor/candump_format.hpp"
#include "handscan/motor/canopen.hpp"

namespace handscan::motor {

EncoderStreamDecoder::EncoderStreamDecoder(EncoderStreamConfig config)
    : cfg_(config),
      clock_(config.unwrapper, EncoderTiming{config.tpdo_period_ns, config.tpdo_latency_ns}) {}

void EncoderStreamDecoder::feed(TimeNs t_rx, std::span<const std::uint8_t> line,
                                std::vector<EncoderSample>& out) {
    std::string_view text(reinterpret_cast<const char*>(line.data()), line.size());
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.remove_suffix(1);
    auto record = parseCandumpAnyLine(text);
    if (!record) {
        ++c_.errors;
        c_.last_error = "CAN: " + record.status().message();
        return;
    }
    const auto& frame = record->frame;
    if (frame.extended || frame.remote || frame.error || frame.id != cobTpdo(1, cfg_.node_id))
        return;
    auto position = decodeEncoderPositionTpdo(frame);
    if (!position) {
        ++c_.errors;
        c_.last_error = "CAN: TPDO1 of node " + std::to_string(cfg_.node_id) + ": " +
                        position.status().message();
        return;
    }
    auto sample = clock_.update(t_rx, *position);
    if (!sample) {
        ++c_.errors;
        c_.last_error = "encoder: " + sample.status().message();
        return;
    }
    out.push_back(*sample);
    ++c_.messages;
}

StreamCounters EncoderStreamDecoder::counters() const {
    StreamCounters c = c_;
    c.gaps = clock_.missed();
    return c;
}

}  // namespace handscan::motor
