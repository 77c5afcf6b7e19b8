#include "handscan/hokuyo/scan_timestamper.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace handscan::hokuyo {

namespace {

ClockMapperConfig hokuyoClock() {
    ClockMapperConfig c;
    c.counter_bits = 24;  // SCIP timestamps: 4 characters = 24 bits of milliseconds
    c.tick_ns = 1e6;
    return c;
}

}  // namespace

ScanTimestamper::ScanTimestamper(ScanTimingConfig config) : cfg_(config), mapper_(hokuyoClock()) {}

TimeNs ScanTimestamper::stamp(std::uint32_t t_device_ms, TimeNs host_rx, std::size_t frame_bytes,
                              int n_values, double value_period_ns) {
    mapper_.observe(t_device_ms, host_rx);
    const TimeNs arrival = mapper_.toHost(t_device_ms).value_or(host_rx);
    const double transmit_ns =
        cfg_.link_bps > 0 ? static_cast<double>(frame_bytes) * 8e9 / cfg_.link_bps : 0.0;
    const double span_ns = std::max(0, n_values - 1) * value_period_ns;
    return arrival - static_cast<TimeNs>(std::llround(transmit_ns + span_ns)) -
           cfg_.extra_latency_ns;
}

double valuePeriodNs(const ScanRequest& request, const SensorParameters& params) {
    return std::max(request.cluster, 1) * params.stepPeriodNs();
}

LaserScan toLaserScan(const ScanPayload& scan, const ScanRequest& request,
                      const SensorParameters& params, TimeNs t_first_value) {
    LaserScan out;
    const int cluster = std::max(request.cluster, 1);
    out.t_host = t_first_value;
    out.t_device_ms = scan.timestamp_ms;
    out.step_period_ns = static_cast<TimeNs>(std::llround(valuePeriodNs(request, params)));
    out.first_step = request.start_step;
    out.angle_min_rad = params.angleRad(request.start_step);
    out.angle_increment_rad = cluster * params.stepAngleRad();
    const std::size_t n = scan.ranges.size();
    out.ranges_m.resize(n);
    out.error_codes.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t v = scan.ranges[i];
        if (v < static_cast<std::uint32_t>(params.dmin_mm) ||
            v > static_cast<std::uint32_t>(params.dmax_mm)) {
            out.ranges_m[i] = std::numeric_limits<float>::quiet_NaN();
            out.error_codes[i] = static_cast<std::uint16_t>(std::min<std::uint32_t>(v, 0xFFFF));
        } else {
            out.ranges_m[i] = static_cast<float>(v) * 1e-3f;
        }
    }
    out.intensities.reserve(scan.intensities.size());
    for (const std::uint32_t v : scan.intensities) {
        out.intensities.push_back(static_cast<std::uint16_t>(std::min<std::uint32_t>(v, 0xFFFF)));
    }
    return out;
}

}  // namespace handscan::hokuyo
