#include "handscan/motor/position_unwrapper.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace handscan::motor {

void PositionUnwrapper::reset() {
    have_last_ = false;
    unwrapped_ = 0;
    wraps_ = 0;
    window_.clear();
}

Result<EncoderSample> PositionUnwrapper::update(TimeNs t_host, std::uint32_t raw) {
    const std::int64_t range = cfg_.total_range == 0 ? (std::int64_t{1} << 32)
                                                     : static_cast<std::int64_t>(cfg_.total_range);
    if (static_cast<std::int64_t>(raw) >= range) {
        return Status(StatusCode::kProtocolError,
                      "encoder position " + std::to_string(raw) +
                          " outside the total measuring range " + std::to_string(range) +
                          " (6002h); check motor.encoder.total_range in device.yaml");
    }
    if (cfg_.units_per_revolution == 0) {
        return Status(
            StatusCode::kInvalidArgument,
            "encoder units per revolution (6001h) is 0; set motor.encoder.units_per_revolution");
    }
    if (have_last_ && t_host < last_t_) {
        return Status(StatusCode::kInvalidArgument, "encoder sample time went backwards by " +
                                                        std::to_string(last_t_ - t_host) + " ns");
    }
    if (!have_last_) {
        unwrapped_ = raw;
    } else {
        // Shortest signed step modulo the range: the counter wraps range-1 -> 0 (or back).
        std::int64_t delta = static_cast<std::int64_t>(raw) - static_cast<std::int64_t>(last_raw_);
        if (delta > range / 2) {
            delta -= range;
            ++wraps_;
        } else if (delta < -(range / 2)) {
            delta += range;
            ++wraps_;
        }
        unwrapped_ += delta;
    }
    have_last_ = true;
    last_raw_ = raw;
    last_t_ = t_host;

    EncoderSample s;
    s.t_host = t_host;
    s.raw_position = raw;
    const double sign = cfg_.reverse ? -1.0 : 1.0;
    s.angle_rad =
        sign * static_cast<double>(unwrapped_) * 2.0 * std::numbers::pi / cfg_.units_per_revolution;
    window_.push_back({t_host, s.angle_rad});
    while (window_.size() > 2 && window_.front().t < t_host - cfg_.speed_window)
        window_.pop_front();
    s.speed_radps = speedEstimate();
    return s;
}

// Least-squares slope of angle over time in the window: exact for constant speed, and averages
// the receive-time jitter of the CAN frames instead of differentiating it.
double PositionUnwrapper::speedEstimate() const {
    const std::size_t n = window_.size();
    if (n < 2) return 0.0;
    const TimeNs t0 = window_.front().t;
    const double a0 = window_.front().angle;
    double st = 0, sa = 0;
    for (const auto& p : window_) {
        st += toSeconds(p.t - t0);
        sa += p.angle - a0;
    }
    const double mt = st / static_cast<double>(n), ma = sa / static_cast<double>(n);
    double num = 0, den = 0;
    for (const auto& p : window_) {
        const double dt = toSeconds(p.t - t0) - mt;
        num += dt * (p.angle - a0 - ma);
        den += dt * dt;
    }
    return den > 0 ? num / den : 0.0;
}

}  // namespace handscan::motor
