#include "handscan/fusion/transform_integrator.hpp"

#include <algorithm>

#include "handscan/core/se3.hpp"

namespace handscan::fusion {

namespace {
constexpr TimeNs kVisualHistory = 5 * kNsPerSec;
}  // namespace

void TransformIntegrator::setScanPose(const PoseEstimate& scan) {
    scan_ = scan;
    // Keep one VIO pose at or before the scan time for interpolation, drop the older ones.
    while (vio_.size() > 1 && vio_[1].t_host <= scan.t_host) vio_.pop_front();
}

void TransformIntegrator::setVisualPose(const PoseEstimate& vio) {
    if (!vio_.empty() && vio.t_host <= vio_.back().t_host) return;  // out of order: ignore
    vio_.push_back(vio);
    // A scan pose refers to its sweep's time, which the matcher reports up to a couple of sweeps
    // late: keep the VIO poses of the last kVisualHistory so the increment can start there.
    while (vio_.size() > 2 && vio_[1].t_host < vio.t_host - kVisualHistory) vio_.pop_front();
}

std::optional<Eigen::Isometry3d> TransformIntegrator::visualPoseAt(TimeNs t) const {
    if (vio_.empty() || t < vio_.front().t_host || t > vio_.back().t_host) return std::nullopt;
    const auto it = std::lower_bound(vio_.begin(), vio_.end(), t,
                                     [](const PoseEstimate& p, TimeNs v) { return p.t_host < v; });
    if (it->t_host == t) return it->T_world_body;
    const auto prev = it - 1;
    const double s =
        static_cast<double>(t - prev->t_host) / static_cast<double>(it->t_host - prev->t_host);
    return interpolate(prev->T_world_body, it->T_world_body, s);
}

Result<PoseEstimate> TransformIntegrator::poseAt(TimeNs t) const {
    if (!scan_) return predictor_.predict(t);  // before the first scan match: prediction only

    // Blue section: the scan-matching pose.
    Eigen::Isometry3d T = scan_->T_world_body;
    TimeNs t_front = scan_->t_host;
    // Green section: the VIO increment after the scan pose, if VIO covers the scan time.
    if (!vio_.empty() && vio_.back().t_host > scan_->t_host) {
        const TimeNs t_v = std::min(vio_.back().t_host, t);
        const auto T_vs = visualPoseAt(scan_->t_host);
        const auto T_vv = visualPoseAt(t_v);
        if (T_vs && T_vv) {
            T = T * (T_vs->inverse() * *T_vv);
            t_front = t_v;
        }
    }
    // Orange section: the IMU prediction since then.
    auto T_front = predictor_.poseAt(t_front);
    if (!T_front) return T_front.status();
    auto T_now = predictor_.poseAt(t);
    if (!T_now) return T_now.status();
    PoseEstimate out;
    out.t_host = t;
    out.T_world_body = T * (T_front->inverse() * *T_now);
    out.T_world_body.linear() = orthonormalize(out.T_world_body.linear());
    out.covariance = scan_->covariance;
    out.solved_dof_mask = scan_->solved_dof_mask;
    out.source = PoseSource::kIntegrated;
    return out;
}

}  // namespace handscan::fusion
