#include "handscan/scan/scan_matcher.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <optional>

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
bool seenFromTheSameSide(const Eigen::Vector3d& normal, const Eigen::Vector3d& c,
                         const Eigen::Vector3f* origins, int n, const Eigen::Vector3d& query_origin,
                         double margin) {
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

// Association (6.1): for each feature at pose T, the cluster of its closest map points, checked
// by its eigenvalues; `corr` is overwritten. With `curvature`, planar matches measure to the
// surface under the query (surface_offset.hpp), a millimetre refinement for the final kernel
// scale (the extra neighbours cost a third of the matching time when searched every time).
void associate(const ScanMatcherConfig& config, const FeatureCloud& features, const LocalMap& map,
               const Eigen::Isometry3d& T, bool curvature, std::vector<Correspondence>& corr,
               int& edges, int& planes) {
    const int K_edge = std::min(config.neighbours, LocalMap::kMaxNeighbours);
    const int K_plane = std::min(config.plane_neighbours, LocalMap::kMaxNeighbours);
    const int K_curv =
        curvature ? std::min(config.curvature_neighbours, LocalMap::kMaxNeighbours) : 0;
    SurfaceOffsetLimits curvature_limits;
    curvature_limits.max_rms_m = config.curvature_max_rms_m;
    const double max_d2 = config.max_neighbour_dist_m * config.max_neighbour_dist_m;
    Eigen::Vector3d nb[LocalMap::kMaxNeighbours];
    double d2[LocalMap::kMaxNeighbours];
    Eigen::Vector3f nb_origin[LocalMap::kMaxNeighbours];
    const bool with_origins = features.planar_origins.size() == features.planars.size();
    corr.clear();
    edges = 0;
    planes = 0;
    for (int kind = 0; kind < 2; ++kind) {
        const bool edge = kind == 0;
        const auto& pts = edge ? features.edges : features.planars;
        for (std::size_t pi = 0; pi < pts.size(); ++pi) {
            const Eigen::Vector3d& p = pts[pi];
            const Eigen::Vector3d q = T * p;
            const int K = edge ? K_edge : K_plane;
            // Planar: the nearest K fit the plane, up to K_curv (closest first) its curvature.
            const int found =
                map.nearest(edge ? FeatureKind::kEdge : FeatureKind::kPlanar, q,
                            edge ? K : std::max(K, K_curv), nb, d2, edge ? nullptr : nb_origin);
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
                if (ev[2] < config.edge_eigen_ratio * ev[1] ||
                    ev[1] > config.edge_max_thickness_m * config.edge_max_thickness_m) {
                    continue;
                }
                corr.push_back({p, c, es.eigenvectors().col(2), true});
                ++edges;
            } else {
                // Two large, one small: a local planar patch.
                if (ev[0] > config.plane_eigen_ratio * ev[1] ||
                    ev[1] < config.plane_min_extent_m * config.plane_min_extent_m) {
                    continue;
                }
                const Eigen::Vector3d nrm = es.eigenvectors().col(0);
                bool thin = true;
                for (int i = 0; i < n && thin; ++i) {
                    thin = std::abs(nrm.dot(nb[i] - c)) <= config.plane_max_thickness_m;
                }
                if (!thin) continue;
                if (with_origins &&
                    !seenFromTheSameSide(nrm, c, nb_origin, n, T * features.planar_origins[pi],
                                         config.view_side_margin_m)) {
                    continue;
                }
                // The plane through the surface under the query, not through the cluster's
                // centroid, which a curved surface moves off it (surface_offset.hpp).
                int n_curv = n;
                while (n_curv < found && d2[n_curv] <= max_d2) ++n_curv;
                const auto offset =
                    K_curv > K ? surfaceOffsetAt(nb, n_curv, c, nrm, es.eigenvectors().col(2),
                                                 es.eigenvectors().col(1), q, curvature_limits)
                               : std::nullopt;
                corr.push_back({p, offset ? Eigen::Vector3d(c + *offset * nrm) : c, nrm, false});
                ++planes;
            }
        }
    }
}

