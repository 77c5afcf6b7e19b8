#include "handscan/replay/reference_motion.hpp"

#include <algorithm>
#include <cmath>

#include "handscan/core/se3.hpp"
#include "handscan/tum/trajectory_pose.hpp"

namespace handscan::replay {

ReferenceMotion::ReferenceMotion(tum::Trajectory trajectory, double perturb_m, double perturb_rad,
                                 double prior_sigma_rot_rad, double prior_sigma_trans_m)
    : trajectory_(std::move(trajectory)), perturb_m_(perturb_m), perturb_rad_(perturb_rad) {
    information_.diagonal().head<3>().setConstant(1.0 /
                                                  (prior_sigma_rot_rad * prior_sigma_rot_rad));
    information_.diagonal().tail<3>().setConstant(1.0 /
                                                  (prior_sigma_trans_m * prior_sigma_trans_m));
}

Result<std::shared_ptr<const ReferenceMotion>> ReferenceMotion::load(const std::string& path,
                                                                     double perturb_m,
                                                                     double perturb_rad,
                                                                     double prior_sigma_rot_rad,
                                                                     double prior_sigma_trans_m) {
    auto tr = tum::readTum(path);
    if (!tr.isOk()) return tr.status();
    if (tr->size() < 2)
        return Status(StatusCode::kInvalidArgument,
                      "--reference-motion " + path + ": needs at least two poses");
    return std::shared_ptr<const ReferenceMotion>(std::make_shared<ReferenceMotion>(
        std::move(*tr), perturb_m, perturb_rad, prior_sigma_rot_rad, prior_sigma_trans_m));
}

Eigen::Isometry3d ReferenceMotion::poseAt(TimeNs t) const {
    return tum::poseAt(trajectory_, toSeconds(t));
}

std::vector<scan::PosePrior> ReferenceMotion::matchPrior(const scan::Sweep& sweep,
                                                         std::uint64_t matched_before) const {
    // A different error direction for every sweep, the same on every run (deterministic replay).
    const auto k = static_cast<double>(sweep.index);
    const Eigen::Vector3d axis =
        Eigen::Vector3d(std::sin(1.3 * k + 0.4), std::cos(2.1 * k), std::sin(0.7 * k + 1.9))
            .normalized();
    const Eigen::Vector3d dir =
        Eigen::Vector3d(std::cos(1.7 * k + 0.2), std::sin(0.9 * k + 1.1), std::cos(2.9 * k))
            .normalized();
    const double s = matched_before == 0 ? 0.0 : 1.0;
    Eigen::Isometry3d perturb = Eigen::Isometry3d::Identity();
    perturb.linear() = Eigen::AngleAxisd(s * perturb_rad_, axis).toRotationMatrix();
    perturb.translation() = s * perturb_m_ * dir;
    scan::PosePrior p;
    p.T_world_body = sweep.T_world_start_odom * perturb;
    p.information = information_;
    return {p};
}

}  // namespace handscan::replay
