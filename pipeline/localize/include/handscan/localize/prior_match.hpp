// PriorMatch: one match of stacked sweeps to the prior map (section 9), as a pure function of its
// inputs, so that the Localizer can run it on a thread of its own while the odometry goes on.
// Two kinds: the lock search (a grid over x, y and yaw around the current guess scored by the
// share of stacked points on the prior map, the best few distinct seeds refined by the scan
// matcher; locked when the best is clearly on the map and no distinct other comes close) and the
// tracking match once locked (the matcher from the current estimate, used when it keeps most
// points on the map and moves the estimate little). Both also check the stacked points for
// change in the accepted pose: far from the prior map where the earlier session saw through
// empty space, its rays going into the point's surface (appeared), and hand back the cells the
// stack's rays crossed (for what vanished).
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <map>
#include <optional>
#include <tuple>
#include <utility>
#include <vector>

#include "handscan/localize/localizer_config.hpp"
#include "handscan/localize/prior_map.hpp"
#include "handscan/scan/feature_extractor.hpp"

namespace handscan::localize {

enum class MatchKind { kLock, kTrack };

struct PriorMatchOutcome {
    MatchKind kind = MatchKind::kLock;
    bool accepted = false;  // locked (kLock) or the update is used (kTrack)
    bool cancelled = false;
    // The stacked cloud's pose (body at the newest sweep's start) in the prior map's frame.
    Eigen::Isometry3d T_prior_new = Eigen::Isometry3d::Identity();
    double on_map = 0.0;     // share of the stacked points on the prior map at that pose
    double runner_up = 0.0;  // kLock: the best distinct other candidate's share
    double correction_m = 0.0;
    double cpu_ms = 0.0;  // thread CPU time of the match
    // The change check of an accepted match (see LocalizerConfig::change_m): planar points
    // checked, far from the prior where the earlier session saw through (appeared), far from it
    // where it never looked (new ground).
    std::uint64_t points_checked = 0, changed_points = 0, new_points = 0;
    std::map<std::tuple<int, int, int>, std::uint64_t> change_cells;  // appeared: cell -> points
    std::vector<SeenSpace::Crossing> seen_cells;  // the prior's SeenSpace cells the rays crossed
};

// The lock search around `T_guess` (the stacked cloud's pose as the hint puts it), headings
// turned about `pivot` (prior frame; none: about T_guess). `cancel` (may be null) ends it early
// with `cancelled` set.
PriorMatchOutcome searchLock(const LocalizerConfig& config, const PriorMap& prior,
                             const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_guess,
                             const std::atomic<bool>* cancel = nullptr,
                             const std::optional<Eigen::Vector3d>& pivot = std::nullopt);

// A tracking match from `T_init` (the stacked cloud's pose as the current estimate puts it).
PriorMatchOutcome trackPrior(const LocalizerConfig& config, const PriorMap& prior,
                             const scan::FeatureCloud& stacked, const Eigen::Isometry3d& T_init);

// Translation (m) and rotation (deg) between two poses.
std::pair<double, double> separation(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

// The share of `pts` (body frame) within config.on_map_m of a prior point at pose T (among
// those the prior map covers: config.score_min_covered).
double shareOnMap(const LocalizerConfig& config, const PriorMap& prior,
                  const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T);

// The lock search's grid score: shareOnMap as the prior's NearCells have it (each point judged by
// its cell's centre), where those were built for config.on_map_m; else (or with
// score_min_covered) shareOnMap itself.
double gridShare(const LocalizerConfig& config, const PriorMap& prior,
                 const std::vector<Eigen::Vector3d>& pts, const Eigen::Isometry3d& T);

// `count` points of a feature cloud picked evenly, edges and planars together (the search's
// sample).
std::vector<Eigen::Vector3d> samplePoints(const scan::FeatureCloud& cloud, int count);

}  // namespace handscan::localize
