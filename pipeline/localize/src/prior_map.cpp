#include "handscan/localize/prior_map.hpp"

#include <Eigen/Eigenvalues>
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

bool finite(const Eigen::Vector3f& v) { return v.allFinite(); }

// The earlier session's rays: each planar point back to the laser centre that saw it, over the
// box holding both.
SeenSpace seenThrough(const scan::FeatureMapPoints& m, const SeenSpaceConfig& config) {
    if (m.planar_origins.size() != m.planars.size()) return {};
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i < m.planars.size(); ++i) {
        if (!finite(m.planar_origins[i])) continue;
        box.extend(m.planars[i].cast<double>());
        box.extend(m.planar_origins[i].cast<double>());
    }
    if (box.isEmpty()) return {};
    box.extend(
        Eigen::Vector3d(box.min().array() - 1.0));  // a margin for the stacked points just outside
    box.extend(Eigen::Vector3d(box.max().array() + 1.0));
    SeenSpace seen(box, config);
    std::vector<SeenSpace::Crossing> cells;
    for (std::size_t i = 0; i < m.planars.size(); ++i) {
        if (!finite(m.planar_origins[i])) continue;
        cells.clear();
        seen.cellsAlong(m.planar_origins[i].cast<double>(), m.planars[i].cast<double>(), cells);
        seen.add(cells);
    }
    return seen;
}

}  // namespace

scan::LocalMap voxelTrees(const scan::FeatureMapPoints& points, const PriorMapConfig& config) {
    std::unordered_map<scan::VoxelKey, VoxelPoints, scan::VoxelKeyHash> per_voxel;
    for (const Eigen::Vector3f& e : points.edges) {
        const Eigen::Vector3d p = e.cast<double>();
        forEachReachingVoxel(p, config.coarse_size_m, config.margin_m,
                             [&](const scan::VoxelKey& k) { per_voxel[k].edges.push_back(p); });
    }
    const bool origins = points.planar_origins.size() == points.planars.size();
    for (std::size_t i = 0; i < points.planars.size(); ++i) {
        const Eigen::Vector3d p = points.planars[i].cast<double>();
        forEachReachingVoxel(
            p, config.coarse_size_m, config.margin_m, [&](const scan::VoxelKey& k) {
                VoxelPoints& v = per_voxel[k];
                v.planars.push_back(p);
                v.planar_origins.push_back(
                    origins ? points.planar_origins[i]
                            : Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
            });
    }
    scan::LocalMap trees(config.coarse_size_m, 1);
    for (auto& [key, v] : per_voxel)
        trees.addVoxel(key, std::move(v.edges), std::move(v.planars), std::move(v.planar_origins));
    return trees;
}

std::vector<Eigen::Vector3f> surfaceNormals(const scan::LocalMap& trees,
                                            const std::vector<Eigen::Vector3f>& planars,
                                            const std::vector<Eigen::Vector3f>& origins) {
    // The scan matcher's planar patch (ScanMatcherConfig: 8 neighbours within 1 m, the smallest
    // eigenvalue under a tenth of the middle one).
    constexpr int kNeighbours = 8;
    constexpr double kMaxDist2 = 1.0;
    constexpr double kFlatness = 0.1;
    const Eigen::Vector3f none = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
    std::vector<Eigen::Vector3f> out(planars.size(), none);
    if (origins.size() != planars.size()) return out;
    Eigen::Vector3d nb[kNeighbours];
    double d2[kNeighbours];
    for (std::size_t i = 0; i < planars.size(); ++i) {
        const Eigen::Vector3d p = planars[i].cast<double>();
        const Eigen::Vector3d o = origins[i].cast<double>();
        if (!o.allFinite()) continue;
        const int n = trees.nearest(scan::FeatureKind::kPlanar, p, kNeighbours, nb, d2);
        if (n < kNeighbours || d2[n - 1] > kMaxDist2) continue;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (int k = 0; k < n; ++k) c += nb[k];
        c /= n;
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (int k = 0; k < n; ++k) cov += (nb[k] - c) * (nb[k] - c).transpose();
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
        es.computeDirect(cov / n);
        if (es.eigenvalues()[0] > kFlatness * es.eigenvalues()[1]) continue;
        Eigen::Vector3d nrm = es.eigenvectors().col(0);
        if (nrm.dot(o - p) < 0.0) nrm = -nrm;  // facing the laser that saw it
        out[i] = nrm.cast<float>();
    }
    return out;
}

PriorMap::PriorMap(const scan::FeatureMapPoints& points, const Eigen::Isometry3d& T_prior_start,
                   const PriorMapConfig& config)
    : points_(points),
      start_(T_prior_start),
      voxels_(voxelTrees(points, config)),
      seen_(seenThrough(points, config.seen)),
      normals_(surfaceNormals(voxels_, points_.planars, points_.planar_origins)),
      near_(points_.edges, points_.planars, config.near_m, config.near_cell_m) {}

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
