// Turns the encoder's position value (CiA 406 6004h: counts within the total measuring range
// 6002h, wrapping from range-1 to 0) into a continuous shaft angle and a speed estimate.
// Pure computation; the device state machine feeds it TPDO1 values with their receive times.
#pragma once

#include <cstdint>
#include <deque>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"

namespace handscan::motor {

struct UnwrapperConfig {
    std::uint32_t units_per_revolution = 4096;  // 6001h measuring units per revolution
    std::uint64_t total_range = 0;        // 6002h total measuring range; 0 = 2^32 (u32 counter)
    bool reverse = false;                 // negate the angle (mounting direction)
    TimeNs speed_window = 20 * kNsPerMs;  // least-squares window of the speed estimate
};

class PositionUnwrapper {
public:
    explicit PositionUnwrapper(UnwrapperConfig config) : cfg_(config) {}

    // Adds one position; fails (and keeps its state) on a value outside the measuring range or a
    // time that goes backwards. Between consecutive values the shaft must turn less than half the
    // measuring range, else the direction of the wrap is ambiguous.
    [[nodiscard]] Result<EncoderSample> update(TimeNs t_host, std::uint32_t raw);
    void reset();
    std::int64_t unwrappedCounts() const { return unwrapped_; }
    std::uint64_t wraps() const { return wraps_; }
    const UnwrapperConfig& config() const { return cfg_; }

private:
    double speedEstimate() const;

    UnwrapperConfig cfg_;
    bool have_last_ = false;
    std::uint32_t last_raw_ = 0;
    TimeNs last_t_ = 0;
    std::int64_t unwrapped_ = 0;
    std::uint64_t wraps_ = 0;
    struct Point {
        TimeNs t;
        double angle;
    };
    std::deque<Point> window_;
};

}  // namespace handscan::motor
