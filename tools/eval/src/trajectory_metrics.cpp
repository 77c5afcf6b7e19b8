#include "handscan/eval/trajectory_metrics.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "handscan/core/se3.hpp"

namespace handscan::eval {

std::vector<PosePair> associate(const Trajectory& gt, const Trajectory& est, double max_gap_s) {
    std::vector<PosePair> out;
    if (gt.size() < 2) return out;
    out.reserve(est.size());
    std::size_t k = 0;
    for (const StampedPose& e : est) {
        if (e.t_s < gt.front().t_s || e.t_s > gt.back().t_s) continue;
        while (k + 1 < gt.size() && gt[k + 1].t_s < e.t_s) ++k;  // est is sorted: walk forward
        const StampedPose& a = gt[k];
        const StampedPose& b = gt[std::min(k + 1, gt.size() - 1)];
        PosePair p;
        p.t_s = e.t_s;
        p.est = e.T;
        if (b.t_s <= a.t_s || e.t_s <= a.t_s) {
            p.gt = e.t_s <= a.t_s ? a.T : b.T;
        } else {
            if (b.t_s - a.t_s > max_gap_s + 1e-9) continue;  // tolerance: times in text round
            p.gt = interpolate(a.T, b.T, (e.t_s - a.t_s) / (b.t_s - a.t_s));
        }
        out.push_back(p);
    }
    return out;
}

namespace {

// Mean geodesic angle between the aligned estimate's orientations and the truth's.
double meanOrientationError(const std::vector<PosePair>& pairs, const Eigen::Matrix3d& R) {
    double sum = 0.0;
    for (const PosePair& p : pairs) sum += rotationAngle(R * p.est.linear(), p.gt.linear());
    return sum / static_cast<double>(pairs.size());
}

}  // namespace

Alignment alignTrajectories(const std::vector<PosePair>& pairs) {
    Alignment a;
    if (pairs.empty()) return a;
    if (pairs.size() < 3) {
        a.T_gt_est.translation() = pairs.front().gt.translation() - pairs.front().est.translation();
        return a;
    }
    // Umeyama (1991) without scale, written out because the near-planar case needs the SVD.
    const auto n = static_cast<Eigen::Index>(pairs.size());
    Eigen::Matrix3Xd src(3, n), dst(3, n);
    for (Eigen::Index i = 0; i < n; ++i) {
        src.col(i) = pairs[static_cast<std::size_t>(i)].est.translation();
        dst.col(i) = pairs[static_cast<std::size_t>(i)].gt.translation();
    }
    const Eigen::Vector3d mu_s = src.rowwise().mean(), mu_d = dst.rowwise().mean();
    src.colwise() -= mu_s;
    dst.colwise() -= mu_d;
    const Eigen::Matrix3d sigma = dst * src.transpose() / static_cast<double>(n);
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sigma, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Eigen::Matrix3d& U = svd.matrixU();
    const Eigen::Matrix3d& V = svd.matrixV();
    // The proper rotation U diag(1, 1, s) V^T with s = det(U V^T) (Umeyama's reflection guard).
    const double s = (U.determinant() * V.determinant() < 0.0) ? -1.0 : 1.0;
    Eigen::Matrix3d R = U * Eigen::Vector3d(1.0, 1.0, s).asDiagonal() * V.transpose();

    // A path that stays in one plane (a walk over flat ground) cannot tell its two proper fits
    // apart: the one above and the one that mirrors the path within its plane and turns it upside
    // down (U diag(1, -1, -s) V^T). A drifting estimate can fit the mirrored branch a little
    // better, which reports every pose 180 degrees off. For such paths the orientations decide.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> shape(src * src.transpose() /
                                                               static_cast<double>(n));
    const Eigen::Vector3d var = shape.eigenvalues().cwiseMax(0.0);  // ascending
    a.planar = std::sqrt(var(0)) < kPlanarPathRatio * std::sqrt(var(1));
    if (a.planar) {
        const Eigen::Matrix3d R_mirror =
            U * Eigen::Vector3d(1.0, -1.0, -s).asDiagonal() * V.transpose();
        if (meanOrientationError(pairs, R_mirror) < meanOrientationError(pairs, R)) {
            R = R_mirror;
            a.took_other_branch = true;
        }
    }
    a.T_gt_est.linear() = R;
    a.T_gt_est.translation() = mu_d - R * mu_s;
    return a;
}

Eigen::Isometry3d alignSE3(const std::vector<PosePair>& pairs) {
    return alignTrajectories(pairs).T_gt_est;
}

