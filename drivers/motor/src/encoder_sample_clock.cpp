#include "handscan/motor/encoder_sample_clock.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::motor {
namespace {

ClockMapperConfig tpdoClock(TimeNs period_ns) {
    ClockMapperConfig c;
    c.counter_bits = 64;
    c.tick_ns = static_cast<double>(std::max<TimeNs>(period_ns, 1));
    c.outlier_ns = period_ns / 2;  // a miscounted period shows as a point far below the envelope
    // Short buckets: the encoder's crystal drifts slowly, but the fit must settle within seconds.
    c.window_ns = 20 * kNsPerSec;
    c.buckets = 100;
    return c;
}

}  // namespace

EncoderSampleClock::EncoderSampleClock(UnwrapperConfig unwrapper, EncoderTiming timing)
    : timing_(timing), unwrapper_(unwrapper), tpdo_clock_(tpdoClock(timing.tpdo_period_ns)) {}

TimeNs EncoderSampleClock::stamp(TimeNs t_rx) {
    if (timing_.tpdo_period_ns <= 0) return t_rx - timing_.tpdo_latency_ns;
    // Count TPDOs on the encoder's cyclic timer: n periods after the previous one's (fitted)
    // transmit time, as many as fit before this receive time (latency is never negative). A
    // latency beyond one period miscounts; the clock fit then sees points below its envelope
    // and restarts, so the error heals.
    if (have_rx_) {
        const double since = static_cast<double>(t_rx - tpdo_clock_.toHostUnwrapped(tpdo_index_));
        const std::int64_t step = std::max<std::int64_t>(
            1, static_cast<std::int64_t>(
                   std::floor(since / static_cast<double>(timing_.tpdo_period_ns))));
        if (step > 1) missed_ += static_cast<std::uint64_t>(step - 1);
        tpdo_index_ += step;
    }
    have_rx_ = true;
    tpdo_clock_.observe(static_cast<std::uint64_t>(tpdo_index_), t_rx);
    // Never later than received (the fit gives the fastest delivery); the position was sampled
    // the fixed latency before it.
    return std::min(tpdo_clock_.toHostUnwrapped(tpdo_index_), t_rx) - timing_.tpdo_latency_ns;
}

Result<EncoderSample> EncoderSampleClock::update(TimeNs t_rx, std::uint32_t raw) {
    TimeNs t = stamp(t_rx);
    // Never before the previous sample (the fit moves while it learns the envelope; a step back
    // would make the unwrapper reject the sample).
    if (last_sample_t_) t = std::max(t, *last_sample_t_ + 1);
    last_sample_t_ = t;
    return unwrapper_.update(t, raw);
}

}  // namespace handscan::motor
