#include "handscan/viz/point_cloud.hpp"

#include <algorithm>
#include <cstring>

namespace handscan::viz {

void appendPointRecord(const journal::MapPoint& p, std::string& out) {
    // An uncoloured point already carries its laser grey (journal::laserGrey).
    const std::uint8_t r = p.r, g = p.g, b = p.b;
    const float xyzi[4] = {p.x, p.y, p.z, static_cast<float>(p.intensity)};
    const std::uint32_t rgb = (std::uint32_t{r} << 16) | (std::uint32_t{g} << 8) | b;
    char record[kPointStride];
    std::memcpy(record, xyzi, sizeof(xyzi));  // the host is little-endian, as the record
    std::memcpy(record + 16, &rgb, sizeof(rgb));
    out.append(record, kPointStride);
}

DisplayMap::DisplayMap(float voxel_m, std::size_t max_points)
    : voxels_(voxel_m), max_points_(std::max<std::size_t>(1, max_points)) {}

void DisplayMap::add(std::span<const journal::MapPoint> points) {
    for (const journal::MapPoint& p : points) {
        if (voxels_.insert(shm::DisplayPoint{p.x, p.y, p.z, 0, 0, 0, 0}))
            appendPointRecord(p, records_);
    }
}

std::size_t DisplayMap::snapshotSize() const { return std::min(size(), max_points_); }

void DisplayMap::snapshot(std::string& out) const {
    const std::size_t n = size();
    if (n <= max_points_) {
        out = records_;
        return;
    }
    // max_points evenly spaced in the order the scan met the voxels, so the map thins smoothly
    // as it grows instead of halving at the budget.
    out.clear();
    out.reserve(max_points_ * kPointStride);
    for (std::size_t j = 0; j < max_points_; ++j) {
        const std::size_t i = j * n / max_points_;  // j n < 2^64 for any map that fits memory
        out.append(records_, i * kPointStride, kPointStride);
    }
}

}  // namespace handscan::viz
