#include "handscan/vio/motion_estimator.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::vio {
namespace {

double bisquare(double r, double c) {
    if (r >= c) return 0.0;
    const double u = 1.0 - (r / c) * (r / c);
    return u * u;
}

// Whitened normal equations of the camera constraints at T under fixed robust weights.
struct Normal {
    Matrix6d JtJ = Matrix6d::Zero();
    Vector6d Jtr = Vector6d::Zero();
    double cost = 0.0;
};

}  // namespace

int constraintResiduals(const FeatureConstraint& f, const Eigen::Isometry3d& T_l_c,
                        Eigen::Vector2d& r) {
    const Eigen::Matrix3d& R = T_l_c.linear();
    const Eigen::Vector3d& t = T_l_c.translation();
    const double x = f.xbar_c.x();
    const double y = f.xbar_c.y();
    if (f.has_depth) {
        const Eigen::Vector3d Xc = R * f.X_l + t;  // eqs. (6)-(7)
        r = {Xc.x() - x * Xc.z(), Xc.y() - y * Xc.z()};
        return 2;
    }
    const Eigen::Vector3d u = R * f.X_l;  // eq. (8)
    r = {t.dot(u.cross(Eigen::Vector3d(x, y, 1.0))), 0.0};
    return 1;
}

int constraintResiduals(const FeatureConstraint& f, const Eigen::Isometry3d& T_l_c,
                        Eigen::Vector2d& r, Eigen::Matrix<double, 2, 6>& J) {
    const Eigen::Matrix3d& R = T_l_c.linear();
    const Eigen::Vector3d& t = T_l_c.translation();
    const double x = f.xbar_c.x();
    const double y = f.xbar_c.y();
    if (f.has_depth) {
        // eqs. (6)-(7): rows 1, 2 of eq. (5) minus x_c, y_c times row 3.
        const Eigen::Vector3d Xc = R * f.X_l + t;
        r = {Xc.x() - x * Xc.z(), Xc.y() - y * Xc.z()};
        // Left perturbation: dX_c / d(w, v) = [-[X_c]x, I].
        const Eigen::RowVector3d a1(1.0, 0.0, -x);
        const Eigen::RowVector3d a2(0.0, 1.0, -y);
        const Eigen::Matrix3d S = -skew(Xc);
        J.row(0) << a1 * S, a1;
        J.row(1) << a2 * S, a2;
        return 2;
    }
    // eq. (8): [X_bar_c]x t . R X_bar_l = t . (u x X_bar_c), u = R X_bar_l: the feature lies in
    // the epipolar plane.
    const Eigen::Vector3d Xc(x, y, 1.0);
    const Eigen::Vector3d u = R * f.X_l;
    const Eigen::Vector3d n = u.cross(Xc);
    r = {t.dot(n), 0.0};
    // t <- t + w x t + v, u <- u + w x u.
    const Eigen::Vector3d dw = t.cross(n) + u.cross(Xc.cross(t));
    J.row(0) << dw.transpose(), n.transpose();
    J.row(1).setZero();
    return 1;
}

