#include "handscan/shm/display_voxel_filter.hpp"

#include <cmath>

namespace handscan::shm {
namespace {

// 21 bits per axis: +-52 km at 5 cm, more than a hand-held scan covers.
std::uint64_t voxelKey(const DisplayPoint& p, float voxel) {
    const auto q = [voxel](float v) {
        return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / voxel)) +
                                          (1 << 20)) &
               0x1FFFFF;
    };
    return (q(p.x_m) << 42) | (q(p.y_m) << 21) | q(p.z_m);
}

}  // namespace

bool DisplayVoxelFilter::insert(const DisplayPoint& p) {
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) return false;
    return voxels_.insert(voxelKey(p, voxel_m_)).second;
}

std::vector<DisplayPoint> DisplayVoxelFilter::add(std::span<const DisplayPoint> points) {
    std::vector<DisplayPoint> out;
    for (const DisplayPoint& p : points) {
        if (insert(p)) out.push_back(p);
    }
    return out;
}

}  // namespace handscan::shm
