#include "handscan/imu/imu_predictor.hpp"

#include <string>

namespace handscan::imu {

ImuPredictor::ImuPredictor(ImuPredictorConfig config, const Eigen::Isometry3d& T_cam_imu)
    : config_(config),
      T_imu_body_(T_cam_imu.inverse()),
      aligner_(config.alignment),
      bias_estimator_(config.bias),
      motion_prior_(config.motion_prior),
      gravity_world_(gravityWorld(config.gravity_mps2)) {
    config_.alignment.gravity_mps2 = config_.gravity_mps2;
    aligner_ = StaticStartAligner(config_.alignment);
}

void ImuPredictor::initialize(const NavState& x, const ImuBiases& biases) {
    history_.clear();
    bias_estimator_.reset();
    motion_prior_.reset();
    biases_ = biases;
    gravity_world_ = gravityWorld(config_.gravity_mps2);
    pending_init_ = x;
    initialized_ = false;
}

void ImuPredictor::startFrom(const NavState& x, const ImuSample& s) {
    ImuHistoryEntry e;
    e.sample = s;
    e.reading = correctBiases(s, biases_);
    e.state = x;
    if (s.t_host > x.t) {
        // Continue from the given state with the first reading held over the short gap.
        e.state = integrateStep(x, e.reading, e.reading, toSeconds(s.t_host - x.t), gravity());
    }
    e.state.t = s.t_host;
    history_.push(e);
    initialized_ = true;
}

Status ImuPredictor::addImu(const ImuSample& s) {
    if (!s.gyro_radps_imu.allFinite() || !s.accel_mps2_imu.allFinite()) {
        ++stats_.rejected_samples;
        return Status(StatusCode::kInvalidArgument,
                      "IMU prediction: sample at t=" + std::to_string(s.t_host) +
                          " ns has a non-finite rate or acceleration; dropped");
    }
    if (have_sample_ && s.t_host <= last_sample_t_) {
        ++stats_.rejected_samples;
        return Status(StatusCode::kInvalidArgument,
                      "IMU prediction: sample at t=" + std::to_string(s.t_host) +
                          " ns is not newer than " + std::to_string(last_sample_t_) +
                          " ns; dropped (check the IMU clock mapping)");
    }
    if (have_sample_ && toSeconds(s.t_host - last_sample_t_) > config_.max_gap_s) ++stats_.gaps;
    have_sample_ = true;
    last_sample_t_ = s.t_host;
    ++stats_.samples;

    if (!initialized_) {
        if (pending_init_) {
            if (s.t_host >= pending_init_->t) {
                startFrom(*pending_init_, s);
                pending_init_.reset();
            }
            return Status::ok();
        }
        if (auto a = aligner_.add(s)) {
            alignment_ = a;
            biases_ = a->biases;
            NavState x;
            x.t = s.t_host;
            x.R_world_imu = a->R_world_imu;
            startFrom(x, s);
        }
        return Status::ok();
    }

    const ImuHistoryEntry& prev = history_.last();
    ImuHistoryEntry e;
    e.sample = s;
    e.reading = correctBiases(s, biases_);
    // Across a gap (the link lost) attitude and velocity are held, not integrated.
    e.state =
        integrateOrHold(prev.state, prev.reading, e.reading,
                        toSeconds(s.t_host - prev.sample.t_host), gravity(), config_.max_gap_s);
    e.state.t = s.t_host;
    history_.push(e);
    history_.trimBefore(s.t_host - fromSeconds(config_.horizon_s));
    return Status::ok();
}

Result<NavState> ImuPredictor::stateAt(TimeNs t) const {
    return history_.stateAt(t, fromSeconds(config_.max_extrapolation_s), gravity());
}

Result<Eigen::Isometry3d> ImuPredictor::poseAt(TimeNs t) const {
    auto x = stateAt(t);
    if (!x) return x.status();
    return bodyPose(*x, T_imu_body_);
}

Result<PoseEstimate> ImuPredictor::predict(TimeNs t) const {
    auto T = poseAt(t);
    if (!T) return T.status();
    PoseEstimate p;
    p.t_host = t;
    p.T_world_body = *T;
    p.source = PoseSource::kImuPrediction;
    p.solved_dof_mask = 0;  // nothing solved by an exteroceptive module: pure prediction
    return p;
}

Status ImuPredictor::correct(TimeNs t, const Eigen::Isometry3d& T_world_body,
                             std::uint8_t solved_dof_mask) {
    return correct(t, T_world_body, projectorFromMask(solved_dof_mask));
}

Status ImuPredictor::correct(TimeNs t, const Eigen::Isometry3d& T_world_body,
                             const Matrix6d& solved) {
    if (!initialized_ || history_.empty() || t < history_.front() || t > history_.back()) {
        ++stats_.rejected_corrections;
        return Status(
            StatusCode::kNotFound,
            "IMU prediction: feedback pose at t=" + std::to_string(t) +
                " ns is outside the IMU history; it must lie between the oldest and newest sample "
                "(raise imu horizon_s if the matcher lags more)");
    }
    auto predicted = stateAt(t);
    if (!predicted) return predicted.status();

    // The correction of the body pose in world axes (rotation, translation) - the coordinates of
    // the matcher's solved subspace - kept only in the solved DOFs, then carried to {I}.
    const Eigen::Isometry3d T_body_pred = bodyPose(*predicted, T_imu_body_);
    Vector6d delta;
    delta.head<3>() = logSO3(T_world_body.linear() * T_body_pred.linear().transpose());
    delta.tail<3>() = T_world_body.translation() - T_body_pred.translation();
    delta = solved * delta;
    Eigen::Isometry3d T_body_new = Eigen::Isometry3d::Identity();
    T_body_new.linear() = orthonormalize(expSO3(delta.head<3>()) * T_body_pred.linear());
    T_body_new.translation() = T_body_pred.translation() + delta.tail<3>();
    const Eigen::Isometry3d T_imu_new = T_body_new * T_imu_body_.inverse();
    NavState x = *predicted;
    x.R_world_imu = T_imu_new.linear();
    x.p_world_imu = T_imu_new.translation();

    FeedbackPose f;
    f.t = t;
    f.R_world_imu = x.R_world_imu;
    f.p_world_imu = x.p_world_imu;
    f.v_predicted = predicted->v_world_imu;
    f.solved = solved;
    auto update = bias_estimator_.add(f, history_, biases_, gravity());
    Status status = Status::ok();
    if (update) {
        biases_ = update->biases;
        gravity_world_ = update->gravity_world;
        x.v_world_imu = update->v_world_imu_latest;
    } else {
        ++stats_.rejected_corrections;
        status = update.status();  // the pose is still applied; only the biases are kept
    }
    // In unsolved translation directions the velocity is the walker's motion prior, not the
    // IMU's double integral (unsolved_motion_prior.hpp).
    x.v_world_imu = motion_prior_.apply(t, x.v_world_imu, unsolvedTranslation(solved));
    if (!motion_prior_.gravityStep().isZero()) {
        gravity_world_ =
            (gravity_world_ + motion_prior_.gravityStep()).normalized() * gravity_world_.norm();
    }
    ++stats_.corrections;
    repropagateFrom(x);
    return status;
}

void ImuPredictor::moveWorld(const Eigen::Isometry3d& T_new_old) {
    const Eigen::Matrix3d R = T_new_old.linear();
    for (std::size_t k = 0; k < history_.size(); ++k) {
        NavState& x = history_[k].state;
        x.R_world_imu = orthonormalize(R * x.R_world_imu);
        x.p_world_imu = T_new_old * x.p_world_imu;
        x.v_world_imu = R * x.v_world_imu;
    }
    gravity_world_ = R * gravity_world_;
    bias_estimator_.reset();
    motion_prior_.reset();
}

Result<double> ImuPredictor::relevel(TimeNs t0, TimeNs t1) {
    Eigen::Vector3d f_world = Eigen::Vector3d::Zero();
    std::size_t n = 0, first = history_.size();
    for (std::size_t k = 0; k < history_.size(); ++k) {
        const ImuHistoryEntry& e = history_[k];
        if (e.sample.t_host < t0 || e.sample.t_host > t1) continue;
        first = std::min(first, k);
        f_world += e.state.R_world_imu * e.reading.accel_mps2;
        ++n;
    }
    if (n < 10)
        return Status(StatusCode::kInvalidArgument,
                      "IMU prediction: relevel over " + std::to_string(n) +
                          " samples (at least 10 needed); attitude kept");
    // The smallest rotation taking the measured "up" onto gravity's up.
    const Eigen::Matrix3d C =
        Eigen::Quaterniond::FromTwoVectors(f_world.normalized(), -gravity().normalized())
            .toRotationMatrix();
    NavState x = history_[first].state;
    x.R_world_imu = orthonormalize(C * x.R_world_imu);
    repropagateFrom(x);
    // The feedback window's poses lie before the gap, which the held states do not connect to:
    // a velocity or a bias estimated across it is wrong by the gap's unknown motion.
    bias_estimator_.reset();
    return rotationAngle(C, Eigen::Matrix3d::Identity());
}

void ImuPredictor::repropagateFrom(const NavState& x0) {
    std::size_t k = history_.nodeAt(x0.t, gravity());
    NavState x = x0;
    ImuReading r = correctBiases(history_[k].sample, biases_);
    history_[k].state = x0;
    history_[k].reading = r;
    for (++k; k < history_.size(); ++k) {
        ImuHistoryEntry& e = history_[k];
        e.reading = correctBiases(e.sample, biases_);
        e.state = integrateOrHold(x, r, e.reading, toSeconds(e.sample.t_host - x.t), gravity(),
                                  config_.max_gap_s);
        e.state.t = e.sample.t_host;
        x = e.state;
        r = e.reading;
    }
}

}  // namespace handscan::imu
