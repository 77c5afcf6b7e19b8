// LocalMap: the map points around one sweep's features (Q_{m-1} of section 6.3), extracted from
// the fine "green" voxels and stored in one pair of k-d trees (edge, planar) per coarse voxel, so
// a query searches only the tree of the voxel it falls in. Built by VoxelMap::extract, read-only
// afterwards (safe to query from several threads).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <unordered_map>
#include <vector>

#include "handscan/scan/voxel_key.hpp"

namespace handscan::scan {

enum class FeatureKind : int { kEdge = 0, kPlanar = 1 };

class LocalMap {
public:
    static constexpr int kMaxNeighbours = 16;

    LocalMap(double fine_size_m, int fine_per_coarse);
    ~LocalMap();
    LocalMap(LocalMap&&) noexcept;
    LocalMap& operator=(LocalMap&&) noexcept;

    // Builder: the points that queries falling into coarse voxel `coarse` may see.
    // `planar_origins`: empty, or the laser centre that saw each planar point (NaN: unknown).
    void addVoxel(const VoxelKey& coarse, std::vector<Eigen::Vector3d> edges,
                  std::vector<Eigen::Vector3d> planars,
                  std::vector<Eigen::Vector3f> planar_origins = {});

    // The k nearest map points of `kind` to `query` (world frame), closest first; returns how many
    // were found (0 when the query lies outside the extracted region). With `origins`, also the
    // laser centre that saw each planar point (NaN when unknown).
    int nearest(FeatureKind kind, const Eigen::Vector3d& query, int k, Eigen::Vector3d* points,
                double* dist_sq, Eigen::Vector3f* origins = nullptr) const;

    std::size_t size(FeatureKind kind) const { return counts_[static_cast<int>(kind)]; }
    std::size_t voxelCount() const { return voxels_.size(); }

private:
    struct VoxelTrees;
    double fine_size_m_;
    int fine_per_coarse_;
    std::unordered_map<VoxelKey, std::unique_ptr<VoxelTrees>, VoxelKeyHash> voxels_;
    std::size_t counts_[2] = {0, 0};
};

}  // namespace handscan::scan
