// PriorMap: an earlier session's feature map (the edge and planar points its odometry kept,
// scan::FeatureMapPoints) precomputed in voxels once, so that every localization match only
// queries it (section 9: "edge and planar features of the prior map precomputed in voxels").
// One pair of k-d trees per coarse voxel (scan::LocalMap), each holding its voxel's points and
// those within a margin around it, so a query near a voxel's face sees its neighbours across.
// Where the earlier session's laser looked through empty space (SeenSpace, from each planar
// point's ray back to the laser centre that saw it) is kept beside it for the change report.
// Read-only after construction.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "handscan/localize/near_cells.hpp"
#include "handscan/localize/seen_space.hpp"
#include "handscan/scan/local_map.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::localize {

struct PriorMapConfig {
    double coarse_size_m = 10.0;
    // Points within this distance outside a coarse voxel join its trees: the scan matcher's
    // farthest cluster point (scan::ScanMatcherConfig::max_neighbour_dist_m).
    double margin_m = 1.0;
    SeenSpaceConfig seen;
    // The lock search's fast "a prior point within on_map_m" (NearCells): the localizer's
    // LocalizerConfig::on_map_m, on cells of this size.
    double near_m = 0.2;
    double near_cell_m = 0.1;
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
    // The earlier session's seen-through space (empty when its points carry no laser centres).
    const SeenSpace& seenSpace() const { return seen_; }
    // The surface normal at each planar point, facing the laser that saw it (NaN: none).
    const std::vector<Eigen::Vector3f>& planarNormals() const { return normals_; }
    // The cells within PriorMapConfig::near_m of a prior point (the lock search's grid score).
    const NearCells& nearCells() const { return near_; }

private:
    scan::FeatureMapPoints points_;
    Eigen::Isometry3d start_;
    scan::LocalMap voxels_;
    SeenSpace seen_;
    std::vector<Eigen::Vector3f> normals_;
    NearCells near_;
};

// One pair of k-d trees per coarse voxel over `points`, each also holding the points within the
// margin around it.
scan::LocalMap voxelTrees(const scan::FeatureMapPoints& points, const PriorMapConfig& config);

// The normal of the surface under each planar point (the plane of its nearest planar neighbours
// in `trees`, as the scan matcher fits it), facing the laser centre that saw it; NaN where the
// neighbours make no plane or the centre is unknown.
std::vector<Eigen::Vector3f> surfaceNormals(const scan::LocalMap& trees,
                                            const std::vector<Eigen::Vector3f>& planars,
                                            const std::vector<Eigen::Vector3f>& origins);

}  // namespace handscan::localize
