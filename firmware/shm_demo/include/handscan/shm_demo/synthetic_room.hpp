// A synthetic scan for demos and tests until replay publishes real pipeline output: an operator
// walks a loop through an 8 m x 6 m x 3 m room; the "laser" sees the surfaces within range and
// the display map keeps one point per 5 cm voxel, coloured per surface.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/shm/display_voxel_filter.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::shm_demo {

struct RoomOptions {
    double width_m = 8.0, depth_m = 6.0, height_m = 3.0;
    double walk_speed_mps = 0.6;
    double range_m = 6.0;
    double voxel_m = 0.05;
    std::uint32_t seed = 7;
};

class SyntheticRoom {
public:
    explicit SyntheticRoom(RoomOptions options = {});
    // Device pose after walking for `t_s` seconds (a loop around the room centre, hand height).
    PoseEstimate poseAt(double t_s) const;
    // New display points seen from `pose` when `samples` random surface samples are drawn (points
    // of voxels already in the map are not returned again).
    std::vector<shm::DisplayPoint> observe(const PoseEstimate& pose, int samples);
    void clear() { voxels_.clear(); }
    std::size_t voxelCount() const { return voxels_.voxelCount(); }

private:
    RoomOptions o_;
    std::mt19937 rng_;
    shm::DisplayVoxelFilter voxels_;
};

}  // namespace handscan::shm_demo
