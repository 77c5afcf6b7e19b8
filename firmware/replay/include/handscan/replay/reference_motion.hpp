// ReferenceMotion: `handscan replay --reference-motion GT.tum`, the scan matcher and the map
// measured alone, apart from the IMU prediction. Sweeps are assembled with the reference motion
// (the simulator's ground truth), and each match starts from it at the sweep's start, moved by a
// deterministic error of `perturb_m` / `perturb_rad` (a different direction per sweep, the same
// on every run), without feedback to the IMU. A replay diagnostic plugged into the estimator as a
// lio::MotionOverride; the device never runs it.
#pragma once

#include <memory>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/lio/motion_override.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/tum/tum_file.hpp"

namespace handscan::replay {

class ReferenceMotion final : public lio::MotionOverride {
public:
    // `prior_sigma_*`: the deviations the matcher's prior is given (the odometry's own, eq. 16).
    ReferenceMotion(tum::Trajectory trajectory, double perturb_m, double perturb_rad,
                    double prior_sigma_rot_rad, double prior_sigma_trans_m);
    // A TUM file with at least two poses; errors name the file.
    static Result<std::shared_ptr<const ReferenceMotion>> load(const std::string& path,
                                                               double perturb_m, double perturb_rad,
                                                               double prior_sigma_rot_rad,
                                                               double prior_sigma_trans_m);

    // Interpolated on SE(3); clamped at the trajectory's ends.
    Eigen::Isometry3d poseAt(TimeNs t) const override;
    // The reference at the sweep's start (as the assembler placed it), perturbed, except for the
    // sweep that founds the map (nothing to match against): placed at the reference itself.
    std::vector<scan::PosePrior> matchPrior(const scan::Sweep& sweep,
                                            std::uint64_t matched_before) const override;

private:
    tum::Trajectory trajectory_;
    double perturb_m_;
    double perturb_rad_;
    Matrix6d information_ = Matrix6d::Zero();
};

}  // namespace handscan::replay
