// DisplayVoxelFilter: turns the pipeline's (full-resolution, colourised) map points into the
// display map's append-only chunks: one point per voxel, the first one seen, and only voxels not
// shown yet. Feed every registered sweep; append what comes back with LiveMapWriter::appendPoints.
#pragma once

#include <cstdint>
#include <span>
#include <unordered_set>
#include <vector>

#include "handscan/shm/layout.hpp"

namespace handscan::shm {

class DisplayVoxelFilter {
public:
    explicit DisplayVoxelFilter(float voxel_m = 0.05f) : voxel_m_(voxel_m) {}
    // Points of `points` that fall into voxels not seen before (non-finite points are dropped).
    std::vector<DisplayPoint> add(std::span<const DisplayPoint> points);
    // True (and the voxel marked) if `p` is the first point of its voxel.
    bool insert(const DisplayPoint& p);
    void clear() { voxels_.clear(); }  // with LiveMapWriter::newScan()
    std::size_t voxelCount() const { return voxels_.size(); }
    float voxelSize() const { return voxel_m_; }

private:
    float voxel_m_;
    std::unordered_set<std::uint64_t> voxels_;
};

}  // namespace handscan::shm
