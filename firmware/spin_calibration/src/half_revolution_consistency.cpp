#include "handscan/spin_calibration/half_revolution_consistency.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <map>
#include <nanoflann.hpp>

namespace handscan::calibrate {
namespace {

struct PointCloud {
    std::vector<Eigen::Vector3d> points;
    std::size_t kdtree_get_point_count() const { return points.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const {
        return points[i][static_cast<Eigen::Index>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
        return false;
    }
};
using KdTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, PointCloud>,
                                                   PointCloud, 3, std::uint32_t>;

struct Revolution {
    std::vector<std::uint32_t> first, second;
};

// The plane's neighbours: up to 2 nearest points from each of the nearest scan lines, the lines
// taken in order of their nearest point, until kPlaneNeighbours points from at least 2 lines.
bool pickAcrossLines(std::span<const SpinObservation> obs, const Revolution& rev,
                     std::span<const std::uint32_t> knn, std::span<const double> d2, double max_d2,
                     std::array<std::uint32_t, kPlaneNeighbours>& picked) {
    std::array<std::uint32_t, kPlaneNeighbours> line_of{};
    std::array<int, kPlaneNeighbours> taken{};
    int lines = 0, n = 0;
    for (int pass = 0; pass < 2 && n < kPlaneNeighbours; ++pass) {
        const int per_line = pass == 0 ? 2 : 3;
        for (std::size_t k = 0; k < knn.size() && n < kPlaneNeighbours; ++k) {
            if (d2[k] > max_d2) break;
            const std::uint32_t line = obs[rev.first[knn[k]]].scan;
            int l = 0;
            while (l < lines && line_of[static_cast<std::size_t>(l)] != line) ++l;
            if (l == lines) {
                if (pass == 1 || lines == kPlaneNeighbours) continue;
                line_of[static_cast<std::size_t>(lines++)] = line;
            }
            if (taken[static_cast<std::size_t>(l)] >= per_line) continue;
            if (std::find(picked.begin(), picked.begin() + n, knn[k]) != picked.begin() + n)
                continue;
            ++taken[static_cast<std::size_t>(l)];
            picked[static_cast<std::size_t>(n++)] = knn[k];
        }
    }
    return n == kPlaneNeighbours && lines >= 2;
}

// The second half's planes in one revolution against its first half's points.
void associateRevolution(std::span<const SpinObservation> obs, const PreparedSpin& spin,
                         const Revolution& rev, std::size_t stride, const AssociationOptions& opt,
                         std::vector<HalfPairResidual>& out) {
    if (rev.first.size() < 100 || rev.second.size() < 100) return;
    PointCloud cloud;
    cloud.points.reserve(rev.first.size());
    for (std::uint32_t i : rev.first) cloud.points.push_back(spin.world(obs[i]));
    KdTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    tree.buildIndex();
    const double max_d2 = opt.max_neighbour_m * opt.max_neighbour_m;
    constexpr std::size_t kCandidates = 48;
    std::array<std::uint32_t, kCandidates> knn{};
    std::array<double, kCandidates> d2{};
    for (std::size_t k = 0; k < rev.second.size(); k += stride) {
        const std::uint32_t q = rev.second[k];
        const Eigen::Vector3d p = spin.world(obs[q]);
        const std::size_t found = tree.knnSearch(p.data(), kCandidates, knn.data(), d2.data());
        std::array<std::uint32_t, kPlaneNeighbours> idx{};
        if (!pickAcrossLines(obs, rev, std::span(knn).first(found), std::span(d2).first(found),
                             max_d2, idx))
            continue;
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (std::uint32_t j : idx) mean += cloud.points[j];
        mean /= kPlaneNeighbours;
        Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
        for (std::uint32_t j : idx) {
            const Eigen::Vector3d d = cloud.points[j] - mean;
            cov += d * d.transpose();
        }
        cov /= kPlaneNeighbours;
        const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
        const Eigen::Vector3d ev = eig.eigenvalues();  // ascending
        if (ev[0] > opt.max_thickness_m * opt.max_thickness_m ||
            ev[1] < opt.min_spread_m * opt.min_spread_m)
            continue;
        const Eigen::Vector3d n = eig.eigenvectors().col(0);
        if (std::abs(n.dot(p - mean)) > opt.max_distance_m) continue;
        HalfPairResidual r;
        r.query = q;
        for (int j = 0; j < kPlaneNeighbours; ++j) r.neighbours[j] = rev.first[idx[j]];
        r.normal = n;
        r.revolution = obs[q].revolution;
        out.push_back(r);
    }
}

}  // namespace

std::vector<HalfPairResidual> associateHalves(std::span<const SpinObservation> obs,
                                              const SpinModel& model,
                                              const SpinCorrection::Vector& x,
                                              const AssociationOptions& opt) {
    std::map<std::int32_t, Revolution> revolutions;
    for (std::size_t i = 0; i < obs.size(); ++i) {
        Revolution& r = revolutions[obs[i].revolution];
        (obs[i].half == 0 ? r.first : r.second).push_back(static_cast<std::uint32_t>(i));
    }
    std::size_t second_halves = 0;
    for (const auto& [index, rev] : revolutions) second_halves += rev.second.size();
    const std::size_t stride = std::max<std::size_t>(
        static_cast<std::size_t>(std::max(1, opt.query_stride)),
        (second_halves + opt.max_queries - 1) / std::max<std::size_t>(1, opt.max_queries));
    const PreparedSpin spin = model.prepare(x);
    std::vector<HalfPairResidual> out;
    for (const auto& [index, rev] : revolutions)
        associateRevolution(obs, spin, rev, stride, opt, out);
    return out;
}

void evaluateResiduals(std::span<const SpinObservation> obs, const SpinModel& model,
                       std::span<const HalfPairResidual> residuals, const SpinCorrection::Vector& x,
                       std::vector<double>& r) {
    r.resize(residuals.size());
    const PreparedSpin spin = model.prepare(x);
    for (std::size_t k = 0; k < residuals.size(); ++k) {
        const HalfPairResidual& res = residuals[k];
        Eigen::Vector3d mean = Eigen::Vector3d::Zero();
        for (std::uint32_t j : res.neighbours) mean += spin.world(obs[j]);
        mean /= kPlaneNeighbours;
        r[k] = res.normal.dot(spin.world(obs[res.query]) - mean);
    }
}

}  // namespace handscan::calibrate
