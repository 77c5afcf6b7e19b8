#include "handscan/fusion/trajectory_smoother.hpp"

#include <algorithm>
#include <limits>

#include "handscan/core/se3.hpp"

namespace handscan::fusion {

void TrajectorySmoother::add(const PoseEstimate& realtime) {
    if (!open_.empty() && realtime.t_host <= open_.back().t_host) return;  // not after: ignore
    open_.push_back(realtime);
}

void TrajectorySmoother::release(TimeNs up_to) {
    while (!open_.empty() && open_.front().t_host <= up_to) {
        closed_.push_back(open_.front());
        open_.pop_front();
    }
}

void TrajectorySmoother::anchor(const PoseEstimate& b, const CarriedFn& carried_from_previous) {
    if (anchor_ && b.t_host <= anchor_->t_host) return;
    const std::optional<PoseEstimate> a = anchor_;
    anchor_ = b;
    // Before the first anchor there is nothing to correct from (the static start: prediction).
    if (!a) return release(b.t_host);
    // Poses from before a were closed by a's own segment; any still kept (a pose that came
    // late) stay as they were output.
    release(a->t_host);
    Result<Eigen::Isometry3d> carried_b = carried_from_previous(b.t_host);
    if (!carried_b) return release(b.t_host);
    // The disagreement at b between the carried chain and the match.
    const Eigen::Vector3d rot_error =
        logSO3(b.T_world_body.linear() * carried_b->linear().transpose());
    const Eigen::Vector3d trans_error = b.T_world_body.translation() - carried_b->translation();
    const double span = static_cast<double>(b.t_host - a->t_host);
    while (!open_.empty() && open_.front().t_host <= b.t_host) {
        PoseEstimate p = open_.front();
        open_.pop_front();
        Result<Eigen::Isometry3d> carried = carried_from_previous(p.t_host);
        if (carried) {
            const double share =
                std::clamp(static_cast<double>(p.t_host - a->t_host) / span, 0.0, 1.0);
            p.T_world_body.linear() = orthonormalize(expSO3(share * rot_error) * carried->linear());
            p.T_world_body.translation() = carried->translation() + share * trans_error;
        }
        closed_.push_back(p);
    }
}

void TrajectorySmoother::flush() { release(std::numeric_limits<TimeNs>::max()); }

std::vector<PoseEstimate> TrajectorySmoother::take() {
    std::vector<PoseEstimate> out;
    out.swap(closed_);
    return out;
}

}  // namespace handscan::fusion
