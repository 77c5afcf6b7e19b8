// LaserOdometry: the scan matching subsystem of section 6 end to end, with a plain config struct
// (as KISS-ICP does). Feed assembled sweeps; each comes back with the refined body pose at its
// start, the per-DOF solved mask of section 8 and timing. The prior is eq. (16): the last refined
// pose composed with the odometry's motion since then, unless the caller passes its own (e.g. the
// eq. (22) combination of VIO and IMU). Sweeps are matched synchronously (deterministic, for
// replay and tests) or on up to four matcher threads (section 6.4): a sweep goes to the first idle
// matcher and is matched against the latest map available, so when one sweep takes longer than
// the sweep period the next one runs beside it on the second core.
#pragma once

#include <Eigen/Geometry>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/scan/feature_extractor.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/scan/sweep.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::scan {

struct LaserOdometryConfig {
    FeatureConfig features;
    VoxelMapConfig map;
    ScanMatcherConfig matcher;
    // Prior of eq. (17)/(18) when the caller gives none: standard deviations of the odometry's
    // pose error since the last refined sweep.
    double prior_sigma_rot_rad = 0.02;
    double prior_sigma_trans_m = 0.05;
    int max_threads = 1;         // matcher threads for submit(); 1..4 (the paper's maximum)
    std::size_t max_queued = 4;  // sweeps waiting for a free matcher before the oldest is dropped
};

// pose.solved_dof_mask and pose.covariance are in world axes (rx ry rz about, tx ty tz along the
// world axes), the convention of the IMU predictor's feedback; match.degeneracy is the matcher's
// own body-frame analysis.
struct SweepResult {
    std::uint64_t sweep_index = 0;
    PoseEstimate pose;  // body pose at the sweep's start, solved mask, covariance
    Matrix6d solved_projector_world = Matrix6d::Zero();  // V^-1 Vbar of eq. (21) in world axes
    Eigen::Isometry3d T_world_prior = Eigen::Isometry3d::Identity();
    MatchResult match;
    bool first_sweep = false;  // no map yet: pose = prior, nothing solved
    bool merged = false;       // merged into the map (the merge gate let it in)
    // The sweep's features (body frame at its start): a localizer on a prior map (section 9)
    // stacks them; shared, so copying the result stays cheap.
    std::shared_ptr<const FeatureCloud> features;
    std::size_t edges = 0;  // features extracted
    std::size_t planars = 0;
    std::size_t local_map_points = 0;  // |Q_{m-1}|
    std::uint64_t map_sweeps = 0;      // sweeps merged into the map this one was matched against
    int matcher_thread = 0;
    double features_ms = 0.0;
    double extract_ms = 0.0;  // rolling + fine voxels + k-d trees
    double match_ms = 0.0;
    double merge_ms = 0.0;
    double total_ms = 0.0;
};

// Decides after a sweep's match, before the merge, whether the sweep joins the map (e.g. the
// tracking monitor: a diverging estimate must not fill the map with garbage).
using MergeGate = std::function<bool(const SweepResult&)>;

class LaserOdometry {
public:
    explicit LaserOdometry(const LaserOdometryConfig& config = {});
    ~LaserOdometry();
    LaserOdometry(const LaserOdometry&) = delete;
    LaserOdometry& operator=(const LaserOdometry&) = delete;

    // Synchronous: matches `sweep` against the map of every earlier sweep, then merges it unless
    // `gate` refuses.
    SweepResult process(const Sweep& sweep,
                        const std::optional<std::vector<PosePrior>>& priors = std::nullopt,
                        const MergeGate& gate = {});

    // Asynchronous (6.4): returns at once; results come from poll() in sweep order.
    void submit(Sweep sweep, std::optional<std::vector<PosePrior>> priors = std::nullopt);
    std::vector<SweepResult> poll();
    // Blocks until every submitted sweep is finished, then returns what poll() would.
    std::vector<SweepResult> drain();
    std::uint64_t droppedSweeps() const;

    // The registered map (edge and planar points, world frame) and its size.
    std::vector<Eigen::Vector3f> mapPoints() const;
    // The map's points by kind, with the planar points' origins (a later session's prior map).
    FeatureMapPoints featureMap() const;
    VoxelMapStats mapStats() const;
    const LaserOdometryConfig& config() const { return config_; }

private:
    struct Job {
        Sweep sweep;
        std::optional<std::vector<PosePrior>> priors;
    };
    struct Worker {
        std::thread thread;
        std::optional<Job> job;
    };

    SweepResult run(const Sweep& sweep, const std::optional<std::vector<PosePrior>>& priors,
                    int thread, const MergeGate& gate = {});
    void workerLoop(int id);
    void startWorkers();

    LaserOdometryConfig config_;
    ScanMatcher matcher_;

    mutable std::mutex map_mutex_;  // guards map_ and the last refined pose
    VoxelMap map_;
    std::uint64_t map_sweeps_ = 0;
    bool have_refined_ = false;
    std::uint64_t refined_index_ = 0;
    Eigen::Isometry3d T_world_refined_ = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_world_refined_odom_ = Eigen::Isometry3d::Identity();

    mutable std::mutex jobs_mutex_;  // guards everything below
    std::condition_variable jobs_cv_;
    std::condition_variable done_cv_;
    std::vector<std::unique_ptr<Worker>> workers_;
    std::deque<Job> queued_;
    std::map<std::uint64_t, SweepResult> finished_;
    std::map<std::uint64_t, int> in_flight_;  // sweep index -> 1 while queued or running
    std::uint64_t dropped_ = 0;
    bool stopping_ = false;
};

}  // namespace handscan::scan