MotionResult MotionEstimator::estimate(const std::vector<FeatureConstraint>& constraints,
                                       const Eigen::Isometry3d& initial,
                                       const std::optional<ImuMotionPrior>& prior,
                                       double focal_px) const {
    MotionResult res;
    res.T_l_c = initial;
    const std::size_t n = constraints.size();
    res.inlier.assign(n, false);
    const double sigma = config_.feature_sigma_px / focal_px;
    const double inv_s2 = 1.0 / (sigma * sigma);
    const double threshold = 1.0 / (config_.degeneracy_max_std * config_.degeneracy_max_std);
    std::vector<double> weight(n, 1.0);

    // Scale of each constraint's residual to normalised image units at T (section comment).
    auto scaleOf = [&](const FeatureConstraint& f, const Eigen::Isometry3d& T) -> double {
        if (f.has_depth) {
            const double z = (T.linear() * f.X_l + T.translation()).z();
            return z > 1e-3 ? 1.0 / z : 0.0;
        }
        return 1.0 / std::max(T.translation().norm(), config_.min_translation_m);
    };
    auto normal = [&](const Eigen::Isometry3d& T, bool with_jacobian) {
        Normal ne;
        Eigen::Vector2d r;
        Eigen::Matrix<double, 2, 6> J;
        for (std::size_t i = 0; i < n; ++i) {
            if (weight[i] <= 0.0) continue;
            const double s = scaleOf(constraints[i], T);
            if (s <= 0.0) continue;
            if (!with_jacobian) {
                constraintResiduals(constraints[i], T, r);
                ne.cost += weight[i] * s * s * inv_s2 * r.squaredNorm();
                continue;
            }
            // A one-row constraint (eq. 8) has r[1] = 0 and a zero second row of J.
            if (constraintResiduals(constraints[i], T, r, J) == 1) {
                // Eq. (8) is scale free: any t along the epipolar planes' common line fits it,
                // t = 0 too. It says nothing of how far the camera moved, so its Jacobian loses
                // the component along t; else its noise, weighted by 1/max(|t|, t_min)^2, pulls
                // the translation towards zero whenever |t| < t_min (measured: the VIO's speed
                // collapsed to ~0 over a simulated tunnel walk).
                const double tn = T.translation().norm();
                if (tn > 1e-9) {
                    const Eigen::Vector3d u = T.translation() / tn;
                    const Eigen::Vector3d jv = J.row(0).tail<3>().transpose();
                    J.row(0).tail<3>() = (jv - u * u.dot(jv)).transpose();
                }
            }
            const double w = weight[i] * s * s * inv_s2;
            ne.cost += w * r.squaredNorm();
            ne.JtJ.noalias() += w * J.transpose() * J;
            ne.Jtr.noalias() += w * J.transpose() * r;
        }
        return ne;
    };
    // Prior term of eq. (11): e = log(T T_hat^-1), T = exp(e) T_hat.
    auto priorError = [&](const Eigen::Isometry3d& T) -> Vector6d {
        return logSE3(T * prior->T_l_c.inverse());
    };
    auto reweight = [&](const Eigen::Isometry3d& T, double kernel_px) {
        Eigen::Vector2d r;
        double sum2 = 0.0;
        res.inliers = 0;
        for (std::size_t i = 0; i < n; ++i) {
            const double s = scaleOf(constraints[i], T);
            constraintResiduals(constraints[i], T, r);
            const double px = s * r.norm() * focal_px;
            weight[i] = s > 0.0 ? bisquare(px, kernel_px) : 0.0;
            res.inlier[i] = weight[i] > 0.0;
            if (res.inlier[i]) {
                ++res.inliers;
                sum2 += px * px;
            }
        }
        res.rms_px = res.inliers > 0 ? std::sqrt(sum2 / res.inliers) : 0.0;
    };

    Eigen::Isometry3d T = initial;
    double mu = 1e-4;
    for (int pass = 0; pass < config_.max_passes; ++pass) {
        const double kernel =
            std::max(config_.kernel_final_px, config_.kernel_initial_px * std::pow(0.5, pass));
        reweight(T, kernel);
        for (int it = 0; it < config_.max_iterations; ++it) {
            const Normal ne = normal(T, true);
            Matrix6d H = ne.JtJ;
            Vector6d g = ne.Jtr;
            double cost = ne.cost;
            if (prior) {
                const Vector6d e = priorError(T);
                H += prior->information;
                g += prior->information * e;
                cost += e.dot(prior->information * e);
            }
            // eq. (21): move only where the camera constraints are well conditioned.
            res.degeneracy = scan::analyzeDegeneracy(ne.JtJ, threshold);
            if (res.degeneracy.well_conditioned == 0) break;
            bool accepted = false;
            Vector6d dx = Vector6d::Zero();
            for (int tries = 0; tries < 6 && !accepted; ++tries) {
                Matrix6d A = H;
                A.diagonal() += mu * H.diagonal() + Vector6d::Constant(1e-12);
                dx = res.degeneracy.projection * (-A.ldlt().solve(g));  // eqs. (20)-(21)
                const Eigen::Isometry3d T_try = expSE3(dx) * T;
                double trial = normal(T_try, false).cost;
                if (prior) {
                    const Vector6d e = priorError(T_try);
                    trial += e.dot(prior->information * e);
                }
                if (trial <= cost) {
                    T = T_try;
                    T.linear() = orthonormalize(T.linear());
                    mu = std::max(1e-9, mu * 0.1);
                    accepted = true;
                } else {
                    mu *= 10.0;
                }
            }
            ++res.iterations;
            if (!accepted || dx.norm() < config_.converged_step) break;
        }
    }
    reweight(T, config_.kernel_final_px);
    const Normal final_ne = normal(T, true);
    res.information = final_ne.JtJ;
    res.degeneracy = scan::analyzeDegeneracy(final_ne.JtJ, threshold);
    res.T_l_c = T;
    return res;
}

}  // namespace handscan::vio
