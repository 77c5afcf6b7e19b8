#include "handscan/localize/near_cells.hpp"

#include <cmath>

namespace handscan::localize {
namespace {

// A cell's place in its brick: the word (z) and the bit (y, x).
int wordOf(const scan::VoxelKey& local) { return local.z(); }
int bitOf(const scan::VoxelKey& local) { return local.y() * 8 + local.x(); }

}  // namespace

NearCells::NearCells(const std::vector<Eigen::Vector3f>& edges,
                     const std::vector<Eigen::Vector3f>& planars, double radius_m, double cell_m)
    : radius_m_(radius_m), cell_m_(cell_m), inv_cell_(1.0 / cell_m) {
    for (const Eigen::Vector3f& p : edges)
        if (p.allFinite()) mark(p);
    for (const Eigen::Vector3f& p : planars)
        if (p.allFinite()) mark(p);
}

void NearCells::mark(const Eigen::Vector3f& pf) {
    const Eigen::Vector3d p = pf.cast<double>();
    const scan::VoxelKey lo = scan::voxelOf(p - Eigen::Vector3d::Constant(radius_m_), cell_m_);
    const scan::VoxelKey hi = scan::voxelOf(p + Eigen::Vector3d::Constant(radius_m_), cell_m_);
    const double r2 = radius_m_ * radius_m_;
    for (int z = lo.z(); z <= hi.z(); ++z)
        for (int y = lo.y(); y <= hi.y(); ++y)
            for (int x = lo.x(); x <= hi.x(); ++x) {
                const Eigen::Vector3d centre = (Eigen::Vector3d(x, y, z).array() + 0.5) * cell_m_;
                if ((centre - p).squaredNorm() > r2) continue;
                const scan::VoxelKey k(x, y, z);
                const scan::VoxelKey b = scan::floorDiv(k, kBrick);
                const scan::VoxelKey local = k - b * kBrick;
                bricks_[b][wordOf(local)] |= std::uint64_t{1} << bitOf(local);
            }
}

bool NearCells::near(const Eigen::Vector3d& p) const {
    if (bricks_.empty()) return false;
    const Eigen::Vector3d f = (p * inv_cell_).array().floor();
    // Compared as doubles first: a far (or non-finite) point must not reach the int conversion.
    if (!(f.array().abs() < 1e9).all()) return false;
    const scan::VoxelKey k = f.cast<int>();
    const scan::VoxelKey b = scan::floorDiv(k, kBrick);
    const auto it = bricks_.find(b);
    if (it == bricks_.end()) return false;
    const scan::VoxelKey local = k - b * kBrick;
    return (it->second[wordOf(local)] >> bitOf(local) & 1u) != 0;
}

}  // namespace handscan::localize
