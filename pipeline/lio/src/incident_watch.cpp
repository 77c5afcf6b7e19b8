#include "handscan/lio/incident_watch.hpp"

#include <cmath>
#include <cstdio>

namespace handscan::lio {
namespace {

std::string format(const char* fmt, double a, double b = 0.0) {
    char buf[160];
    std::snprintf(buf, sizeof buf, fmt, a, b);
    return buf;
}

}  // namespace

std::optional<Incident> IncidentWatch::addImu(const ImuSample& s) {
    last_imu_t_ = s.t_host;
    imu_reported_ = false;
    if (!config_.enabled || !s.accel_mps2_imu.allFinite()) return std::nullopt;
    const double f = s.accel_mps2_imu.norm();
    if (f >= config_.free_fall_mps2) {
        falling_since_ = -1;
        fall_reported_ = false;
        return std::nullopt;
    }
    if (falling_since_ < 0) falling_since_ = s.t_host;
    if (fall_reported_ || toSeconds(s.t_host - falling_since_) < config_.free_fall_after_s)
        return std::nullopt;
    fall_reported_ = true;
    return Incident{falling_since_, s.t_host, fusion::LostReason::kDropped,
                    format("free fall: specific force %.1f m/s^2 for %.2f s (the scanner dropped?)",
                           f, toSeconds(s.t_host - falling_since_))};
}

std::optional<Incident> IncidentWatch::addScan(const LaserScan& scan) {
    if (!config_.enabled || scan.size() == 0) return std::nullopt;
    // The IMU: silent while the laser's scans keep coming.
    if (last_imu_t_ > 0 && !imu_reported_ &&
        toSeconds(scan.t_host - last_imu_t_) > config_.imu_silent_after_s) {
        imu_reported_ = true;
        return Incident{last_imu_t_, scan.t_host, fusion::LostReason::kImuSilent,
                        format("no IMU sample for %.2f s while the laser runs (IMU link down?)",
                               toSeconds(scan.t_host - last_imu_t_))};
    }
    std::size_t valid = 0;
    for (float r : scan.ranges_m) valid += std::isfinite(r) ? 1 : 0;
    const double fraction = static_cast<double>(valid) / static_cast<double>(scan.size());
    if (fraction >= config_.blind_valid_fraction) {
        blind_since_ = -1;
        blind_reported_ = false;
        return std::nullopt;
    }
    if (blind_since_ < 0) blind_since_ = scan.t_host;
    if (blind_reported_ || toSeconds(scan.t_host - blind_since_) < config_.blind_after_s)
        return std::nullopt;
    blind_reported_ = true;
    return Incident{blind_since_, scan.t_host, fusion::LostReason::kLaserBlind,
                    format("%.1f %% of the laser's steps returned for %.2f s (window covered?)",
                           100.0 * fraction, toSeconds(scan.t_host - blind_since_))};
}

}  // namespace handscan::lio
