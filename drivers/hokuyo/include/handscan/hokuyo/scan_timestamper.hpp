// ScanTimestamper: host time for every step of a scan from the sensor's 24-bit millisecond scan
// timestamp, and the conversion of a decoded SCIP scan into a handscan::LaserScan.
//
// The sensor clock is mapped onto host CLOCK_MONOTONIC by the core ClockMapper (lower envelope of
// (timestamp, receive time) pairs, drift estimated online, 24-bit wrap every 2^24 ms = 4.66 h).
// The mapped value is the earliest time a frame carrying that timestamp can arrive. We take the
// frame to leave the sensor as soon as its last step is measured (assumption: the SCIP spec does
// not say which instant the timestamp marks; the constant part of any error is a fixed laser-time
// offset that calibration absorbs), so:
//   t(last value)  = map(t_device) - frame_bytes * 8 / link_bps - extra_latency
//   t(first value) = t(last value) - (n_values - 1) * cluster * 60 s / (rpm * ARES)
#pragma once

#include <cstddef>
#include <cstdint>

#include "handscan/core/clock_mapper.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/hokuyo/scip_codec.hpp"
#include "handscan/hokuyo/sensor_parameters.hpp"

namespace handscan::hokuyo {

struct ScanTimingConfig {
    double link_bps = 100e6;      // UTM-30LX-EW: 100BASE-TX
    TimeNs extra_latency_ns = 0;  // any further fixed delay known from calibration
};

class ScanTimestamper {
public:
    explicit ScanTimestamper(ScanTimingConfig config = {});

    // Feeds one (timestamp, receive time of the frame's last byte) pair and returns the host time
    // of the scan's first value.
    TimeNs stamp(std::uint32_t t_device_ms, TimeNs host_rx, std::size_t frame_bytes, int n_values,
                 double value_period_ns);

    const ClockMapper& mapper() const { return mapper_; }

private:
    ScanTimingConfig cfg_;
    ClockMapper mapper_;
};

// A decoded scan as a LaserScan (SI units; values below DMIN or above DMAX become NaN with the raw
// value kept in error_codes). `t_first_value` is the host time of ranges_m[0].
LaserScan toLaserScan(const ScanPayload& scan, const ScanRequest& request,
                      const SensorParameters& params, TimeNs t_first_value);

// Time between consecutive values of a scan requested with `request` (cluster steps apart).
double valuePeriodNs(const ScanRequest& request, const SensorParameters& params);

}  // namespace handscan::hokuyo
