#include "handscan/localize/prior_map.hpp"

#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "handscan/scan/voxel_key.hpp"

namespace handscan::localize {

namespace {

struct VoxelPoints {
    std::vector<Eigen::Vector3d> edges, planars;
    std::vector<Eigen::Vector3f> planar_origins;
};

// Calls `fn(key)` for every coarse voxel whose box grown by `margin` holds p.
template <typename Fn>
void forEachReachingVoxel(const Eigen::Vector3d& p, double size, double margin, Fn&& fn) {
    const Eigen::Vector3d lo = (p.array() - margin) / size;
    const Eigen::Vector3d hi = (p.array() + margin) / size;
    for (auto z = static_cast<int>(std::floor(lo.z())); z <= static_cast<int>(std::floor(hi.z()));
         ++z)
        for (auto y = static_cast<int>(std::floor(lo.y()));
             y <= static_cast<int>(std::floor(hi.y())); ++y)
            for (auto x = static_cast<int>(std::floor(lo.x()));
                 x <= static_cast<int>(std::floor(hi.x())); ++x)
                fn(scan::VoxelKey(x, y, z));
}

}  // namespace

PriorMap::PriorMap(const scan::FeatureMapPoints& points, const Eigen::Isometry3d& T_prior_start,
                   const PriorMapConfig& config)
    : points_(points), start_(T_prior_start), voxels_(config.coarse_size_m, 1) {
    std::unordered_map<scan::VoxelKey, VoxelPoints, scan::VoxelKeyHash> per_voxel;
    for (const Eigen::Vector3f& e : points_.edges) {
        const Eigen::Vector3d p = e.cast<double>();
        forEachReachingVoxel(p, config.coarse_size_m, config.margin_m,
                             [&](const scan::VoxelKey& k) { per_voxel[k].edges.push_back(p); });
    }
    const bool origins = points_.planar_origins.size() == points_.planars.size();
    for (std::size_t i = 0; i < points_.planars.size(); ++i) {
        const Eigen::Vector3d p = points_.planars[i].cast<double>();
        forEachReachingVoxel(
            p, config.coarse_size_m, config.margin_m, [&](const scan::VoxelKey& k) {
                VoxelPoints& v = per_voxel[k];
                v.planars.push_back(p);
                v.planar_origins.push_back(
                    origins ? points_.planar_origins[i]
                            : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
            });
    }
    for (auto& [key, v] : per_voxel)
        voxels_.addVoxel(key, std::move(v.edges), std::move(v.planars),
                         std::move(v.planar_origins));
}

double PriorMap::nearestDistance(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector3d nb;
    double d2 = 0.0;
    for (const scan::FeatureKind kind : {scan::FeatureKind::kEdge, scan::FeatureKind::kPlanar}) {
        if (voxels_.nearest(kind, p, 1, &nb, &d2) == 1) best = std::min(best, std::sqrt(d2));
    }
    return best;
}

}  // namespace handscan::localize
