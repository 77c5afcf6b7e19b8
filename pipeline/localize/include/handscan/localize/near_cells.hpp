// NearCells: the cells of a fine grid (0.1 m) whose centre lies within a radius (the localizer's
// on_map_m) of a prior point, as bits in sparse 8x8x8-cell bricks. The lock search scores
// ~1500 poses of ~400 points each by "is a prior point this close"; a k-d tree answers each in
// microseconds, a bit here in tens of nanoseconds (section 9: the prior map's features
// "precomputed in voxels"). A point is judged by its cell's centre, so it may be up to half a
// cell's diagonal (0.087 m) off the exact answer: good enough to rank grid poses, whose
// positions are 0.5 m apart; the refined candidates the lock is decided on are scored exactly.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {

class NearCells {
public:
    NearCells() = default;
    // Every cell of `cell_m` whose centre is within `radius_m` of one of `points`.
    NearCells(const std::vector<Eigen::Vector3f>& edges,
              const std::vector<Eigen::Vector3f>& planars, double radius_m, double cell_m);

    // Whether p's cell lies within the radius of a point (false when built empty).
    bool near(const Eigen::Vector3d& p) const;
    double radius() const { return radius_m_; }
    double cell() const { return cell_m_; }
    std::size_t bricks() const { return bricks_.size(); }

private:
    static constexpr int kBrick = 8;  // cells per brick edge: a brick's 512 bits in 8 words
    using Bits = std::array<std::uint64_t, kBrick>;
    void mark(const Eigen::Vector3f& p);

    double radius_m_ = 0.0;
    double cell_m_ = 0.1;
    double inv_cell_ = 10.0;
    std::unordered_map<scan::VoxelKey, Bits, scan::VoxelKeyHash> bricks_;
};

}  // namespace handscan::localize
