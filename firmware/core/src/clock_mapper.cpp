#include "handscan/core/clock_mapper.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace handscan {

ClockMapper::ClockMapper(ClockMapperConfig config)
    : cfg_(config),
      mask_(config.counter_bits >= 64 ? ~std::uint64_t{0}
                                      : ((std::uint64_t{1} << config.counter_bits) - 1)) {}

std::int64_t ClockMapper::unwrap(std::uint64_t device_raw) const {
    if (cfg_.counter_bits >= 64) return static_cast<std::int64_t>(device_raw);
    const std::uint64_t half = (mask_ >> 1) + 1;
    const std::uint64_t delta = (device_raw - last_raw_) & mask_;
    // Forward by less than half the range, or backward by less than half the range.
    const std::int64_t signed_delta =
        delta < half ? static_cast<std::int64_t>(delta)
                     : static_cast<std::int64_t>(delta) - static_cast<std::int64_t>(mask_ + 1);
    return last_unwrapped_ + signed_delta;
}

void ClockMapper::restart(std::uint64_t device_raw, TimeNs host_rx) {
    have_first_ = true;
    last_raw_ = device_raw & mask_;
    last_unwrapped_ = static_cast<std::int64_t>(last_raw_);
    origin_ticks_ = last_unwrapped_;
    origin_host_ = host_rx;
    envelope_.clear();
    envelope_.push_back({0.0, 0.0});
    offset_ = 0.0;
    slope_ = 0.0;
    gross_in_a_row_ = 0;
    below_in_a_row_ = 0;
}

ClockMapper::Event ClockMapper::observe(std::uint64_t device_raw, TimeNs host_rx) {
    device_raw &= mask_;
    if (!have_first_) {
        restart(device_raw, host_rx);
        return Event::kFirst;
    }
    const std::int64_t unwrapped = unwrap(device_raw);
    const Point p{(static_cast<double>(unwrapped - origin_ticks_)) * cfg_.tick_ns,
                  static_cast<double>(host_rx - origin_host_)};
    const double r = residual(p);
    const bool went_backwards =
        unwrapped<last_unwrapped_&& static_cast<double>(last_unwrapped_ - unwrapped) *
                  cfg_.tick_ns> static_cast<double>(cfg_.outlier_ns);
    if (went_backwards || std::abs(r) > static_cast<double>(cfg_.reset_ns)) {
        // Either a restart of the device or a single garbage timestamp: restart only when it
        // persists, otherwise drop the point.
        if (++gross_in_a_row_ >= cfg_.reset_after) {
            ++resets_;
            restart(device_raw, host_rx);
            return Event::kReset;
        }
        ++outliers_;
        return Event::kOutlier;
    }
    gross_in_a_row_ = 0;
    if (r < -static_cast<double>(cfg_.outlier_ns)) {
        // Received before it could have been sent: a bad host timestamp. If it persists, it is the
        // fit that was wrong (the first points all arrived late): start again from here.
        if (++below_in_a_row_ >= cfg_.reset_after) {
            ++resets_;
            restart(device_raw, host_rx);
            return Event::kReset;
        }
        ++outliers_;
        return Event::kOutlier;
    }
    below_in_a_row_ = 0;
    const bool wrapped = device_raw < last_raw_ && unwrapped > last_unwrapped_;
    if (wrapped) ++wraps_;
    if (unwrapped >= last_unwrapped_) {
        last_raw_ = device_raw;
        last_unwrapped_ = unwrapped;
    }
    insert(p);
    refit();
    return wrapped ? Event::kWrapped : Event::kAccepted;
}

void ClockMapper::insert(const Point& p) {
    const double bucket_ns = static_cast<double>(cfg_.window_ns) / std::max(1, cfg_.buckets);
    // Same bucket as the newest point: keep the lower one (relative to the nominal rate).
    if (!envelope_.empty()) {
        Point& last = envelope_.back();
        if (std::floor(last.d / bucket_ns) == std::floor(p.d / bucket_ns)) {
            if (p.h - p.d * (1.0 + slope_) < last.h - last.d * (1.0 + slope_)) last = p;
            return;
        }
    }
    envelope_.push_back(p);
    while (!envelope_.empty() && p.d - envelope_.front().d > static_cast<double>(cfg_.window_ns)) {
        envelope_.pop_front();
    }
}

void ClockMapper::refit() {
    const std::size_t n = envelope_.size();
    if (n == 1) {
        offset_ = envelope_.front().h - envelope_.front().d * (1.0 + slope_);
        return;
    }
    // Lower convex hull (monotone chain; points are sorted by device time). Work in the residual
    // space of the nominal rate so the numbers stay small.
    std::vector<Point> pts;
    pts.reserve(n);
    for (const Point& e : envelope_) pts.push_back({e.d, e.h - e.d});
    std::vector<Point> hull;
    hull.reserve(n);
    for (const Point& q : pts) {
        while (hull.size() >= 2) {
            const Point& a = hull[hull.size() - 2];
            const Point& b = hull.back();
            const double cross = (b.d - a.d) * (q.h - a.h) - (b.h - a.h) * (q.d - a.d);
            if (cross <= 0.0)
                hull.pop_back();
            else
                break;
        }
        hull.push_back(q);
    }
    if (hull.size() < 2) return;
    double mean_d = 0.0;
    for (const Point& q : pts) mean_d += q.d;
    mean_d /= static_cast<double>(n);
    // The LP optimum passes through the hull edge spanning the mean device time.
    std::size_t i = 0;
    while (i + 2 < hull.size() && hull[i + 1].d < mean_d) ++i;
    const Point& a = hull[i];
    const Point& b = hull[i + 1];
    const double s = (b.h - a.h) / (b.d - a.d);
    slope_ = s;
    // In residual space h - d = offset + s d, i.e. h = offset + (1 + s) d.
    offset_ = a.h - s * a.d;
}

TimeNs ClockMapper::toHostUnwrapped(std::int64_t device_ticks) const {
    const double d = static_cast<double>(device_ticks - origin_ticks_) * cfg_.tick_ns;
    return origin_host_ + static_cast<TimeNs>(std::llround(offset_ + (1.0 + slope_) * d));
}

std::optional<TimeNs> ClockMapper::toHost(std::uint64_t device_raw) const {
    if (!have_first_) return std::nullopt;
    return toHostUnwrapped(unwrap(device_raw & mask_));
}

}  // namespace handscan