ErrorStats computeStats(std::vector<double> e) {
    ErrorStats s;
    s.n = e.size();
    if (e.empty()) return s;
    double sum = 0.0, sum2 = 0.0;
    for (double v : e) {
        sum += v;
        sum2 += v * v;
        s.max = std::max(s.max, v);
    }
    s.mean = sum / static_cast<double>(e.size());
    s.rmse = std::sqrt(sum2 / static_cast<double>(e.size()));
    const std::size_t mid = e.size() / 2;
    std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(mid), e.end());
    s.median = e[mid];
    if (e.size() % 2 == 0) {
        s.median = 0.5 * (s.median + *std::max_element(
                                         e.begin(), e.begin() + static_cast<std::ptrdiff_t>(mid)));
    }
    return s;
}

AteResult computeAte(const std::vector<PosePair>& pairs) {
    const Alignment a = alignTrajectories(pairs);
    AteResult r = computeAteWith(pairs, a.T_gt_est);
    r.planar_path = a.planar;
    r.orientation_chose_branch = a.took_other_branch;
    return r;
}

AteResult computeAteWith(const std::vector<PosePair>& pairs, const Eigen::Isometry3d& T_gt_est) {
    AteResult r;
    r.T_gt_est = T_gt_est;
    std::vector<double> et, er;
    et.reserve(pairs.size());
    er.reserve(pairs.size());
    for (const PosePair& p : pairs) {
        const Eigen::Isometry3d aligned = r.T_gt_est * p.est;
        et.push_back((aligned.translation() - p.gt.translation()).norm());
        er.push_back(rotationAngle(aligned.linear(), p.gt.linear()) * 180.0 / M_PI);
    }
    r.translation_m = computeStats(std::move(et));
    r.rotation_deg = computeStats(std::move(er));
    return r;
}

DriftResult computeDrift(const std::vector<PosePair>& pairs, const std::vector<double>& lengths_m,
                         double start_spacing_m) {
    DriftResult r;
    const std::size_t n = pairs.size();
    std::vector<double> dist(n, 0.0);
    for (std::size_t i = 1; i < n; ++i) {
        dist[i] = dist[i - 1] + (pairs[i].gt.translation() - pairs[i - 1].gt.translation()).norm();
    }
    r.path_length_m = n ? dist.back() : 0.0;
    double sum_t = 0.0, sum_r = 0.0;
    std::size_t total = 0;
    for (double L : lengths_m) {
        SegmentDrift d;
        d.length_m = L;
        double next_start = 0.0;
        std::size_t j = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (dist[i] < next_start) continue;
            next_start = dist[i] + start_spacing_m;
            j = std::max(j, i);
            while (j < n && dist[j] < dist[i] + L) ++j;
            if (j >= n) break;
            // Segment error: relative motion of the estimate against that of the ground truth.
            const Eigen::Isometry3d d_gt = pairs[i].gt.inverse() * pairs[j].gt;
            const Eigen::Isometry3d d_est = pairs[i].est.inverse() * pairs[j].est;
            const Eigen::Isometry3d E = d_gt.inverse() * d_est;
            const double seg = dist[j] - dist[i];
            d.translation_percent += E.translation().norm() / seg * 100.0;
            d.rotation_deg_per_m += logSO3(E.linear()).norm() * 180.0 / M_PI / seg;
            ++d.segments;
        }
        sum_t += d.translation_percent;
        sum_r += d.rotation_deg_per_m;
        total += d.segments;
        if (d.segments) {
            d.translation_percent /= static_cast<double>(d.segments);
            d.rotation_deg_per_m /= static_cast<double>(d.segments);
        }
        r.per_length.push_back(d);
    }
    if (total) {
        r.mean_translation_percent = sum_t / static_cast<double>(total);
        r.mean_rotation_deg_per_m = sum_r / static_cast<double>(total);
    }
    return r;
}

EndPointResult computeEndPoint(const std::vector<PosePair>& pairs) {
    EndPointResult r;
    if (pairs.size() < 2) return r;
    double length = 0.0;
    for (std::size_t i = 1; i < pairs.size(); ++i) {
        length += (pairs[i].gt.translation() - pairs[i - 1].gt.translation()).norm();
    }
    const Eigen::Isometry3d d_gt = pairs.front().gt.inverse() * pairs.back().gt;
    const Eigen::Isometry3d d_est = pairs.front().est.inverse() * pairs.back().est;
    const Eigen::Isometry3d E = d_gt.inverse() * d_est;
    r.error_m = E.translation().norm();
    r.error_percent = length > 0.0 ? r.error_m / length * 100.0 : 0.0;
    r.rotation_error_deg = logSO3(E.linear()).norm() * 180.0 / M_PI;
    r.gt_start_end_gap_m = d_gt.translation().norm();
    r.is_loop = r.gt_start_end_gap_m < std::max(0.5, 0.01 * length);
    return r;
}

}  // namespace handscan::eval
