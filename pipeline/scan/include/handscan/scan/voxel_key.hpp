// Integer voxel coordinates and the floor arithmetic shared by the two voxel levels of 6.3.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>

namespace handscan::scan {

using VoxelKey = Eigen::Vector3i;

struct VoxelKeyHash {
    std::size_t operator()(const VoxelKey& k) const {
        // Three large primes (as in Teschner et al. 2003 spatial hashing).
        return static_cast<std::size_t>(
            (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.x())) * 73856093ULL) ^
            (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.y())) * 19349669ULL) ^
            (static_cast<std::uint64_t>(static_cast<std::uint32_t>(k.z())) * 83492791ULL));
    }
};

inline VoxelKey voxelOf(const Eigen::Vector3d& p, double size) {
    return {static_cast<int>(std::floor(p.x() / size)), static_cast<int>(std::floor(p.y() / size)),
            static_cast<int>(std::floor(p.z() / size))};
}

inline int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

inline VoxelKey floorDiv(const VoxelKey& k, int b) {
    return {floorDiv(k.x(), b), floorDiv(k.y(), b), floorDiv(k.z(), b)};
}

}  // namespace handscan::scan
