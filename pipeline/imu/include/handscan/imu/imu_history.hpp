// The last few seconds of IMU samples with the predicted state at each one. The sweep assembler
// asks for the motion at every laser step's time (stateAt interpolates between samples with a
// partial mechanization step, so it is consistent with the integration), and the bias estimator
// re-integrates intervals between feedback poses from the raw samples kept here.
#pragma once

#include <deque>

#include "handscan/core/status.hpp"
#include "handscan/imu/mechanization.hpp"
#include "handscan/imu/preintegration.hpp"

namespace handscan::imu {

struct ImuHistoryEntry {
    ImuSample sample;    // raw, as received
    ImuReading reading;  // bias-corrected with the biases in effect when it was integrated
    NavState state;      // predicted state at sample.t_host
};

class ImuHistory {
public:
    bool empty() const { return entries_.empty(); }
    std::size_t size() const { return entries_.size(); }
    TimeNs front() const { return entries_.front().sample.t_host; }
    TimeNs back() const { return entries_.back().sample.t_host; }
    const ImuHistoryEntry& last() const { return entries_.back(); }
    const ImuHistoryEntry& operator[](std::size_t i) const { return entries_[i]; }
    ImuHistoryEntry& operator[](std::size_t i) { return entries_[i]; }

    void push(const ImuHistoryEntry& e) { entries_.push_back(e); }
    void clear() { entries_.clear(); }
    // Drops entries older than t, keeping one at or before t so that t stays queryable.
    void trimBefore(TimeNs t);
    // Index of the last entry with time <= t (t must be >= front()).
    std::size_t indexAtOrBefore(TimeNs t) const;
    // Index of an entry exactly at t in (front(), back()], inserting one whose raw sample is
    // interpolated when t falls between samples (a feedback time becomes a node of the history,
    // so queries before it keep the old prediction and queries after it see the corrected one).
    std::size_t nodeAt(TimeNs t, const Eigen::Vector3d& gravity);

    // The state at time t in [front(), back() + max_extrapolation]; beyond back() the last reading
    // is held constant.
    Result<NavState> stateAt(TimeNs t, TimeNs max_extrapolation,
                             const Eigen::Vector3d& gravity) const;
    // The bias-corrected reading at t (interpolated between raw samples) under biases b.
    ImuReading readingAt(TimeNs t, const ImuBiases& b) const;
    // IMU-only relative motion over [t0, t1] (both within the history) under biases b.
    Result<Preintegrated> preintegrate(TimeNs t0, TimeNs t1, const ImuBiases& b) const;

private:
    std::deque<ImuHistoryEntry> entries_;
};

}  // namespace handscan::imu
