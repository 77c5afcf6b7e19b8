#include "handscan/merge/overlap_consistency.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>

namespace handscan::merge {
namespace {

struct Cloud {
    const std::vector<Eigen::Vector3f>& pts;
    std::size_t kdtree_get_point_count() const { return pts.size(); }
    float kdtree_get_pt(std::size_t i, std::size_t d) const { return pts[i][static_cast<int>(d)]; }
    template <class Box>
    bool kdtree_get_bbox(Box& /*bb*/) const {
        return false;
    }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<float, Cloud>, Cloud,
                                                 3, std::uint32_t>;

}  // namespace

Consistency measureConsistency(const std::vector<Eigen::Vector3f>& earlier,
                               const std::vector<Eigen::Vector3f>& later,
                               const ConsistencyOptions& o) {
    Consistency c;
    if (earlier.size() < static_cast<std::size_t>(o.neighbours) || later.empty()) return c;
    const Cloud cloud{earlier};
    Tree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    const auto k = static_cast<std::size_t>(o.neighbours);
    std::vector<std::uint32_t> idx(k);
    std::vector<float> d2(k);
    std::vector<double> dist;
    const double stride =
        std::max(1.0, static_cast<double>(later.size()) / static_cast<double>(o.samples));
    for (double i = 0; i < static_cast<double>(later.size()); i += stride) {
        const Eigen::Vector3f& q = later[static_cast<std::size_t>(i)];
        ++c.sampled;
        if (tree.knnSearch(q.data(), k, idx.data(), d2.data()) < k) continue;
        if (d2[0] > o.overlap_m * o.overlap_m) continue;
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (std::uint32_t j : idx) mean += earlier[j].cast<double>();
        mean /= static_cast<double>(k);
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (std::uint32_t j : idx) {
            const Eigen::Vector3d d = earlier[j].cast<double>() - mean;
            cov += d * d.transpose();
        }
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
        es.computeDirect(cov / static_cast<double>(k));
        if (std::sqrt(std::max(0.0, es.eigenvalues()[0])) > o.max_thickness_m) continue;
        ++c.overlap_points;
        dist.push_back(std::abs(es.eigenvectors().col(0).dot(q.cast<double>() - mean)));
    }
    if (dist.empty()) return c;
    std::sort(dist.begin(), dist.end());
    c.median_m = dist[dist.size() / 2];
    c.p90_m = dist[dist.size() * 9 / 10];
    double sum = 0.0;
    for (double d : dist) sum += d;
    c.mean_m = sum / static_cast<double>(dist.size());
    return c;
}

}  // namespace handscan::merge
