// Time stamps of a CiA 406 encoder's positions, the one place that decides them for the live
// driver (MotorDevice) and for recordings (EncoderStreamDecoder). The encoder sends TPDO1 on its
// own cyclic timer (6200h), so the n-th TPDO left the encoder at t0 + n * period on the encoder's
// clock: mapping that count onto the receive times with the lower-envelope ClockMapper removes
// the bus and host latency jitter from the angle's time stamps (1 ms of jitter at 1 rev/s would
// otherwise be 6 mrad, 6 cm at 10 m). The position was sampled the fixed latency
// (motor.tpdo_latency_ms) before the fastest delivery. Without a cyclic timer (period 0) the stamp
// is the receive time minus that latency.
#pragma once

#include <cstdint>
#include <optional>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/motor/position_unwrapper.hpp"

namespace handscan::motor {

struct EncoderTiming {
    TimeNs tpdo_period_ns = 5 * kNsPerMs;  // 6200h cyclic timer as configured; 0: not cyclic
    TimeNs tpdo_latency_ns = 0;            // position sampled -> frame received
};

class EncoderSampleClock {
public:
    EncoderSampleClock(UnwrapperConfig unwrapper, EncoderTiming timing);

    // The sample of the TPDO1 position `raw` received at `t_rx`; fails (and counts nothing) on a
    // position the unwrapper rejects. Times never step back, so the unwrapper never refuses one.
    [[nodiscard]] Result<EncoderSample> update(TimeNs t_rx, std::uint32_t raw);
    // TPDOs the cyclic count says never arrived.
    std::uint64_t missed() const { return missed_; }
    const PositionUnwrapper& unwrapper() const { return unwrapper_; }

private:
    TimeNs stamp(TimeNs t_rx);

    EncoderTiming timing_;
    PositionUnwrapper unwrapper_;
    ClockMapper tpdo_clock_;
    bool have_rx_ = false;
    std::optional<TimeNs> last_sample_t_;
    std::int64_t tpdo_index_ = 0;
    std::uint64_t missed_ = 0;
};

}  // namespace handscan::motor
