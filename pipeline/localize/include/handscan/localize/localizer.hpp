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
// Changes: after each match, stacked points far from any prior point where the earlier session's
// laser saw through empty space are counted per change cell (something appeared: moved
// furniture, a closed door); the stack's rays are kept, and a prior point where this session
// sees through empty space has vanished. Surfaces far from the prior map that the earlier session
// never looked at are new ground (a room it did not see, the far side of a box), not changes.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <tuple>
#include <vector>

#include "handscan/core/time.hpp"
#include "handscan/localize/localizer_config.hpp"
#include "handscan/localize/prior_map.hpp"
#include "handscan/localize/prior_match.hpp"
#include "handscan/localize/sweep_stack.hpp"

namespace handscan::localize {

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
    // How long the match's result came after its stack (sweep time), longest (kWhenReady).
    double max_apply_delay_s = 0.0;
    std::uint64_t points_checked = 0;  // stacked planar points tested for change
    std::uint64_t changed_points = 0;  // far from the prior map where it saw through (appeared)
    std::uint64_t new_points = 0;      // far from the prior map where it never looked
};

enum class ChangeKind {
    kAppeared,  // this session's surface where the earlier session saw through empty space
    kVanished,  // the earlier session's surface where this session sees through empty space
};

struct ChangeCell {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    ChangeKind kind = ChangeKind::kAppeared;
    std::uint64_t points = 0;   // this session's (appeared) or the prior's (vanished) points
    std::uint64_t matches = 0;  // appeared: the matches that found points of it
};

// Before the lock: no match finished yet, or the last one found no lock.
enum class LockState { kSearching, kNotLocked, kLocked };

class Localizer {
public:
    // `hint`: the body pose at the session's first sweep in the prior map's frame (TUM order
    // on the command line; its position and heading count: both sessions are gravity aligned,
    // so the odometry's own tilt is kept); none: the prior session's start.
    Localizer(const LocalizerConfig& config, std::shared_ptr<const PriorMap> prior,
              std::optional<Eigen::Isometry3d> hint = std::nullopt);
    ~Localizer();  // cancels a running match and waits for its thread
    Localizer(const Localizer&) = delete;
    Localizer& operator=(const Localizer&) = delete;

    // A sweep the odometry matched and the tracking monitor let into its map. Applies a finished
    // match (see MatchApply) and starts the next one when due; true when the estimate changed
    // (a lock or an update).
    bool addSweep(TimeNs t_start, const Eigen::Isometry3d& T_odom_body,
                  std::shared_ptr<const scan::FeatureCloud> features);
    // Waits for the running match, if any, and applies it; true when the estimate changed.
    bool settle();
    // Not locked yet: the operator says where they stand now (their tap on the prior map); the
    // search starts again around it from the next sweep (the odometry goes on). False once locked.
    bool placeAt(const Eigen::Isometry3d& hint);

    bool locked() const { return locked_; }
    LockState lockState() const;
    bool matchRunning() const { return running_.valid(); }
    // The odometry's world in the prior map's frame (the hint's guess before the lock).
    const Eigen::Isometry3d& priorFromOdom() const { return T_prior_odom_; }
    const LocalizerStats& stats() const { return stats_; }
    // Change cells with at least config.change_cell_min_points points (appeared ones seen by at
    // least config.change_cell_min_matches matches), appeared first, each kind by position.
    // Goes over the prior's points for what vanished: call it when the report is wanted.
    std::vector<ChangeCell> changes() const;
    // This session's seen-through space so far, in the prior's SeenSpace cells.
    const SeenSpace& seenSpace() const { return seen_; }
    const PriorMap& prior() const { return *prior_; }
    const LocalizerConfig& config() const { return config_; }

private:
    struct Running {
        TimeNs t = 0;  // the newest stacked sweep's start
        Eigen::Isometry3d T_odom_new;
    };
    void launch();
    bool apply(const PriorMatchOutcome& o);
    // A lock search not accepted on its own: true when it and the previous one agree (see
    // LocalizerConfig::confirm_margin).
    bool confirmed(const PriorMatchOutcome& o);

    LocalizerConfig config_;
    std::shared_ptr<const PriorMap> prior_;
    std::optional<Eigen::Isometry3d> hint_;
    SweepStack stack_;
    bool locked_ = false;
    bool have_first_ = false;
    Eigen::Isometry3d T_prior_odom_ = Eigen::Isometry3d::Identity();
    Eigen::Vector3d first_position_odom_ = Eigen::Vector3d::Zero();  // the hint's place
    // The last search's best place for the odometry's world, when it passed confirm_margin
    // but not lock_margin: a lock once the next search agrees.
    std::optional<Eigen::Isometry3d> unconfirmed_;
    TimeNs last_attempt_t_ = 0;
    TimeNs newest_t_ = 0;
    LocalizerStats stats_;
    struct CellCount {
        std::uint64_t points = 0, matches = 0;
    };
    std::map<std::tuple<int, int, int>, CellCount> change_cells_;
    SeenSpace seen_;  // this session's rays of accepted matches, in the prior's cells
    // The match on the localizer's thread (invalid: none running) and what it was started on.
    std::future<PriorMatchOutcome> running_;
    Running running_on_;
    std::atomic<bool> cancel_{false};
};

// The hint as the odometry's world in the prior map's frame: the hint's position and heading
// (its body x axis projected on the horizontal) for the body at T_odom_body, the odometry's tilt
// kept, so that the result only turns about the vertical.
Eigen::Isometry3d priorFromOdomAtHint(const Eigen::Isometry3d& hint,
                                      const Eigen::Isometry3d& T_odom_body);

}  // namespace handscan::localize
