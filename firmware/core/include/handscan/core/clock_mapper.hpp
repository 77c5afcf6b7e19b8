// Maps a device clock onto host CLOCK_MONOTONIC from (device time, host receive time) pairs.
//
// Model: host_rx = offset + (1 + drift) * device_time + latency, latency >= 0 and jittery. The
// transport only ever adds delay, so the true line is the *lower envelope* of the points (as the
// best Hokuyo time-stamping drivers do). We keep the minimum point of each of a fixed number of
// buckets over a sliding window and solve the linear program "line below every point, as close as
// possible on average": its optimum is the edge of the lower convex hull that spans the mean device
// time. N-bit counters are unwrapped; points far below the line are outliers; a device time jumping
// backwards (not a wrap) or a persistent large residual is a device restart and resets the fit.
#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "handscan/core/time.hpp"

namespace handscan {

struct ClockMapperConfig {
    int counter_bits = 64;  // width of the device counter (24 for Hokuyo ms, 32 for Xsens)
    double tick_ns = 1.0;   // nanoseconds per device tick (1e6: ms counter, 1e5: 10 kHz)
    TimeNs window_ns = 300 * kNsPerSec;  // how much history the fit uses
    int buckets = 120;                   // lower-envelope points kept over the window
    TimeNs outlier_ns = 50 * kNsPerMs;   // a point this far *below* the line is an outlier
    TimeNs reset_ns = 2 * kNsPerSec;     // |residual| beyond this, repeatedly, is a restart
    int reset_after = 3;                 // consecutive gross residuals that mean a restart
};

class ClockMapper {
public:
    enum class Event { kAccepted, kFirst, kWrapped, kOutlier, kReset };

    explicit ClockMapper(ClockMapperConfig config = {});

    // Adds an observation: the device's raw counter value and the host time it was received at.
    Event observe(std::uint64_t device_raw, TimeNs host_rx);

    // Host time of a raw device counter value near the latest observation (unwrapped against it).
    // nullopt before the first observation.
    std::optional<TimeNs> toHost(std::uint64_t device_raw) const;
    // Host time of an already unwrapped device tick count.
    TimeNs toHostUnwrapped(std::int64_t device_ticks) const;
    // Unwraps a raw counter value against the latest observation.
    std::int64_t unwrap(std::uint64_t device_raw) const;

    bool ready() const { return have_first_; }
    double driftPpm() const { return slope_ * 1e6; }  // device clock runs (1 + drift) slow vs host
    int wraps() const { return wraps_; }
    int resets() const { return resets_; }
    int outliers() const { return outliers_; }

private:
    struct Point {
        double d;  // device time since origin, ns (unwrapped)
        double h;  // host time since origin, ns
    };
    void restart(std::uint64_t device_raw, TimeNs host_rx);
    void insert(const Point& p);
    void refit();
    double residual(const Point& p) const { return p.h - (offset_ + (1.0 + slope_) * p.d); }

    ClockMapperConfig cfg_;
    std::uint64_t mask_;
    bool have_first_ = false;
    std::uint64_t last_raw_ = 0;
    std::int64_t last_unwrapped_ = 0;
    std::int64_t origin_ticks_ = 0;
    TimeNs origin_host_ = 0;
    std::deque<Point> envelope_;  // bucket minima, ordered by device time
    double offset_ = 0.0;         // ns
    double slope_ = 0.0;          // drift (dimensionless)
    int wraps_ = 0;
    int resets_ = 0;
    int outliers_ = 0;
    int gross_in_a_row_ = 0;
    int below_in_a_row_ = 0;
};

}  // namespace handscan
