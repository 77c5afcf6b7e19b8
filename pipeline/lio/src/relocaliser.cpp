#include "handscan/lio/relocaliser.hpp"

#include "handscan/core/log.hpp"

namespace handscan::lio {

localize::LocalizerConfig relocaliserDefaults() {
    localize::LocalizerConfig c;
    // One sweep: a half revolution sees the scene all round, and its points are placed by the
    // IMU over half a second only (stacking two smeared them: 60 % on the map against 58 %
    // elsewhere). An attempt every 1.5 s at most: each costs about a second of CPU, and while
    // the search runs nothing else needs the core (nothing enters the map).
    c.stack.span_s = 0.4;
    c.period_s = 1.5;
    // Positions within 3 m (a 2 s IMU gap at walking speed), headings within +-90 degrees (a
    // walker turning a corner while the IMU was silent; the heading is held across the gap).
    c.search_radius_m = 3.0;
    c.search_yaw_deg = 90.0;
    c.search_yaw_step_deg = 7.5;
    c.search_points = 300;
    // On its own map the scanner's points lie on the map's surfaces to the laser's noise once
    // refined; 0.2 m (a new session's, whose map is another walk's) let the floor and the
    // ceiling alone put a wrong place half a metre along a wall within a few % of the right one.
    // A wrong lock merges a wrong map, staying lost only delays the scan: lock on a clear win.
    c.on_map_m = 0.1;
    c.lock_min_on_map = 0.75;
    c.lock_margin = 0.15;
    return c;
}

std::optional<Eigen::Isometry3d> Relocaliser::addSweep(
    const scan::LaserOdometry& odometry, TimeNs t, const Eigen::Isometry3d& T_odom_body,
    std::shared_ptr<const scan::FeatureCloud> features) {
    if (!features) return std::nullopt;
    if (!search_) {
        auto map = std::make_shared<const localize::PriorMap>(odometry.featureMap(), T_odom_body);
        search_ = std::make_unique<localize::Localizer>(config_, std::move(map), T_odom_body);
    }
    const std::uint64_t attempts0 = search_->stats().attempts;
    (void)search_->addSweep(t, T_odom_body, std::move(features));
    if (!search_->locked()) {
        if (search_->stats().attempts > attempts0)
            log().info(
                "relocalisation at {:.2f} s: not found yet ({:.0f} % on the map, another "
                "place {:.0f} %)",
                toSeconds(t), 100.0 * search_->stats().lock_on_map,
                100.0 * search_->stats().lock_runner_up);
        return std::nullopt;
    }
    const Eigen::Isometry3d T_map_odom = search_->priorFromOdom();
    search_.reset();
    return T_map_odom;
}

}  // namespace handscan::lio
