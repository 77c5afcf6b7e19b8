// Relocaliser: after a failure that leaves the pose unknown (an IMU gap; a loss the matches did
// not recover: TrackingMonitor::awaitingRelocalisation), finds the scanner again on the map it
// built before, with the search a new session uses on an earlier session's map (section 9,
// localize::Localizer): the scan's feature map, frozen at the loss, is the prior map; the lost
// sweeps are stacked with the poses of their own map (LaserInertialOdometry tracks them on a fresh
// LaserOdometry meanwhile), whose frame is the IMU's at the loss: the hint. The search covers a
// few metres and a wide turn about where the loss began (a 2 s IMU gap holds the heading while
// the walker may turn 60 degrees), and locks only where two searches agree. While the operator is
// elsewhere (a room not yet scanned) it does not lock and keeps trying every period; "go back to
// a place already scanned" is what the live status says meanwhile. When it locks, T_map_odom
// carries the lost map's frame onto the scan's map.
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
    // its pose at t on the lost sweeps' own map. The first one of a loss takes `odometry`'s map
    // (the scan's, frozen) as the search's prior. Returns T_map_odom when the search locks (then
    // the next loss starts afresh).
    std::optional<Eigen::Isometry3d> addSweep(const scan::LaserOdometry& odometry, TimeNs t,
                                              const Eigen::Isometry3d& T_odom_body,
                                              std::shared_ptr<const scan::FeatureCloud> features);

private:
    localize::LocalizerConfig config_;
    std::unique_ptr<localize::Localizer> search_;
};

}  // namespace handscan::lio
