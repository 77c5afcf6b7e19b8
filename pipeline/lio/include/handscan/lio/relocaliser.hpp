// Relocaliser: after a failure that leaves the pose unknown (TrackingMonitor::fail: the IMU
// silent, the laser blinded, the scanner dropped), finds the scanner again on the map it built
// before the failure, with the search a new session uses on an earlier session's map (section 9,
// localize::Localizer): the odometry's own feature map, frozen at the loss, is the prior map; the
// IMU's pose is the hint; each lost sweep's features are stacked with the IMU's poses (matches do
// not correct them while the monitor waits). The search covers a few metres and a wide turn
// about the vertical (a 2 s IMU gap holds the heading while the walker may turn 60 degrees).
// While the operator is elsewhere (a room not yet scanned) it does not lock and keeps trying
// every period; "go back to a place already scanned" is what the live status says meanwhile.
// When it locks, T_map_odom carries the drifted frame of the IMU's poses back onto the map.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>

#include "handscan/localize/localizer.hpp"
#include "handscan/scan/laser_odometry.hpp"

namespace handscan::lio {

// The search's settings for a relocalisation (differs from a new session's: a shorter stack, as
// the scanner is on its own map, where every sweep finds it; a wider heading search).
localize::LocalizerConfig relocaliserDefaults();

class Relocaliser {
public:
    explicit Relocaliser(const localize::LocalizerConfig& config = relocaliserDefaults())
        : config_(config) {}

    // A sweep while the monitor awaits a relocalisation: its features (body frame at t), and
    // the IMU's pose at t. The first one of a loss freezes `odometry`'s map as the search's
    // prior. Returns T_map_odom when the search locks (then the next loss starts afresh).
    std::optional<Eigen::Isometry3d> addSweep(const scan::LaserOdometry& odometry, TimeNs t,
                                              const Eigen::Isometry3d& T_odom_body,
                                              std::shared_ptr<const scan::FeatureCloud> features);

private:
    localize::LocalizerConfig config_;
    std::unique_ptr<localize::Localizer> search_;
};

}  // namespace handscan::lio
