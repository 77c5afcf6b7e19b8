// The encoder's recorded CAN traffic (one candump -l line per message, as /motor/can holds it)
// back into EncoderSamples: TPDO1 positions of one node, stamped by the same EncoderSampleClock
// the live MotorDevice uses, so a recording replays with the time stamps the device had.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/stream_counters.hpp"
#include "handscan/motor/encoder_sample_clock.hpp"

namespace handscan::motor {

struct EncoderStreamConfig {
    std::uint8_t node_id = 1;
    UnwrapperConfig unwrapper;
    TimeNs tpdo_period_ns = 5 * kNsPerMs;  // 6200h cyclic timer as configured
    TimeNs tpdo_latency_ns = 0;  // position sampled -> frame received (motor.tpdo_latency_ms)
};

class EncoderStreamDecoder {
public:
    explicit EncoderStreamDecoder(EncoderStreamConfig config);
    void feed(TimeNs t_rx, std::span<const std::uint8_t> line, std::vector<EncoderSample>& out);
    StreamCounters counters() const;

private:
    EncoderStreamConfig cfg_;
    EncoderSampleClock clock_;
    StreamCounters c_;
};

}  // namespace handscan::motor
