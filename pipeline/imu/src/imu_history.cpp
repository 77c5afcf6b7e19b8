#include "handscan/imu/imu_history.hpp"

#include <algorithm>
#include <string>

namespace handscan::imu {

void ImuHistory::trimBefore(TimeNs t) {
    while (entries_.size() > 2 && entries_[1].sample.t_host <= t) entries_.pop_front();
}

std::size_t ImuHistory::indexAtOrBefore(TimeNs t) const {
    const auto it =
        std::upper_bound(entries_.begin(), entries_.end(), t,
                         [](TimeNs v, const ImuHistoryEntry& e) { return v < e.sample.t_host; });
    return static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - entries_.begin()) - 1));
}

std::size_t ImuHistory::nodeAt(TimeNs t, const Eigen::Vector3d& gravity) {
    const std::size_t k = indexAtOrBefore(t);
    if (entries_[k].sample.t_host == t || k + 1 >= entries_.size()) return k;
    const ImuHistoryEntry& a = entries_[k];
    const ImuHistoryEntry& b = entries_[k + 1];
    const double s = static_cast<double>(t - a.sample.t_host) /
                     static_cast<double>(b.sample.t_host - a.sample.t_host);
    ImuHistoryEntry n;
    n.sample = a.sample;
    n.sample.t_host = t;
    n.sample.gyro_radps_imu =
        a.sample.gyro_radps_imu + s * (b.sample.gyro_radps_imu - a.sample.gyro_radps_imu);
    n.sample.accel_mps2_imu =
        a.sample.accel_mps2_imu + s * (b.sample.accel_mps2_imu - a.sample.accel_mps2_imu);
    n.reading = lerp(a.reading, b.reading, s);
    n.state = integrateStep(a.state, a.reading, n.reading, toSeconds(t - a.sample.t_host), gravity);
    n.state.t = t;
    entries_.insert(entries_.begin() + static_cast<std::ptrdiff_t>(k + 1), n);
    return k + 1;
}

Result<NavState> ImuHistory::stateAt(TimeNs t, TimeNs max_extrapolation,
                                     const Eigen::Vector3d& gravity) const {
    if (entries_.empty()) {
        return Status(StatusCode::kNotFound,
                      "IMU prediction: no state yet (not aligned or no samples)");
    }
    if (t < front() || t > back() + max_extrapolation) {
        return Status(StatusCode::kNotFound,
                      "IMU prediction: t=" + std::to_string(t) +
                          " ns is outside the IMU history [" + std::to_string(front()) + ", " +
                          std::to_string(back()) +
                          "] ns; widen imu horizon_s or query closer to the newest sample");
    }
    const std::size_t k = indexAtOrBefore(t);
    const ImuHistoryEntry& e = entries_[k];
    if (e.sample.t_host == t) return e.state;
    ImuReading r1 = e.reading;
    if (k + 1 < entries_.size()) {
        const ImuHistoryEntry& n = entries_[k + 1];
        const double s = static_cast<double>(t - e.sample.t_host) /
                         static_cast<double>(n.sample.t_host - e.sample.t_host);
        r1 = lerp(e.reading, n.reading, s);
    }
    NavState x = integrateStep(e.state, e.reading, r1, toSeconds(t - e.sample.t_host), gravity);
    x.t = t;
    return x;
}

ImuReading ImuHistory::readingAt(TimeNs t, const ImuBiases& b) const {
    const std::size_t k = indexAtOrBefore(t);
    ImuReading r0 = correctBiases(entries_[k].sample, b);
    if (k + 1 >= entries_.size() || entries_[k].sample.t_host >= t) return r0;
    const ImuReading r1 = correctBiases(entries_[k + 1].sample, b);
    const double s = static_cast<double>(t - entries_[k].sample.t_host) /
                     static_cast<double>(entries_[k + 1].sample.t_host - entries_[k].sample.t_host);
    return lerp(r0, r1, s);
}

Result<Preintegrated> ImuHistory::preintegrate(TimeNs t0, TimeNs t1, const ImuBiases& b) const {
    if (entries_.empty() || t0 < front() || t1 > back() || t1 < t0) {
        return Status(StatusCode::kNotFound, "IMU preintegration: interval [" + std::to_string(t0) +
                                                 ", " + std::to_string(t1) +
                                                 "] ns is not inside the IMU history");
    }
    Preintegrator pre(b);
    TimeNs t = t0;
    ImuReading r = readingAt(t0, b);
    for (std::size_t k = indexAtOrBefore(t0) + 1; k < entries_.size() && t < t1; ++k) {
        const TimeNs tk = std::min(entries_[k].sample.t_host, t1);
        const ImuReading rk = tk == entries_[k].sample.t_host ? correctBiases(entries_[k].sample, b)
                                                              : readingAt(tk, b);
        pre.add(r, rk, toSeconds(tk - t));
        t = tk;
        r = rk;
    }
    return pre.result();
}

}  // namespace handscan::imu
