// MotionEstimator (section 5.2): the motion T_l^c from key-frame l to frame c (X_c = R X_l + t,
// eq. 5) from three sets of constraints: features with depth at the key-frame (eqs. 6-7),
// features without depth (eq. 8), and the IMU prediction (eqs. 10-11). Six unknowns, the
// landmarks are not optimised. Levenberg-Marquardt on iteratively reweighted (bisquare) residuals
// with a kernel that narrows from coarse to fine, so features the tracker followed wrongly fall
// out (Andersen 2008's robust fitting); they are reported as outliers. Degeneracy per section 8:
// the eigenvalues of the camera constraints' J^T J (scan's DegeneracyRemapper) decide which
// directions the camera solved; the iteration moves only in those (eq. 21), the others keep the
// initial guess (the IMU prediction).
//
// Residuals are scaled to normalised image units so that one noise figure weighs them: eqs.
// (6)-(7) by 1/z_c (they become the reprojection error), eq. (8) by 1/max(|t|, t_min) (the sine
// of the angle between the feature and the epipolar plane). The perturbation is on the left,
// T_l^c <- exp(xi) T_l^c, xi = (rotation, translation) in {C_c}; for the body pose T_world_c =
// T_world_l (T_l^c)^-1 that is the right perturbation exp(-xi) in the body frame, the convention
// of scan::DegeneracyAnalysis.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <vector>

#include "handscan/core/se3.hpp"
#include "handscan/scan/degeneracy.hpp"

namespace handscan::vio {

struct FeatureConstraint {
    // At the key-frame: X_l (metres, {C_l}) when has_depth, else X_bar_l = (x, y, 1).
    Eigen::Vector3d X_l = Eigen::Vector3d::UnitZ();
    bool has_depth = false;
    Eigen::Vector2d xbar_c = Eigen::Vector2d::Zero();  // normalised coordinates in frame c
};

// Eqs. (10)-(11): the IMU-predicted T_l^c and the information of its error xi (left
// perturbation, (rot, trans) in {C_c}) relative to the camera constraints' noise.
struct ImuMotionPrior {
    Eigen::Isometry3d T_l_c = Eigen::Isometry3d::Identity();
    Matrix6d information = Matrix6d::Zero();
};

struct MotionEstimatorConfig {
    // Feature noise: standard deviation of a tracked position, in pixels (converted with the
    // focal length given to estimate()).
    double feature_sigma_px = 1.0;
    // Bisquare kernel: zero weight beyond this many pixels; the first pass uses the initial
    // value, each later one half the previous down to the final value.
    double kernel_initial_px = 24.0;
    double kernel_final_px = 4.0;
    int max_passes = 4;              // reweighting passes (kernel scales)
    int max_iterations = 8;          // LM steps per pass
    double min_translation_m = 0.1;  // t_min of the eq. (8) scaling
    // Section 8: a direction is solved when the camera constraints give it a standard deviation
    // below this (rotations count as their displacement at 1 m), i.e. an eigenvalue of the
    // whitened J^T J above 1 / max_std^2.
    double degeneracy_max_std = 0.02;
    double converged_step = 1e-7;
};

struct MotionResult {
    Eigen::Isometry3d T_l_c = Eigen::Isometry3d::Identity();
    scan::DegeneracyAnalysis degeneracy;      // of the camera constraints (body tangent)
    Matrix6d information = Matrix6d::Zero();  // whitened camera J^T J at the solution
    std::vector<bool> inlier;                 // per constraint: weight > 0 in the final pass
    int inliers = 0;
    int iterations = 0;
    double rms_px = 0.0;  // inlier reprojection-equivalent rms
};

class MotionEstimator {
public:
    explicit MotionEstimator(const MotionEstimatorConfig& config = {}) : config_(config) {}

    // `initial`: the starting T_l^c (the IMU prediction when there is one). `focal_px` converts
    // the pixel figures of the config into normalised units.
    MotionResult estimate(const std::vector<FeatureConstraint>& constraints,
                          const Eigen::Isometry3d& initial,
                          const std::optional<ImuMotionPrior>& prior, double focal_px) const;

    const MotionEstimatorConfig& config() const { return config_; }

private:
    MotionEstimatorConfig config_;
};

// One constraint's residuals and their Jacobians at T_l^c, before scaling: 2 rows for eqs.
// (6)-(7), 1 for eq. (8) (then r[1] = 0 and J's second row is zero). Returns the row count.
int constraintResiduals(const FeatureConstraint& f, const Eigen::Isometry3d& T_l_c,
                        Eigen::Vector2d& r, Eigen::Matrix<double, 2, 6>& J);
// The same residuals without the Jacobians (the same values bit for bit): the trial steps and
// the reweighting need only these.
int constraintResiduals(const FeatureConstraint& f, const Eigen::Isometry3d& T_l_c,
                        Eigen::Vector2d& r);

}  // namespace handscan::vio
