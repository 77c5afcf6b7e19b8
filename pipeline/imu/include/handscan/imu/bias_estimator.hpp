// IMU bias correction from laser/visual feedback (paper section 4.2, with the per-DOF rule of
// section 8.3). Each feedback is a corrected pose of {I}; between consecutive feedback poses the
// corrected relative motion is compared with the IMU-only prediction (preintegration).
//   1. Gyro bias: the rotation residual log(dR_imu^T R_i^T R_j) is linear in the gyro bias change;
//      the residuals of every interval in the window are solved together in least squares.
//   2. With the new gyro bias the translation is re-predicted (first order, no re-integration)
//      and compared with the feedback translation; the velocities at every feedback pose and the
//      accelerometer bias change are solved together (position and velocity-continuity rows).
// The sliding window (the last `window_s` of feedback) plays the role of the paper's averaging
// of per-interval biases: its length sets how fast the biases follow. Residual rows are projected
// onto the DOFs solved at both ends of an interval, so unsolved directions carry no feedback and
// weak priors keep the previous biases (and predicted velocities) there - the effect of eq. (26).
#pragma once

#include <deque>

#include "handscan/core/se3.hpp"
#include "handscan/core/status.hpp"
#include "handscan/imu/imu_history.hpp"

namespace handscan::imu {

struct BiasEstimatorConfig {
    double window_s = 4.0;               // feedback kept in the sliding window
    double min_spacing_s = 0.1;          // feedback closer than this to the last one is skipped
    double velocity_row_weight = 0.3;    // weight of velocity continuity vs position rows
                                         // (IMU dv over 1 s ~2 cm/s uncertain through attitude
                                         // error, positions ~mm: EuRoC V1_02 tuned, see tests)
    double velocity_prior_weight = 0.01; // pull of each velocity towards the prediction
    double gyro_prior_weight = 1e-3;     // pull of the gyro bias change towards zero
    double accel_prior_weight = 0.01;    // pull of the accel bias change towards zero
    double max_gyro_bias_radps = 0.2;    // estimates beyond these are rejected as outliers
    double max_accel_bias_mps2 = 2.0;
};

struct FeedbackPose {
    TimeNs t = 0;
    Eigen::Matrix3d R_world_imu = Eigen::Matrix3d::Identity();  // as applied (corrected DOFs only)
    Eigen::Vector3d p_world_imu = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_predicted = Eigen::Vector3d::Zero();      // prior for the velocity there
    Matrix6d solved = Matrix6d::Identity();                     // projector of solved DOFs
};

struct BiasUpdate {
    ImuBiases biases;
    Eigen::Vector3d v_world_imu_latest = Eigen::Vector3d::Zero();  // velocity at the newest feedback
    bool gyro_updated = false;
    bool accel_updated = false;
    int intervals = 0;
};

class BiasEstimator {
public:
    explicit BiasEstimator(BiasEstimatorConfig config = {}) : config_(config) {}

    // Adds one feedback pose and re-estimates. `history` must span the window. Returns the new
    // biases and the velocity at the feedback, or an error (then the biases are unchanged).
    Result<BiasUpdate> add(const FeedbackPose& f, const ImuHistory& history, const ImuBiases& current,
                           const Eigen::Vector3d& gravity);
    void reset() { window_.clear(); }
    std::size_t windowSize() const { return window_.size(); }

private:
    BiasEstimatorConfig config_;
    std::deque<FeedbackPose> window_;
};

}  // namespace handscan::imu
