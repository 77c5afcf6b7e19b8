// VoxelMap: the two-level voxel map of section 6.3 (Figure 10). Level one is a stationary grid of
// coarse voxels M_{m-1} over a fixed window that rolls with the sensor: when the sensor nears the
// window's edge, the voxels on the far side are moved over and their points cleared, so memory
// stays bounded. Level two splits each coarse voxel into fine voxels (a magnitude smaller): before
// matching, the fine voxels occupied by the new features ("green") select the map points Q_{m-1}
// that go into per-voxel k-d trees (LocalMap). Points are kept at constant density: one point per
// leaf cell per feature kind.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "handscan/scan/local_map.hpp"
#include "handscan/scan/voxel_key.hpp"

namespace handscan::scan {

struct VoxelMapConfig {
    double coarse_size_m = 10.0;               // M voxels
    int fine_per_coarse = 10;                  // S^j voxels: 1 m
    Eigen::Vector3i window_voxels{11, 11, 7};  // 110 x 110 x 70 m kept around the sensor
    int roll_margin_voxels = 3;                // roll when the sensor is this close to an edge
    double edge_leaf_m = 0.1;                  // constant density: one edge point per leaf
    double planar_leaf_m = 0.2;                // one planar point per leaf
    int green_dilation = 1;                    // fine voxels around each green one extracted
};

// Every point of the map by kind, with the laser centre that saw each planar point (NaN when
// unknown): what a later session localizes on (section 9).
struct FeatureMapPoints {
    std::vector<Eigen::Vector3f> edges;
    std::vector<Eigen::Vector3f> planars;
    std::vector<Eigen::Vector3f> planar_origins;  // one per planar point
};

struct VoxelMapStats {
    std::size_t points[2] = {0, 0};  // edge, planar points stored
    std::size_t fine_cells = 0;
    std::size_t coarse_voxels_used = 0;
    std::uint64_t truncated_points = 0;  // cleared by rolling (cumulative)
    std::uint64_t rejected_outside = 0;  // insertions outside the window (cumulative)
    std::uint64_t rejected_density = 0;  // insertions into an occupied leaf (cumulative)
    std::size_t memory_bytes = 0;        // approximate heap use of the stored points and cells
};

class VoxelMap {
public:
    explicit VoxelMap(const VoxelMapConfig& config = {});

    // Moves the stationary window so that `sensor_world` stays roll_margin voxels inside it;
    // voxels that leave the window are cleared (map truncation, Figure 10a). Returns the number
    // of points cleared.
    std::size_t recenter(const Eigen::Vector3d& sensor_world);

    // Merges world-frame points at constant density; returns how many were kept. `origins_world`
    // (empty, or one per point): the laser centre that saw each point.
    std::size_t insert(FeatureKind kind, const std::vector<Eigen::Vector3d>& points_world,
                       const std::vector<Eigen::Vector3d>& origins_world = {});

    // Q_{m-1}: map points in the fine voxels occupied by the features (already projected into the
    // world with the best guess of motion), in per-coarse-voxel k-d trees.
    LocalMap extract(const std::vector<Eigen::Vector3d>& edges_world,
                     const std::vector<Eigen::Vector3d>& planars_world) const;

    std::vector<Eigen::Vector3f> points(FeatureKind kind) const;
    // Both kinds with the planar points' origins, in the same order as points().
    FeatureMapPoints featurePoints() const;
    VoxelMapStats stats() const;
    // The most points the window can ever hold (every leaf of every fine voxel filled).
    std::size_t capacityBound() const;
    bool empty() const { return stats_points_[0] + stats_points_[1] == 0; }
    const VoxelMapConfig& config() const { return config_; }

private:
    struct FineCell {
        std::vector<Eigen::Vector3f> pts[2];
        std::vector<Eigen::Vector3f> origins[2];  // per point; NaN when unknown
        std::vector<std::uint64_t> leaves[2];
    };
    struct CoarseVoxel {
        VoxelKey key = VoxelKey::Zero();
        bool used = false;
        std::unordered_map<std::uint32_t, FineCell> cells;
    };

    bool inside(const VoxelKey& coarse) const;
    std::size_t slotOf(const VoxelKey& coarse) const;
    std::size_t clearSlot(CoarseVoxel& v);
    const FineCell* findCell(const VoxelKey& fine) const;

    VoxelMapConfig config_;
    double fine_size_m_;
    int leaves_per_axis_[2];
    std::vector<CoarseVoxel> slots_;
    VoxelKey origin_ = VoxelKey::Zero();  // lower corner of the window (coarse index)
    bool has_origin_ = false;
    std::size_t stats_points_[2] = {0, 0};
    std::uint64_t truncated_ = 0;
    std::uint64_t rejected_outside_ = 0;
    std::uint64_t rejected_density_ = 0;
};

}  // namespace handscan::scan
