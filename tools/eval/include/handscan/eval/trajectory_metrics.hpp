// Trajectory accuracy against ground truth, as the issue defines it:
//  * association: every estimated pose within the ground truth's time span is paired with the
//    ground truth interpolated (slerp + linear) at its time;
//  * ATE: translation error after the SE(3) alignment (Umeyama / Horn, no scale) of the estimate
//    onto the ground truth: RMSE, mean, median, max;
//  * relative drift (KITTI style): for path segments of 5/10/20/40 m measured along the ground
//    truth, the translation error of the segment's relative motion divided by its length, mean per
//    length and over all segments, in %; rotation drift in deg/m alike;
//  * end-point error: the error of the start-to-end relative motion, which for a loop is the
//    loop-closure gap the estimator accumulated.
#pragma once

#include <vector>

#include "handscan/eval/tum.hpp"

namespace handscan::eval {

struct PosePair {
    double t_s = 0.0;
    Eigen::Isometry3d gt = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d est = Eigen::Isometry3d::Identity();
};

// Pairs est poses with interpolated gt; gt gaps longer than max_gap_s are not interpolated over.
std::vector<PosePair> associate(const Trajectory& gt, const Trajectory& est,
                                double max_gap_s = 0.25);

// A path whose thinnest extent is below this fraction of its middle one counts as planar.
inline constexpr double kPlanarPathRatio = 0.1;

struct Alignment {
    Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();
    bool planar = false;             // positions alone leave the up/down branch ambiguous
    bool took_other_branch = false;  // ... and the orientations chose the non-Umeyama one
};
// The rigid transform T with T * est ~ gt in least squares over the positions (Umeyama 1991).
// For a planar path the two proper least-squares branches (differing by an in-plane mirror and an
// upside-down turn) are told apart by the orientations.
Alignment alignTrajectories(const std::vector<PosePair>& pairs);
Eigen::Isometry3d alignSE3(const std::vector<PosePair>& pairs);

struct ErrorStats {
    std::size_t n = 0;
    double rmse = 0.0, mean = 0.0, median = 0.0, max = 0.0;
};
ErrorStats computeStats(std::vector<double> errors);

struct AteResult {
    ErrorStats translation_m;
    ErrorStats rotation_deg;
    Eigen::Isometry3d T_gt_est = Eigen::Isometry3d::Identity();  // the alignment
    bool planar_path = false;
    bool orientation_chose_branch = false;  // see alignTrajectories
};
AteResult computeAte(const std::vector<PosePair>& pairs);
// The errors with a given alignment instead of the pairs' own: a second session localized in the
// first session's frame is measured against its ground truth moved by the first's alignment.
AteResult computeAteWith(const std::vector<PosePair>& pairs, const Eigen::Isometry3d& T_gt_est);

struct SegmentDrift {
    double length_m = 0.0;
    std::size_t segments = 0;
    double translation_percent = 0.0;  // mean of |t_err| / length * 100
    double rotation_deg_per_m = 0.0;
};
struct DriftResult {
    std::vector<SegmentDrift> per_length;
    double mean_translation_percent = 0.0;  // over all segments of all lengths (KITTI)
    double mean_rotation_deg_per_m = 0.0;
    double path_length_m = 0.0;
};
DriftResult computeDrift(const std::vector<PosePair>& pairs,
                         const std::vector<double>& lengths_m = {5.0, 10.0, 20.0, 40.0},
                         double start_spacing_m = 0.1);

struct EndPointResult {
    double error_m = 0.0;        // | est relative motion start->end - gt's | (translation)
    double error_percent = 0.0;  // of the path length
    double rotation_error_deg = 0.0;
    double gt_start_end_gap_m = 0.0;  // how far the ground truth's end is from its start
    bool is_loop = false;             // gt gap below 1% of the path or 0.5 m
};
EndPointResult computeEndPoint(const std::vector<PosePair>& pairs);

}  // namespace handscan::eval
