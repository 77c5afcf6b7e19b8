// PriorMap: an earlier session's feature map (the edge and planar points its odometry kept,
// scan::FeatureMapPoints) precomputed in voxels once, so that every localization match only
// queries it (section 9: "edge and planar features of the prior map precomputed in voxels").
// One pair of k-d trees per coarse voxel (scan::LocalMap), each holding its voxel's points and
// those within a margin around it, so a query near a voxel's face sees its neighbours across.
// Read-only after construction.
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "handscan/scan/local_map.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::localize {

struct PriorMapConfig {
    double coarse_size_m = 10.0;
    // Points within this distance outside a coarse voxel join its trees: the scan matcher's
    // farthest cluster point (scan::ScanMatcherConfig::max_neighbour_dist_m).
    double margin_m = 1.0;
};

class PriorMap {
public:
    // `T_prior_start`: where the earlier session started (the first pose of its trajectory),
    // the search centre when a new session gives no hint.
    PriorMap(const scan::FeatureMapPoints& points, const Eigen::Isometry3d& T_prior_start,
             const PriorMapConfig& config = {});

    const scan::LocalMap& voxels() const { return voxels_; }
    const scan::FeatureMapPoints& points() const { return points_; }
    const Eigen::Isometry3d& start() const { return start_; }
    std::size_t size() const { return points_.edges.size() + points_.planars.size(); }
    // Distance from `p` to the nearest prior point of either kind (infinity when none is stored
    // within the voxel's reach).
    double nearestDistance(const Eigen::Vector3d& p) const;

private:
    scan::FeatureMapPoints points_;
    Eigen::Isometry3d start_;
    scan::LocalMap voxels_;
};

}  // namespace handscan::localize
