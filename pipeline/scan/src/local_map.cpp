#include "handscan/scan/local_map.hpp"

#include <algorithm>
#include <limits>
#include <nanoflann.hpp>

namespace handscan::scan {
namespace {

struct PointsAdaptor {
    std::vector<Eigen::Vector3d> pts;
    std::size_t kdtree_get_point_count() const { return pts.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const {
        return pts[i][static_cast<int>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box& /*bb*/) const {
        return false;
    }
};

using KdTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointsAdaptor>,
                                        PointsAdaptor, 3, std::uint32_t>;

struct Cloud {
    PointsAdaptor data;
    std::unique_ptr<KdTree> tree;

    void build(std::vector<Eigen::Vector3d> pts) {
        data.pts = std::move(pts);
        if (!data.pts.empty()) {
            tree = std::make_unique<KdTree>(3, data, nanoflann::KDTreeSingleIndexAdaptorParams(10));
        }
    }
};

}  // namespace

struct LocalMap::VoxelTrees {
    Cloud clouds[2];
    std::vector<Eigen::Vector3f> planar_origins;
};

LocalMap::LocalMap(double fine_size_m, int fine_per_coarse)
    : fine_size_m_(fine_size_m), fine_per_coarse_(fine_per_coarse) {}
LocalMap::~LocalMap() = default;
LocalMap::LocalMap(LocalMap&&) noexcept = default;
LocalMap& LocalMap::operator=(LocalMap&&) noexcept = default;

void LocalMap::addVoxel(const VoxelKey& coarse, std::vector<Eigen::Vector3d> edges,
                        std::vector<Eigen::Vector3d> planars,
                        std::vector<Eigen::Vector3f> planar_origins) {
    auto trees = std::make_unique<VoxelTrees>();
    if (planar_origins.size() == planars.size()) trees->planar_origins = std::move(planar_origins);
    counts_[0] += edges.size();
    counts_[1] += planars.size();
    trees->clouds[0].build(std::move(edges));
    trees->clouds[1].build(std::move(planars));
    voxels_[coarse] = std::move(trees);
}

int LocalMap::nearest(FeatureKind kind, const Eigen::Vector3d& query, int k,
                      Eigen::Vector3d* points, double* dist_sq, Eigen::Vector3f* origins) const {
    const VoxelKey coarse = floorDiv(voxelOf(query, fine_size_m_), fine_per_coarse_);
    const auto it = voxels_.find(coarse);
    if (it == voxels_.end()) {
        return 0;
    }
    const Cloud& cloud = it->second->clouds[static_cast<int>(kind)];
    if (!cloud.tree) {
        return 0;
    }
    k = std::min(k, kMaxNeighbours);
    std::uint32_t idx[kMaxNeighbours];
    const double q[3] = {query.x(), query.y(), query.z()};
    const auto found =
        static_cast<int>(cloud.tree->knnSearch(q, static_cast<std::size_t>(k), idx, dist_sq));
    const auto& known = it->second->planar_origins;
    for (int i = 0; i < found; ++i) {
        points[i] = cloud.data.pts[idx[i]];
        if (origins != nullptr) {
            origins[i] = kind == FeatureKind::kPlanar && !known.empty()
                             ? known[idx[i]]
                             : Eigen::Vector3f(Eigen::Vector3f::Constant(
                                   std::numeric_limits<float>::quiet_NaN()));
        }
    }
    return found;
}

}  // namespace handscan::scan
