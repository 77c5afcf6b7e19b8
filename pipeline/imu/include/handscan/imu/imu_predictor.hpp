// The IMU prediction subsystem (paper section 4): the 200 Hz backbone of the pipeline. It
// integrates every IMU sample (eqs. (3)-(4), midpoint rule on SO(3)), aligns with gravity from
// the static start, answers "where was the body at time t" for any t in the last `horizon_s`
// (the sweep assembler asks for every laser step), and takes pose feedback from the scan matcher
// or the visual-inertial odometry: correct() replaces the predicted pose at the feedback time in
// the solved DOFs only, re-estimates the biases and velocity from the sliding window of feedback,
// and re-integrates the samples after the feedback time so the prediction continues from it.
//
// Frames: {I} IMU, {C} tracking camera = body, {W} gravity aligned (z up) with its origin at the
// IMU at the end of the static start. T_cam_imu is cam0's from the Kalibr camchain.
#pragma once

#include <optional>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/imu/bias_estimator.hpp"
#include "handscan/imu/dof_projector.hpp"
#include "handscan/imu/gravity_alignment.hpp"
#include "handscan/imu/imu_history.hpp"
#include "handscan/imu/unsolved_motion_prior.hpp"

namespace handscan::imu {

struct ImuPredictorConfig {
    double gravity_mps2 = 9.81;
    double horizon_s = 15.0;            // history kept for poseAt() and the feedback window
    double max_extrapolation_s = 0.05;  // how far past the newest sample predict() may go
    double max_gap_s = 0.1;             // a longer gap between samples is counted as a dropout
    GravityAlignmentConfig alignment;
    BiasEstimatorConfig bias;
    UnsolvedMotionPriorConfig motion_prior;  // the velocity in unsolved directions (section 8)
};

struct ImuPredictorStats {
    std::uint64_t samples = 0;
    std::uint64_t rejected_samples = 0;  // non-finite or out of order
    std::uint64_t gaps = 0;              // intervals longer than max_gap_s (integrated across)
    std::uint64_t corrections = 0;
    std::uint64_t rejected_corrections = 0;
};

class ImuPredictor {
public:
    ImuPredictor(ImuPredictorConfig config, const Eigen::Isometry3d& T_cam_imu);
    // With the rig's calibration: the body is the tracking camera (camchain cam0's T_cam_imu).
    ImuPredictor(ImuPredictorConfig config, const Calibration& calibration)
        : ImuPredictor(config, calibration.T_camera_imu()) {}

    // Adds one sample. Before alignment, samples feed the static-start detector; afterwards each
    // one is integrated. A bad sample is dropped with an error; the prediction goes on.
    [[nodiscard]] Status addImu(const ImuSample& s);

    // Starts the prediction from a known state (e.g. ground truth or a visual initialisation)
    // instead of the static start. The next sample at or after x.t continues from it.
    void initialize(const NavState& x, const ImuBiases& biases);
    bool initialized() const { return initialized_; }
    const std::optional<GravityAlignment>& alignment() const { return alignment_; }

    // The predicted IMU state / body pose at time t (interpolated within the history, held-rate
    // extrapolation up to max_extrapolation_s past the newest sample).
    Result<NavState> stateAt(TimeNs t) const;
    Result<Eigen::Isometry3d> poseAt(TimeNs t) const;
    // PoseEstimate of the body with source kImuPrediction.
    Result<PoseEstimate> predict(TimeNs t) const;

    // Feedback from the scan matcher / VIO: the body pose at time t, trusted only in the solved
    // DOFs (world-axis mask or projector, see dof_projector.hpp).
    [[nodiscard]] Status correct(TimeNs t, const Eigen::Isometry3d& T_world_body,
                                 std::uint8_t solved_dof_mask);
    [[nodiscard]] Status correct(TimeNs t, const Eigen::Isometry3d& T_world_body,
                                 const Matrix6d& solved);

    // The world frame moved (a relocalisation found where the map really is: x' = T x): every
    // kept state and gravity are carried into the new frame; the feedback window (poses in the
    // old frame) and the motion prior start again. Biases are properties of the sensor: kept.
    void moveWorld(const Eigen::Isometry3d& T_new_old);
    // After a gap (attitude held while the body turned, integrateOrHold): the tilt the held
    // attitude left, from the mean specific force in {W} over the samples in [t0, t1] (it is -g
    // where the body's mean acceleration is small next to g: a walker over a step or two), is
    // taken out of every state from t0 on, which are integrated again: uncorrected, gravity
    // leaks into the acceleration (7 deg of tilt: 1.2 m/s^2, metres within seconds). Yaw stays
    // unknown. The feedback window and the motion prior start again (as in moveWorld). Returns the
    // tilt corrected (rad); an error when [t0, t1] holds too few samples.
    [[nodiscard]] Result<double> relevel(TimeNs t0, TimeNs t1);

    const ImuBiases& biases() const { return biases_; }
    TimeNs newestTime() const { return history_.empty() ? 0 : history_.back(); }
    TimeNs oldestTime() const { return history_.empty() ? 0 : history_.front(); }
    const ImuPredictorStats& stats() const { return stats_; }
    const Eigen::Isometry3d& T_imu_body() const { return T_imu_body_; }
    // Gravity in {W}: (0, 0, -g) until feedback refines its direction in the map frame.
    const Eigen::Vector3d& gravity() const { return gravity_world_; }
    // The velocity held in unsolved translation directions (see unsolved_motion_prior.hpp).
    const UnsolvedMotionPrior& motionPrior() const { return motion_prior_; }

private:
    void startFrom(const NavState& x, const ImuSample& s);
    // Re-integrates every sample after x.t from state x with the current biases.
    void repropagateFrom(const NavState& x);

    ImuPredictorConfig config_;
    Eigen::Isometry3d T_imu_body_;
    StaticStartAligner aligner_;
    BiasEstimator bias_estimator_;
    UnsolvedMotionPrior motion_prior_;
    ImuHistory history_;
    ImuBiases biases_;
    Eigen::Vector3d gravity_world_;
    std::optional<GravityAlignment> alignment_;
    std::optional<NavState> pending_init_;
    bool initialized_ = false;
    TimeNs last_sample_t_ = 0;
    bool have_sample_ = false;
    ImuPredictorStats stats_;
};

}  // namespace handscan::imu