// The laser normal equations at pose T: sum w J^T J and sum w J^T r over the correspondences,
// with robust weights of the given scale.
struct NormalEquations {
    Matrix6d JtJ = Matrix6d::Zero();
    Vector6d Jtr = Vector6d::Zero();
    double wsum = 0.0;
    double wr2 = 0.0;
};

NormalEquations accumulate(const ScanMatcherConfig& config, const std::vector<Correspondence>& corr,
                           const Eigen::Isometry3d& T, double scale) {
    NormalEquations ne;
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
        const double w = robustWeight(config.kernel, r, scale);
        if (w <= 0.0) continue;
        // Right perturbation T exp(xi), xi = (w, v): dq/dw = -R [p]x, dq/dv = R.
        Eigen::Matrix<double, 1, 6> J;
        J.leftCols<3>() = -grad.transpose() * R * skew(m.p_body);
        J.rightCols<3>() = grad.transpose() * R;
        ne.JtJ.noalias() += w * J.transpose() * J;
        ne.Jtr.noalias() += w * J.transpose() * r;
        ne.wsum += w;
        ne.wr2 += w * r * r;
    }
    return ne;
}

}  // namespace

double degeneracyEigenvalueThreshold(const ScanMatcherConfig& config) {
    const double r = config.laser_sigma_m / config.degeneracy_max_std_m;
    return r * r;
}

double degeneracyProbeEigenvalueThreshold(const ScanMatcherConfig& config) {
    const double r = config.laser_sigma_m / config.degeneracy_probe_max_std_m;
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
    const double inv_sigma2 = 1.0 / (config_.laser_sigma_m * config_.laser_sigma_m);
    std::vector<Correspondence> corr;
    corr.reserve(features.edges.size() + features.planars.size());

    Matrix6d H_final = Matrix6d::Identity();
    // Gauss-Newton on the fixed correspondences; true when it converged.
    auto iterate = [&](double eigenvalue_threshold, double scale) {
        for (int it = 0; it < config_.max_iterations; ++it) {
            const NormalEquations ne = accumulate(config_, corr, T, scale);
            const Matrix6d& JtJ = ne.JtJ;  // sum w J^T J: the laser constraints alone
            res.rms_m = ne.wsum > 0.0 ? std::sqrt(ne.wr2 / ne.wsum) : 0.0;
            Matrix6d H = JtJ * inv_sigma2;
            Vector6d g = ne.Jtr * inv_sigma2;
            for (const PosePrior& prior : priors) {
                // eqs. (17)-(18): the prior pose error, weighted by its information.
                const Vector6d e = logSE3(prior.T_world_body.inverse() * T);
                H += prior.information;
                g += prior.information * e;
            }
            Vector6d dx = -H.ldlt().solve(g);  // eq. (20)
            res.degeneracy = analyzeDegeneracy(JtJ, eigenvalue_threshold);
            dx = res.degeneracy.projection * dx;  // eq. (21): move only in solved directions
            T = T * expSE3(dx);
            T.linear() = orthonormalize(T.linear());
            H_final = H;
            ++res.iterations;
            if (dx.head<3>().norm() < config_.converged_rot_rad &&
                dx.tail<3>().norm() < config_.converged_trans_m) {
                return true;
            }
        }
        return false;
    };

    for (int assoc = 0; assoc < config_.max_associations; ++assoc) {
        const double scale =
            std::max(config_.kernel_scale_m, config_.kernel_scale_initial_m * std::pow(0.5, assoc));
        associate(config_, features, map, T, scale <= config_.kernel_scale_m, corr,
                  res.edge_matches, res.plane_matches);
        ++res.associations;
        if (static_cast<int>(corr.size()) < config_.min_correspondences) {
            res.enough_matches = false;
            res.T_world_body =
                initial != nullptr ? *initial : (priors.empty() ? T : priors.front().T_world_body);
            res.degeneracy = analyzeDegeneracy(Matrix6d::Zero(), 1.0);
            return res;
        }
        res.enough_matches = true;

        const Eigen::Isometry3d T_assoc = T;
        res.converged = iterate(threshold, scale);
        const Vector6d moved = logSE3(T_assoc.inverse() * T);
        if (res.converged && moved.head<3>().norm() < 10 * config_.converged_rot_rad &&
            moved.tail<3>().norm() < 10 * config_.converged_trans_m) {
            break;  // a fresh association barely moved the pose: the correspondences are stable
        }
    }

    // Weak directions (below the threshold, above the probe's): solved when the scene, not the
    // noise of the clusters, holds them - the pose moved off along one comes back under fresh
    // associations (see ScanMatcherConfig::degeneracy_probe_max_std_m). Probed from the
    // strongest down; the first that does not come back ends the search.
    const double probe_threshold = degeneracyProbeEigenvalueThreshold(config_);
    double confirmed_threshold = threshold;
    for (int i = res.degeneracy.well_conditioned; i < 6 && probe_threshold < threshold; ++i) {
        const double lambda = res.degeneracy.eigenvalues[i];
        if (lambda < probe_threshold) break;
        ++res.probed_directions;
        const Vector6d v = res.degeneracy.V.row(i).transpose();
        const std::optional<double> to_min = comesBack(features, map, T, v);
        if (!to_min) break;
        // Start the last round at the laser's minimum along v: the prior may hold the pose
        // further off than the finest kernel reaches.
        T = T * expSE3(*to_min * v);
        ++res.confirmed_directions;
        const double next = i + 1 < 6 ? res.degeneracy.eigenvalues[i + 1] : 0.0;
        confirmed_threshold = std::max(probe_threshold, 0.5 * (lambda + next));
    }
    if (res.confirmed_directions > 0) {
        // Eq. (21) again with the confirmed directions among the solved ones: the pose moves
        // along them too, from a fresh association at the finest scale.
        associate(config_, features, map, T, true, corr, res.edge_matches, res.plane_matches);
        ++res.associations;
        if (static_cast<int>(corr.size()) >= config_.min_correspondences) {
            res.converged = iterate(confirmed_threshold, config_.kernel_scale_m);
        }
    }
    res.T_world_body = T;
    res.covariance = H_final.inverse();
    return res;
}

