#include "handscan/lio/motion_compensation.hpp"

#include <algorithm>
#include <vector>

#include "handscan/core/se3.hpp"

namespace handscan::lio {

Status recompensateSweep(scan::Sweep& sweep, const PoseQuery& pose_at, TimeNs sample_period) {
    if (sweep.points.empty()) return Status::ok();
    TimeNs t0 = sweep.points.front().t, t1 = t0;
    for (const scan::SweepPoint& p : sweep.points) {
        t0 = std::min(t0, p.t);
        t1 = std::max(t1, p.t);
    }
    t0 = std::min(t0, sweep.t_start);
    const TimeNs dt = std::max<TimeNs>(1, sample_period);
    const std::size_t n = static_cast<std::size_t>((t1 - t0) / dt) + 2;
    auto T_start = pose_at(sweep.t_start);
    if (!T_start) return T_start.status();
    const Eigen::Isometry3d T_start_world = T_start->inverse();
    // Relative poses T(t_start)^-1 T(t_k) at the sample times.
    std::vector<Eigen::Isometry3d> rel(n);
    for (std::size_t k = 0; k < n; ++k) {
        auto T = pose_at(t0 + static_cast<TimeNs>(k) * dt);
        if (!T) return T.status();
        rel[k] = T_start_world * *T;
    }
    for (scan::SweepPoint& p : sweep.points) {
        const double u = static_cast<double>(p.t - t0) / static_cast<double>(dt);
        const std::size_t k = std::min(n - 2, static_cast<std::size_t>(std::max(0.0, u)));
        const Eigen::Isometry3d T_start_point =
            interpolate(rel[k], rel[k + 1], std::clamp(u - static_cast<double>(k), 0.0, 1.0));
        p.p_start = T_start_point * p.p_body;
        p.origin_start = T_start_point * p.origin_body;  // the laser centre moves with it
    }
    sweep.T_world_start_odom = *T_start;
    return Status::ok();
}

}  // namespace handscan::lio
