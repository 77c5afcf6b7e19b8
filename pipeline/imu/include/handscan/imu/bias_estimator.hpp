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
    // Feedback kept in the sliding window. Long enough to span a turn of a walking operator, which
    // is what tells the body-frame accel bias from the world-frame gravity tilt (below).
    double window_s = 8.0;
    double min_spacing_s = 0.1;  // feedback closer than this to the last one is skipped
    // Noise model: every row of the window problem is whitened by its standard deviation, so
    // the weights mean something (the previous hand-tuned weights let the velocity follow the
    // newest pose's noise: +-1 cm/s ringing between consecutive sweeps, and a 15 cm matcher slip
    // became a 0.26 m/s velocity error that rang for seconds).
    double feedback_sigma_m = 0.01;     // position of one feedback pose (a scan match: ~5-10 mm)
    double feedback_sigma_rad = 0.002;  // orientation of one feedback pose (~0.1 deg)
    // IMU velocity increment over an interval: attitude error x g and accelerometer noise grow
    // with its length; a floor for short intervals.
    double velocity_sigma_mps = 0.003;
    double velocity_sigma_mps2 = 0.02;
    double velocity_prior_sigma_mps = 1.0;      // each velocity vs the prediction there (weak)
    double gyro_bias_step_sigma_radps = 0.005;  // change of the gyro bias per update (prior)
    double accel_bias_step_sigma_mps2 = 0.02;   // change of the accel bias per update (prior)
    // Gravity in the map frame. The map's frame is the predictor's world at the end of the
    // static start, levelled with the accelerometer: a horizontal accel bias of 0.02 m/s^2 tilts
    // it by 0.12 deg, so in the map frame gravity has a 0.02 m/s^2 horizontal part. Rotation
    // feedback ties the IMU attitude to the (tilted) map, so that part acts as a world-fixed
    // acceleration error that a body-frame bias can only follow while the heading stays put:
    // after a turn it drove 4 cm/s/s of velocity error along a corridor the matcher could not
    // solve. It is estimated as a horizontal correction of the gravity vector (observable from
    // turns: the body-frame bias turns with the device, the tilt does not).
    double gravity_step_sigma_mps2 = 0.01;  // change of the horizontal gravity per update
    // 3.4 deg: beyond, the window is inconsistent (the unsolved-direction prior may turn gravity
    // by up to 3 deg where a smooth tunnel bends the map, unsolved_motion_prior.hpp).
    double max_gravity_tilt_rad = 0.06;
    // Robust (Tukey biweight) weights on the whitened per-interval residuals: a matcher slip (a
    // pose a decimetre off) is ignored instead of steering the velocity and biases.
    double robust_c = 5.0;
    int robust_iterations = 3;
    double max_gyro_bias_radps = 0.2;  // estimates beyond these are rejected as outliers
    double max_accel_bias_mps2 = 2.0;
};

struct FeedbackPose {
    TimeNs t = 0;
    Eigen::Matrix3d R_world_imu = Eigen::Matrix3d::Identity();  // as applied (corrected DOFs only)
    Eigen::Vector3d p_world_imu = Eigen::Vector3d::Zero();
    Eigen::Vector3d v_predicted = Eigen::Vector3d::Zero();  // prior for the velocity there
    Matrix6d solved = Matrix6d::Identity();                 // projector of solved DOFs
};

struct BiasUpdate {
    ImuBiases biases;
    Eigen::Vector3d gravity_world = Eigen::Vector3d::Zero();  // refined gravity (map frame)
    Eigen::Vector3d v_world_imu_latest =
        Eigen::Vector3d::Zero();  // velocity at the newest feedback
    bool gyro_updated = false;
    bool accel_updated = false;
    int intervals = 0;
};

class BiasEstimator {
public:
    explicit BiasEstimator(BiasEstimatorConfig config = {}) : config_(config) {}

    // Adds one feedback pose and re-estimates. `history` must span the window. Returns the new
    // biases and the velocity at the feedback, or an error (then the biases are unchanged).
    Result<BiasUpdate> add(const FeedbackPose& f, const ImuHistory& history,
                           const ImuBiases& current, const Eigen::Vector3d& gravity);
    void reset() { window_.clear(); }
    std::size_t windowSize() const { return window_.size(); }

private:
    BiasEstimatorConfig config_;
    std::deque<FeedbackPose> window_;
};

}  // namespace handscan::imu