std::optional<double> ScanMatcher::comesBack(const FeatureCloud& features, const LocalMap& map,
                                             const Eigen::Isometry3d& T, const Vector6d& v) const {
    std::vector<Correspondence> corr;
    corr.reserve(features.edges.size() + features.planars.size());
    int edges = 0;
    int planes = 0;
    // Laser-only Gauss-Newton restricted to v from `from`, each step on fresh correspondences;
    // returns how far it went along v (nullopt: no information left).
    auto descend = [&](Eigen::Isometry3d from, double scale) -> std::optional<double> {
        double travelled = 0.0;
        for (int it = 0; it < config_.degeneracy_probe_iterations; ++it) {
            // Centimetre steps: the curvature refinement would only cost time here.
            associate(config_, features, map, from, false, corr, edges, planes);
            const NormalEquations ne = accumulate(config_, corr, from, scale);
            const double lambda = v.dot(ne.JtJ * v);
            if (lambda <= 0.0) return std::nullopt;
            const double step = -v.dot(ne.Jtr) / lambda;
            from = from * expSE3(step * v);
            travelled += step;
        }
        return travelled;
    };
    // The laser's own minimum along v: T holds the prior there, which may be centimetres off.
    const std::optional<double> to_min = descend(T, config_.kernel_scale_m);
    if (!to_min) return std::nullopt;
    const Eigen::Isometry3d T_min = T * expSE3(*to_min * v);
    for (int k = 1; k <= 2; ++k) {
        const double offset = k * config_.degeneracy_probe_offset_m;
        // The kernel must let the displaced features still see their true neighbours.
        const double scale = std::max(config_.kernel_scale_m, 2.0 * offset);
        for (const double sign : {1.0, -1.0}) {
            // The information of clusters whose normals only noise tilts towards v is local to
            // one association and does not pull back; a recess's faces do.
            const std::optional<double> travelled =
                descend(T_min * expSE3(sign * offset * v), scale);
            if (!travelled) return std::nullopt;
            const double back = -*travelled / (sign * offset);
            if (back < config_.degeneracy_probe_min_return ||
                back > 2.0 - config_.degeneracy_probe_min_return) {
                return std::nullopt;
            }
        }
    }
    return to_min;
}

}  // namespace handscan::scan
