// A device's own clock and its transport to the host. Simulation time t (seconds since the start
// of the recording, the "true" time) maps to:
//   host CLOCK_MONOTONIC      host_ns(t) = host_start_ns + t                (the reference)
//   device clock (seconds)    device_s(t) = offset_s + (1 + drift_ppm * 1e-6) * t
//   host receive time         host_ns(t_sent + latency_s + jitter), jitter >= 0 (exponential):
//                             transports only ever add delay (what ClockMapper's lower-envelope
//                             fit assumes).
#pragma once

#include <cmath>

#include "handscan/core/time.hpp"
#include "handscan/sim/random.hpp"

namespace handscan::sim {

struct ClockModel {
    double offset_s = 0.0;   // device clock reading at t = 0
    double drift_ppm = 0.0;  // device clock runs (1 + drift) fast against the host
    double latency_s = 0.0;  // fixed transport delay
    double jitter_s = 0.0;   // mean of the exponential extra delay

    double deviceSeconds(double t) const { return offset_s + (1.0 + drift_ppm * 1e-6) * t; }
    // Simulation time at which the device clock reads `device_s`.
    double trueSeconds(double device_s) const {
        return (device_s - offset_s) / (1.0 + drift_ppm * 1e-6);
    }
    // Transport delay of one delivery.
    double delay(Rng& rng) const {
        return latency_s + (jitter_s > 0 ? -jitter_s * std::log(1.0 - rng.uniform()) : 0.0);
    }
};

// Host time of simulation time t.
inline TimeNs hostNs(TimeNs host_start_ns, double t) { return host_start_ns + fromSeconds(t); }

}  // namespace handscan::sim
