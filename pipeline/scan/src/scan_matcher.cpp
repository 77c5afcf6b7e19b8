#include "handscan/scan/scan_matcher.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "handscan/scan/surface_offset.hpp"

namespace handscan::scan {
namespace {

// A feature's correspondence, fixed during the inner iterations: the distance is measured to the
// line through `c` along `dir` (edge) or to the plane through `c` with normal `dir` (planar).
struct Correspondence {
    Eigen::Vector3d p_body;
    Eigen::Vector3d c;
    Eigen::Vector3d dir;
    bool edge;
};

double robustWeight(RobustKernel kernel, double r, double scale) {
    const double a = std::abs(r);
    switch (kernel) {
        case RobustKernel::kNone:
            return 1.0;
        case RobustKernel::kHuber:
            return a <= scale ? 1.0 : scale / a;
        case RobustKernel::kBisquare: {
            if (a >= scale) {
                return 0.0;
            }
            const double u = 1.0 - (a / scale) * (a / scale);
            return u * u;
        }
    }
    return 1.0;
}

// Thin walls: a point on one face of a wall has the other face's map points within reach, and
// both faces fit the same plane shape, so the match would pull the pose by the wall's thickness.
// The laser centres that saw the map points tell the faces apart: a match is rejected when most
// of its map points were seen from the other side of the plane than the query point.
bool seenFromTheSameSide(const Eigen::Vector3d& normal, const Eigen::Vector3d& c, const Eigen::Vector3f* origins,
                         int n, const Eigen::Vector3d& query_origin, double margin) {
    const double side = normal.dot(query_origin - c);
    if (std::abs(side) < margin) return true;  // sensor (nearly) in the plane: no side to tell
    int same = 0;
    int other = 0;
    for (int i = 0; i < n; ++i) {
        if (!origins[i].allFinite()) continue;
        const double s = normal.dot(origins[i].cast<double>() - c);
        if (std::abs(s) < margin) continue;
        (s * side > 0.0 ? same : other) += 1;
    }
    return other <= same;
}

}  // namespace

double degeneracyEigenvalueThreshold(const ScanMatcherConfig& config) {
    const double r = config.laser_sigma_m / config.degeneracy_max_std_m;
    return r * r;
}

MatchResult ScanMatcher::match(const FeatureCloud& features, const LocalMap& map,
                               const std::vector<PosePrior>& priors,
                               const Eigen::Isometry3d* initial) const {
    MatchResult res;
    Eigen::Isometry3d T = initial != nullptr ? *initial
                          : priors.empty()   ? Eigen::Isometry3d::Identity()
                                             : priors.front().T_world_body;
    res.T_world_body = T;
    const double threshold = degeneracyEigenvalueThreshold(config_);
    res.degeneracy = analyzeDegeneracy(Matrix6d::Zero(), 1.0);  // nothing solved yet
    const int K_edge = std::min(config_.neighbours, LocalMap::kMaxNeighbours);
    const int K_plane = std::min(config_.plane_neighbours, LocalMap::kMaxNeighbours);
    const int K_curv = std::min(config_.curvature_neighbours, LocalMap::kMaxNeighbours);
    SurfaceOffsetLimits curvature_limits;
    curvature_limits.max_rms_m = config_.curvature_max_rms_m;
    const double max_d2 = config_.max_neighbour_dist_m * config_.max_neighbour_dist_m;
    const double inv_sigma2 = 1.0 / (config_.laser_sigma_m * config_.laser_sigma_m);
    std::vector<Correspondence> corr;
    corr.reserve(features.edges.size() + features.planars.size());
    Eigen::Vector3d nb[LocalMap::kMaxNeighbours];
    double d2[LocalMap::kMaxNeighbours];
    Eigen::Vector3f nb_origin[LocalMap::kMaxNeighbours];
    const bool with_origins = features.planar_origins.size() == features.planars.size();

    Matrix6d H_final = Matrix6d::Identity();
    for (int assoc = 0; assoc < config_.max_associations; ++assoc) {
        const double scale = std::max(config_.kernel_scale_m,
                                      config_.kernel_scale_initial_m * std::pow(0.5, assoc));
        // The curvature offset is a millimetre refinement: it waits for the final kernel scale
        // (the extra neighbours cost a third of the matching time when searched every time).
        const int K_curv_now = scale <= config_.kernel_scale_m ? K_curv : 0;
        // Association: clusters of the closest map points, checked by their eigenvalues (6.1).
        corr.clear();
        res.edge_matches = 0;
        res.plane_matches = 0;
        for (int kind = 0; kind < 2; ++kind) {
            const bool edge = kind == 0;
            const auto& pts = edge ? features.edges : features.planars;
            for (std::size_t pi = 0; pi < pts.size(); ++pi) {
                const Eigen::Vector3d& p = pts[pi];
                const Eigen::Vector3d q = T * p;
                const int K = edge ? K_edge : K_plane;
                // Planar: the nearest K fit the plane, up to K_curv (closest first) its curvature.
                const int found = map.nearest(edge ? FeatureKind::kEdge : FeatureKind::kPlanar, q,
                                              edge ? K : std::max(K, K_curv_now), nb, d2, edge ? nullptr : nb_origin);
                const int n = std::min(found, K);
                if (n < K || d2[n - 1] > max_d2) {
                    continue;
                }
                Eigen::Vector3d c = Eigen::Vector3d::Zero();
                for (int i = 0; i < n; ++i) c += nb[i];
                c /= n;
                Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
                for (int i = 0; i < n; ++i) cov += (nb[i] - c) * (nb[i] - c).transpose();
                cov /= n;
                Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
                es.computeDirect(cov);
                const Eigen::Vector3d ev = es.eigenvalues();  // increasing
                if (edge) {
                    // One large, two small eigenvalues: an edge line segment.
                    if (ev[2] < config_.edge_eigen_ratio * ev[1] ||
                        ev[1] > config_.edge_max_thickness_m * config_.edge_max_thickness_m) {
                        continue;
                    }
                    corr.push_back({p, c, es.eigenvectors().col(2), true});
                    ++res.edge_matches;
                } else {
                    // Two large, one small: a local planar patch.
                    if (ev[0] > config_.plane_eigen_ratio * ev[1] ||
                        ev[1] < config_.plane_min_extent_m * config_.plane_min_extent_m) {
                        continue;
                    }
                    const Eigen::Vector3d nrm = es.eigenvectors().col(0);
                    bool thin = true;
                    for (int i = 0; i < n && thin; ++i) {
                        thin = std::abs(nrm.dot(nb[i] - c)) <= config_.plane_max_thickness_m;
                    }
                    if (!thin) continue;
                    if (with_origins && !seenFromTheSameSide(nrm, c, nb_origin, n, T * features.planar_origins[pi],
                                                             config_.view_side_margin_m)) {
                        continue;
                    }
                    // The plane through the surface under the query, not through the cluster's
                    // centroid, which a curved surface moves off it (surface_offset.hpp).
                    int n_curv = n;
                    while (n_curv < found && d2[n_curv] <= max_d2) ++n_curv;
                    const auto offset = K_curv_now > K ? surfaceOffsetAt(nb, n_curv, c, nrm, es.eigenvectors().col(2),
                                                                          es.eigenvectors().col(1), q, curvature_limits)
                                                       : std::nullopt;
                    corr.push_back({p, offset ? Eigen::Vector3d(c + *offset * nrm) : c, nrm, false});
                    ++res.plane_matches;
                }
            }
        }
        ++res.associations;
        if (static_cast<int>(corr.size()) < config_.min_correspondences) {
            res.enough_matches = false;
            res.T_world_body = initial != nullptr ? *initial : (priors.empty() ? T : priors.front().T_world_body);
            res.degeneracy = analyzeDegeneracy(Matrix6d::Zero(), 1.0);
            return res;
        }
        res.enough_matches = true;

        const Eigen::Isometry3d T_assoc = T;
        bool converged = false;
        for (int it = 0; it < config_.max_iterations; ++it) {
            Matrix6d JtJ = Matrix6d::Zero();   // sum w J^T J: the laser constraints alone
            Vector6d Jtr = Vector6d::Zero();
            double wsum = 0.0;
            double wr2 = 0.0;
            const Eigen::Matrix3d R = T.linear();
            for (const Correspondence& m : corr) {
                const Eigen::Vector3d q = T * m.p_body;
                const Eigen::Vector3d d = q - m.c;
                double r;
                Eigen::Vector3d grad;  // d r / d q
                if (m.edge) {
                    // eq. (14): distance to the line; its gradient is the unit perpendicular.
                    const Eigen::Vector3d perp = d - m.dir * m.dir.dot(d);
                    r = perp.norm();
                    if (r < 1e-9) continue;
                    grad = perp / r;
                } else {
                    // eq. (15): signed distance to the plane.
                    r = m.dir.dot(d);
                    grad = m.dir;
                }
                const double w = robustWeight(config_.kernel, r, scale);
                if (w <= 0.0) continue;
                // Right perturbation T exp(xi), xi = (w, v): dq/dw = -R [p]x, dq/dv = R.
                Eigen::Matrix<double, 1, 6> J;
                J.leftCols<3>() = -grad.transpose() * R * skew(m.p_body);
                J.rightCols<3>() = grad.transpose() * R;
                JtJ.noalias() += w * J.transpose() * J;
                Jtr.noalias() += w * J.transpose() * r;
                wsum += w;
                wr2 += w * r * r;
            }
            res.rms_m = wsum > 0.0 ? std::sqrt(wr2 / wsum) : 0.0;
            Matrix6d H = JtJ * inv_sigma2;
            Vector6d g = Jtr * inv_sigma2;
            for (const PosePrior& prior : priors) {
                // eqs. (17)-(18): the prior pose error, weighted by its information.
                const Vector6d e = logSE3(prior.T_world_body.inverse() * T);
                H += prior.information;
                g += prior.information * e;
            }
            Vector6d dx = -H.ldlt().solve(g);  // eq. (20)
            res.degeneracy = analyzeDegeneracy(JtJ, threshold);
            dx = res.degeneracy.projection * dx;  // eq. (21): move only in solved directions
            T = T * expSE3(dx);
            T.linear() = orthonormalize(T.linear());
            H_final = H;
            ++res.iterations;
            if (dx.head<3>().norm() < config_.converged_rot_rad && dx.tail<3>().norm() < config_.converged_trans_m) {
                converged = true;
                break;
            }
        }
        res.converged = converged;
        const Vector6d moved = logSE3(T_assoc.inverse() * T);
        if (converged && moved.head<3>().norm() < 10 * config_.converged_rot_rad &&
            moved.tail<3>().norm() < 10 * config_.converged_trans_m) {
            break;  // a fresh association barely moved the pose: the correspondences are stable
        }
    }
    res.T_world_body = T;
    res.covariance = H_final.inverse();
    return res;
}

}  // namespace handscan::scan
