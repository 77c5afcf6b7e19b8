// Top view (x-y) of the ground truth and the aligned estimate as a PNG, with a scale bar and the
// start marked, for the closing notes and bug reports.
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/eval/trajectory_metrics.hpp"

namespace handscan::eval {

// `pairs` as from associate(); the estimate is drawn after applying T_gt_est.
Status plotTopView(const std::string& png_path, const std::vector<PosePair>& pairs,
                   const Eigen::Isometry3d& T_gt_est, int size_px = 1000);

}  // namespace handscan::eval
