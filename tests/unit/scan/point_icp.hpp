// Reference registration for real-data tests: plain point-to-point ICP as 3DTK's slam6D runs it
// by default (every point, closest model point within a maximal pair distance, closed-form
// rigid alignment of the pairs each iteration, stop when the mean squared pair distance has
// changed by less than epsilon over the last two iterations). Used to tell what a published
// registration is the minimum of; not part of the pipeline.
#pragma once

#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <vector>

namespace handscan::scan::testing {

class PointIcp {
public:
    explicit PointIcp(std::vector<Eigen::Vector3d> model) : cloud_{std::move(model)} {
        tree_ = std::make_unique<Tree>(3, cloud_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    }

    struct Result {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        std::vector<Eigen::Isometry3d> steps;  // the pose after each iteration
        bool converged = false;
    };

    // `scan` in its own frame, `T` its starting pose in the model's frame. `eps_m2` as slam6D's
    // --epsICP (1e-5 cm^2 there).
    Result align(const std::vector<Eigen::Vector3d>& scan, Eigen::Isometry3d T, double max_pair_m,
                 int max_iterations, double eps_m2 = 1e-9) const {
        Result r;
        double ret = 0.0, prev = 0.0, prev2 = 0.0;
        Eigen::Matrix3Xd a(3, static_cast<Eigen::Index>(scan.size()));
        Eigen::Matrix3Xd b(3, static_cast<Eigen::Index>(scan.size()));
        for (int it = 0; it < max_iterations; ++it) {
            prev2 = prev;
            prev = ret;
            Eigen::Index n = 0;
            for (const Eigen::Vector3d& p : scan) {
                const Eigen::Vector3d q = T * p;
                const double qq[3] = {q.x(), q.y(), q.z()};
                std::uint32_t idx = 0;
                double d2 = 0.0;
                if (tree_->knnSearch(qq, 1, &idx, &d2) == 1 && d2 <= max_pair_m * max_pair_m) {
                    a.col(n) = q;
                    b.col(n) = cloud_.pts[idx];
                    ++n;
                }
            }
            if (n < 4) break;
            Eigen::Isometry3d D;
            D.matrix() = Eigen::umeyama(a.leftCols(n), b.leftCols(n), false);
            double sum = 0.0;
            for (Eigen::Index k = 0; k < n; ++k)
                sum += (D * Eigen::Vector3d(a.col(k)) - b.col(k)).squaredNorm();
            ret = sum / static_cast<double>(n);
            T = D * T;
            r.steps.push_back(T);
            if (std::abs(ret - prev) < eps_m2 && std::abs(ret - prev2) < eps_m2) {
                r.converged = true;
                break;
            }
        }
        r.T = T;
        return r;
    }

private:
    struct Points {
        std::vector<Eigen::Vector3d> pts;
        std::size_t kdtree_get_point_count() const { return pts.size(); }
        double kdtree_get_pt(std::size_t i, std::size_t d) const {
            return pts[i][static_cast<int>(d)];
        }
        template <class Box>
        bool kdtree_get_bbox(Box& /*bb*/) const {
            return false;
        }
    };
    using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>,
                                                     Points, 3, std::uint32_t>;
    Points cloud_;
    std::unique_ptr<Tree> tree_;
};

}  // namespace handscan::scan::testing
