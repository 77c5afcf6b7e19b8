#include "handscan/tum/trajectory_pose.hpp"

#include <algorithm>

#include "handscan/core/se3.hpp"

namespace handscan::tum {

Eigen::Isometry3d poseAt(const Trajectory& tr, double t_s) {
    const auto it = std::lower_bound(tr.begin(), tr.end(), t_s,
                                     [](const StampedPose& p, double v) { return p.t_s < v; });
    if (it == tr.begin()) return tr.front().T;
    if (it == tr.end()) return tr.back().T;
    const auto& a = *(it - 1);
    return interpolate(a.T, it->T, (t_s - a.t_s) / (it->t_s - a.t_s));
}

}  // namespace handscan::tum
