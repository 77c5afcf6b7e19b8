#include "handscan/lio/relocaliser.hpp"

#include "handscan/core/log.hpp"

namespace handscan::lio {

localize::LocalizerConfig relocaliserDefaults() {
    localize::LocalizerConfig c;
    // Three sweeps (1.5 s, a full view all round), placed by the lost sweeps' own odometry
    // (LaserInertialOdometry::matchSweep): placed by the IMU alone after a gap, whose velocity
    // is unknown, one sweep found at best 56 % of its points on the map (48 % elsewhere). An
    // attempt every 1.5 s at most: each costs about a second of CPU, and while the search runs
    // nothing else needs the core (nothing enters the map).
    c.stack.span_s = 1.4;
    c.period_s = 1.5;
    // Positions within 3 m (a 2 s IMU gap at walking speed), headings within +-90 degrees (a
    // walker turning a corner while the IMU was silent; the heading is held across the gap).
    c.search_radius_m = 3.0;
    c.search_yaw_deg = 90.0;
    c.search_yaw_step_deg = 7.5;
    c.search_turns_about_first = true;  // the heading was lost where the gap was
    c.refine_max_steps = 2.0;
    c.search_points = 300;
    // On its own map the scanner's points lie on the map's surfaces to the laser's noise once
    // refined; 0.2 m (a new session's, whose map is another walk's) let the floor and the
    // ceiling alone put a wrong place half a metre along a wall within a few % of the right one.
    // A wrong lock merges a wrong map, staying lost only delays the scan: lock on a clear win.
    c.on_map_m = 0.2;
    c.lock_min_on_map = 0.75;
    // Scored where the map reaches: after a gap the operator has often walked on into rooms
    // not scanned yet, which hold up to half of the stack (40-53 % on the map at best).
    c.score_min_covered = 0.3;
    c.lock_margin = 0.15;
    // ... and the same place twice in a row by 5 % (a corridor's bays alias by 9-11 % in one
    // view; a courtyard's arcade won one search by 15 % three metres from the true place).
    c.confirm_margin = 0.05;
    c.confirm_always = true;
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
