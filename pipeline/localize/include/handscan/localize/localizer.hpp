// Localizer: keeps a new session in an earlier session's frame (section 9). The session's own
// odometry runs as usual; every `period_s` (0.5 Hz) the sweeps of the last ~2 s, stacked with the
// odometry's poses (SweepStack), are matched to the prior map's features (PriorMap) by the same
// scan matcher the odometry uses, robust (bisquare) so that moved furniture is an outlier rather
// than a pull. The result is T_prior_odom, the odometry's world in the prior map's frame: the
// session's poses and map points go through it.
//
// The lock: before the first match there is only a hint (the operator's tap, or the prior map's
// start), good to a few metres and tens of degrees. Both sessions are gravity aligned, so the
// search is over x, y and yaw: a grid of candidates around the hint scored by how many stacked
// points find a prior point close by, the best few refined by the matcher; the lock is declared
// when the best refined candidate has most stacked points on the prior map, and no other
// candidate as good lies elsewhere (a symmetric building waits for a view that tells). Until it
// locks nothing of the session enters the map.
//
// Changes: after each match, stacked points far from any prior point although the prior map
// covers their surroundings are counted per change cell (moved furniture, a closed door);
// points with no prior point near at all are new ground (a room the first session did not see).
#pragma once

#include <Eigen/Geometry>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

#include "handscan/core/time.hpp"
#include "handscan/localize/prior_map.hpp"
#include "handscan/localize/sweep_stack.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {

struct LocalizerConfig {
    SweepStackConfig stack;
    double period_s = 2.0;  // one match to the prior map per this (0.5 Hz)
    // The initial search around the hint: positions within this radius on this grid, headings
    // within +-yaw on this step.
    double search_radius_m = 3.0;
    double search_step_m = 0.5;
    double search_yaw_deg = 30.0;
    double search_yaw_step_deg = 5.0;
    int search_points = 400;  // stacked points scored per candidate (evenly picked)
    int refine_candidates = 6;
    // A stacked point is "on the prior map" when a prior point lies this close: the prior's
    // planar density is one point per 0.2 m cell, so a point on a mapped surface has one within
    // ~0.15 m.
    double on_map_m = 0.2;
    // Lock: at least this share of the stacked points on the prior map, and every other refined
    // candidate farther than distinct_m / distinct_deg from it this much lower.
    double lock_min_on_map = 0.6;
    double lock_margin = 0.1;
    double distinct_m = 0.5;
    double distinct_deg = 10.0;
    // After the lock a match is used when this share is on the map and it moves the estimate
    // less than this (the odometry drifts millimetres per period; more is a wrong match).
    double track_min_on_map = 0.5;
    double max_correction_m = 0.3;
    double max_correction_deg = 3.0;
    // Changes: farther than change_m from every prior point with a prior point within covered_m.
    double change_m = 0.3;
    double covered_m = 1.5;
    double change_cell_m = 0.5;
    int change_cell_min_points = 3;  // a cell is reported from this many points up
    scan::ScanMatcherConfig matcher;
};

struct LocalizerStats {
    std::uint64_t attempts = 0;          // matches to the prior map tried
    std::uint64_t lock_attempts = 0;     // of those, initial searches
    std::uint64_t updates = 0;           // tracking matches used
    std::uint64_t rejected_updates = 0;  // tracking matches refused (off the map, too far)
    TimeNs t_lock = 0;                   // sweep time of the lock (0: not locked)
    double lock_on_map = 0.0;            // share of stacked points on the prior map at lock
    double lock_runner_up = 0.0;         // the best distinct other candidate's share
    double last_on_map = 0.0;
    double max_correction_m = 0.0;  // largest tracking correction used
    double sum_correction_m = 0.0;
    double cpu_ms = 0.0;  // time in attempts (thread CPU), total
    double max_attempt_ms = 0.0;
    std::uint64_t points_checked = 0;  // stacked points tested for change
    std::uint64_t changed_points = 0;  // far from the prior map where it is mapped
    std::uint64_t new_points = 0;      // where the prior map has nothing near
};

struct ChangeCell {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    std::uint64_t points = 0;
};

class Localizer {
public:
    // `hint`: the body pose at the session's first sweep in the prior map's frame (TUM order
    // on the command line); none: the prior session's start.
    Localizer(const LocalizerConfig& config, std::shared_ptr<const PriorMap> prior,
              std::optional<Eigen::Isometry3d> hint = std::nullopt);

    // A sweep the odometry matched and the tracking monitor let into its map. Runs a match to
    // the prior map when one is due; true when the estimate changed (a lock or an update).
    bool addSweep(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
                  std::shared_ptr<const scan::FeatureCloud> features);

    bool locked() const { return locked_; }
    // The odometry's world in the prior map's frame (the hint's guess before the lock).
    const Eigen::Isometry3d& priorFromOdom() const { return T_prior_odom_; }
    const LocalizerStats& stats() const { return stats_; }
    // Change cells with at least config.change_cell_min_points points, by position.
    std::vector<ChangeCell> changes() const;
    const PriorMap& prior() const { return *prior_; }
    const LocalizerConfig& config() const { return config_; }

private:
    struct Candidate {
        Eigen::Isometry3d T;
        double score = 0.0;  // share on the map
    };
    // The share of `pts` (body frame) within on_map_m of a prior point at pose T.
    double onMap(const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T) const;
    void tryLock(const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_odom_new);
    bool track(const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_odom_new);
    void recordChanges(const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_prior_new);

    LocalizerConfig config_;
    std::shared_ptr<const PriorMap> prior_;
    std::optional<Eigen::Isometry3d> hint_;
    scan::ScanMatcher matcher_;
    SweepStack stack_;
    bool locked_ = false;
    bool have_first_ = false;
    Eigen::Isometry3d T_prior_odom_ = Eigen::Isometry3d::Identity();
    TimeNs last_attempt_t_ = 0;
    LocalizerStats stats_;
    std::map<std::tuple<int, int, int>, std::uint64_t> change_cells_;  // cell -> points
};

// Every `stride`-th point of a feature cloud, edges and planars together (the search's sample).
std::vector<Eigen::Vector3d> samplePoints(const scan::FeatureCloud& cloud, int count);

}  // namespace handscan::localize
