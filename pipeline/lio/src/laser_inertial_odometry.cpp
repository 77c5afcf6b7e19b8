#include "handscan/lio/laser_inertial_odometry.hpp"

#include <cmath>
#include <cstdio>

#include "handscan/core/log.hpp"
#include "handscan/core/se3.hpp"
#include "handscan/lio/motion_compensation.hpp"
#include "handscan/scan/degeneracy.hpp"

namespace handscan::lio {

LaserInertialOdometry::LaserInertialOdometry(const LioConfig& config,
                                             const Calibration& calibration,
                                             std::shared_ptr<const MotionOverride> motion)
    : config_(config),
      motion_(std::move(motion)),
      predictor_(config.imu, calibration.T_camera_imu()),
      integrator_(predictor_),
      monitor_(config.tracking),
      incidents_(config.incidents),
      relocaliser_(config.relocalise),
      clocks_(
          [&] {
              // Diagnostics with a motion override match without the IMU: nothing to align.
              ClockTrackerConfig c = config.clocks;
              c.enabled = c.enabled && !motion_;
              return c;
          }(),
          calibration.T_camera_imu().linear(),
          calibration.T_camera_shaftbase.linear() * Eigen::Vector3d::UnitZ()) {
    // Points are placed with the predicted body motion at each step's own time (no rigid sweep).
    // A time the predictor cannot answer (before gravity alignment, beyond its history) is
    // remembered: a sweep containing it is not placed (see matchSweep).
    auto pose_at = [this](TimeNs t) -> Eigen::Isometry3d {
        if (motion_) return motion_->poseAt(t);
        auto T = predictor_.poseAt(t);
        if (T.isOk()) return *T;
        last_unknown_pose_t_ = std::max(last_unknown_pose_t_, t);
        return Eigen::Isometry3d::Identity();
    };
    assembler_ = std::make_unique<scan::SweepAssembler>(
        scan::SpinGeometry::fromCalibration(calibration), config.assembler, pose_at);
    odometry_ = std::make_unique<scan::LaserOdometry>(config.odometry);
}

LaserInertialOdometry::~LaserInertialOdometry() = default;

void LaserInertialOdometry::noteIncident(const std::optional<Incident>& incident) {
    // Only once there is a map to lose: before the first match nothing is tracked yet.
    if (!incident || !integrator_.lastScanPose()) return;
    const bool was_lost = monitor_.lost();
    const fusion::TrackingVerdict v =
        monitor_.fail(incident->t, incident->t_seen, incident->reason, incident->detail,
                      incident->reason == fusion::LostReason::kImuSilent);
    if (incident->reason == fusion::LostReason::kImuSilent) {
        relevel_pending_ = true;
        imu_back_t_ = 0;
    }
    if (v.lost && !was_lost)
        log().warn("tracking lost at t={} ns ({}): {}", incident->t,
                   fusion::lostReasonName(incident->reason), incident->detail);
}

void LaserInertialOdometry::addImu(const ImuSample& stamped) {
    ++stats_.imu_samples;
    clocks_.addImu(stamped);
    ImuSample sample = stamped;
    sample.t_host -= clocks_.imuOffset();
    noteIncident(incidents_.addImu(sample));
    if (!predictor_.addImu(sample).isOk()) {
        ++stats_.rejected;
        return;
    }
    if (!predictor_.initialized()) return;
    if (relevel_pending_ && !motion_) relevelAfterGap(sample.t_host);
    if (motion_) {
        // Diagnostics: nothing corrects the IMU prediction, so the override stands in for the
        // VIO of section 7 - the 200 Hz output is the last match carried forward by the
        // override's increments, in its frame (before the first match: the override itself),
        // and trajectory.tum measures the matcher.
        PoseEstimate ref;
        ref.t_host = sample.t_host;
        ref.T_world_body = motion_->poseAt(sample.t_host);
        ref.source = PoseSource::kVisualOdometry;
        integrator_.setVisualPose(ref);
        if (!integrator_.lastScanPose()) {
            ref.tracking_lost = monitor_.lost();
            poses_.push_back(ref);
            trajectory_.add(ref);
            ++stats_.poses_out;
            return;
        }
    }
    // Transform integration (section 7): the latest scan-matching pose + prediction since.
    auto pose = integrator_.poseAt(sample.t_host);
    if (pose.isOk()) {
        pose->tracking_lost = monitor_.lost();
        // The camera's directions while its frames keep coming (a bypassed camera gives none).
        if (!visual_.empty() &&
            sample.t_host - visual_.back().t <= static_cast<TimeNs>(config_.visual_max_gap_s * 1e9))
            pose->visual_solved_dof_mask = visual_.back().mask;
        poses_.push_back(*pose);
        trajectory_.add(*pose);
        ++stats_.poses_out;
    }
}

void LaserInertialOdometry::addEncoder(const EncoderSample& stamped) {
    ++stats_.encoder_samples;
    if (!config_.laser_enabled) return;
    clocks_.addEncoder(stamped);
    EncoderSample sample = stamped;
    sample.t_host -= clocks_.encoderOffset();
    if (!assembler_->addEncoder(sample).isOk()) ++stats_.rejected;
    processSweeps();
}

void LaserInertialOdometry::addScan(const LaserScan& scan) {
    ++stats_.scans;
    if (!config_.laser_enabled) return;
    noteIncident(incidents_.addScan(scan));
    if (!assembler_->addScan(scan).isOk()) ++stats_.rejected;
    processSweeps();
}

void LaserInertialOdometry::addVisualPose(const PoseEstimate& pose, const Matrix6d& solved_world) {
    if (!predictor_.initialized() || !pose.T_world_body.matrix().allFinite()) return;
    if (!visual_.empty() && pose.t_host <= visual_.back().t) return;  // out of order
    visual_.push_back({pose.t_host, solved_world, pose.T_world_body, pose.solved_dof_mask});
    // Long enough for a sweep matched a couple of sweeps after its start (the integrator's too).
    while (!visual_.empty() && visual_.front().t < pose.t_host - 5 * kNsPerSec) visual_.pop_front();
    if (config_.laser_enabled || motion_) return;
    integrator_.setVisualPose(pose);
    // Visual-inertial only: the VIO's pose is the measurement (as a match would be, section 7):
    // it corrects the IMU predictor in the directions it solved and anchors the 200 Hz output.
    if (pose.t_host - last_visual_feedback_t_ <
        static_cast<TimeNs>(config_.visual_feedback_interval_s * 1e9))
        return;
    last_visual_feedback_t_ = pose.t_host;
    PoseEstimate anchor = pose;
    anchor.source = PoseSource::kVisualOdometry;
    trajectory_.anchor(anchor, [this](TimeNs t) { return carriedPose(t); });
    if (config_.imu_feedback &&
        !predictor_.correct(pose.t_host, pose.T_world_body, solved_world).isOk())
        ++stats_.rejected;
    integrator_.setScanPose(anchor);
}

std::optional<Eigen::Isometry3d> LaserInertialOdometry::visualPoseAt(TimeNs t) const {
    if (visual_.empty() || t < visual_.front().t || t > visual_.back().t) return std::nullopt;
    for (std::size_t i = 1; i < visual_.size(); ++i) {
        if (visual_[i].t < t) continue;
        const VisualSolve& a = visual_[i - 1];
        const VisualSolve& b = visual_[i];
        return interpolate(a.T_chain, b.T_chain,
                           static_cast<double>(t - a.t) / static_cast<double>(b.t - a.t));
    }
    return visual_.back().T_chain;
}

Matrix6d LaserInertialOdometry::visualSolved(TimeNs t_from, TimeNs t_to) const {
    const auto gap = static_cast<TimeNs>(config_.visual_max_gap_s * 1e9);
    if (visual_.empty() || visual_.front().t > t_from + gap || visual_.back().t < t_to - gap)
        return Matrix6d::Zero();
    // Every direction any frame left unsolved is unsolved: the complement of the span of their
    // unsolved subspaces.
    Matrix6d unsolved = Matrix6d::Zero();
    TimeNs prev = 0;
    for (const VisualSolve& v : visual_) {
        if (v.t < t_from - gap) continue;
        if (v.t > t_to + gap) break;
        if (prev != 0 && v.t - prev > gap) return Matrix6d::Zero();
        prev = v.t;
        unsolved += Matrix6d::Identity() - v.solved_world;
    }
    if (prev == 0) return Matrix6d::Zero();
    return Matrix6d::Identity() - scan::rangeProjector(unsolved, 0.5);
}

void LaserInertialOdometry::finish() {
    if (config_.laser_enabled) {
        processSweeps();
        scan::Sweep last = assembler_->flush();
        if (!last.empty()) matchSweep(std::move(last));
    }
    trajectory_.flush();
}

Result<Eigen::Isometry3d> LaserInertialOdometry::carriedPose(TimeNs t) const {
    auto p = integrator_.poseAt(t);
    if (!p) return p.status();
    return p->T_world_body;
}

void LaserInertialOdometry::processSweeps() {
    for (scan::Sweep& sweep : assembler_->takeSweeps()) matchSweep(std::move(sweep));
}

void LaserInertialOdometry::matchSweep(scan::Sweep sweep) {
    const std::uint64_t ordinal = assembled_sweeps_++;
    // Without a motion estimate for every step (before gravity alignment) the sweep cannot be
    // placed: matching it would put a wrongly oriented copy of the scene into the map.
    if (!predictor_.initialized() || sweep.points.size() < 100 ||
        sweep.t_start <= last_unknown_pose_t_ || relevel_pending_) {
        ++stats_.unplaced_sweeps;
        return;
    }
    // Diagnostics (a motion override): the matcher alone, from the override, no feedback.
    const bool reference = static_cast<bool>(motion_);
    // The pose is unknown (an IMU gap, or a loss the matches did not recover): the prediction
    // would place the sweeps smeared and drifting away (after a gap its velocity and heading are
    // held ones), and matching them to the scan's map from there converges to a wrong place. The
    // scan's map is frozen for the relocaliser; the lost sweeps are tracked on a map of their own
    // (the IMU's frame since the loss), which the matches' feedback keeps the predictor honest on,
    // until the relocaliser finds that map's place on the scan's.
    const bool relocating = monitor_.awaitingRelocalisation() && !reference;
    if (relocating && !frozen_) {
        frozen_ = std::move(odometry_);
        odometry_ = std::make_unique<scan::LaserOdometry>(config_.odometry);
    }
    std::optional<std::vector<scan::PosePrior>> priors;
    // The directions the VIO solved since the previous match: its increment carries the prior
    // there (eq. 17); elsewhere the prior holds the IMU prediction's uncertainty (eq. 22).
    Matrix6d visual = Matrix6d::Zero();
    if (!visual_.empty() && integrator_.lastScanPose())
        visual = visualSolved(integrator_.lastScanPose()->t_host, sweep.t_start);
    const bool with_visual = !visual.isZero();
    if (reference) {
        priors = motion_->matchPrior(sweep, stats_.sweeps);
    } else if (config_.imu_feedback) {
        // The predictor was corrected by the previous match while this sweep was assembled:
        // place every point again with the corrected motion, so the sweep is rigid in one frame.
        auto pose_at = [this](TimeNs t) { return predictor_.poseAt(t); };
        auto integrated = integrator_.poseAt(sweep.t_start);
        if (recompensateSweep(sweep, pose_at).isOk() && integrated.isOk()) {
            // The prior of eq. (18): the transform-integrated pose (section 7), i.e. the last
            // match composed with the corrected prediction since. It agrees with the map in every
            // DOF, also where the predictor held its own estimate (unsolved directions), and
            // counts no correction twice.
            scan::PosePrior prior;
            prior.T_world_body = integrated->T_world_body;
            if (with_visual) {
                // Eq. (17) where it matters, eq. (22) elsewhere: the last match carried forward
                // by the VIO's increment in the directions the camera solved and the laser left
                // unsolved last time (the tunnel's axis); in the others the IMU prediction, which
                // the laser keeps corrected (on structured walks the VIO's increments are the
                // worse ones: house 60 s 0.08 % -> 13 % drift when they carried every direction).
                const auto& last = integrator_.lastScanPose();
                const auto Tv0 = visualPoseAt(last->t_host);
                const auto Tv1 = visualPoseAt(sweep.t_start);
                if (Tv0 && Tv1) {
                    const Eigen::Isometry3d T_vio = last->T_world_body * (Tv0->inverse() * *Tv1);
                    const Matrix6d only_camera_world =
                        Matrix6d::Identity() -
                        scan::rangeProjector(
                            Matrix6d::Identity() - visual + last_laser_solved_world_, 0.5);
                    const Matrix6d P = scan::bodyToWorldAxes(
                        only_camera_world, prior.T_world_body.linear().transpose());
                    prior.T_world_body = prior.T_world_body *
                                         expSE3(P * logSE3(prior.T_world_body.inverse() * T_vio));
                }
            }
            prior.information = predictionInformation(
                prior.T_world_body.linear(),
                with_visual ? Matrix6d(scan::rangeProjector(last_solved_world_ + visual, 1e-3))
                            : last_solved_world_);
            priors.emplace({prior});
        } else {
            ++stats_.rejected;
        }
    }
    // The prior (eqs. 17-18): without feedback the odometry composes the last refined pose with
    // the predicted motion since then and adds its uncertainty. The tracking monitor judges the
    // match before it is merged: an inconsistent one stays out of the map.
    fusion::TrackingVerdict verdict;
    auto gate = [&](const scan::SweepResult& m) {
        fusion::SweepEvidence e;
        e.t = sweep.t_start;
        e.T_world_prior = m.T_world_prior;
        e.T_world_match = m.match.T_world_body;
        e.prior_information = priorInformation(priors);
        e.founds_map = m.first_sweep;
        e.enough_matches = m.match.enough_matches;
        e.features = m.edges + m.planars;
        e.matches = static_cast<std::size_t>(m.match.edge_matches) +
                    static_cast<std::size_t>(m.match.plane_matches);
        e.rms_m = m.match.rms_m;
        verdict = monitor_.assess(e);
        // The lost sweeps' own map grows with every consistent one; none enters the scan's.
        if (relocating) return verdict.consistent || m.first_sweep;
        return verdict.enters_map;
    };
    scan::SweepResult r = odometry_->process(sweep, priors, gate);
    ++stats_.sweeps;
    // A match that does not fit the map is no measurement: the pose stays the prediction's. One
    // that fits but disagrees with the prediction corrects it (the map is the reference), and
    // stays out of the map until the monitor sees consistent sweeps again.
    if (!verdict.fits_map) {
        r.pose.T_world_body = r.T_world_prior;
        r.pose.solved_dof_mask = 0;
        r.solved_projector_world.setZero();
    }
    if (relocating) relocalise(sweep.t_start, r);
    PoseEstimate scan_pose = r.pose;
    scan_pose.t_host = sweep.t_start;
    scan_pose.source = PoseSource::kScanMatching;
    scan_pose.tracking_lost = verdict.lost;
    // The kept trajectory's segment since the previous match, closed by this one before the
    // feedback re-propagates the prediction from t_start.
    trajectory_.anchor(scan_pose, [this](TimeNs t) { return carriedPose(t); });
    if (config_.imu_feedback && !reference && !r.first_sweep)
        feedBack(sweep, r, verdict.fits_map && r.match.enough_matches, visual);
    integrator_.setScanPose(scan_pose);
    if (!reference) trackClocks(ordinal, sweep.t_start, r, verdict, relocating);

    RegisteredSweep reg;
    reg.result = r;
    reg.tracking = verdict;
    reg.visual_solved_dof_mask = scan::maskFromProjector(visual);
    reg.points_world.reserve(sweep.points.size());
    reg.intensities.reserve(sweep.points.size());
    reg.times.reserve(sweep.points.size());
    const Eigen::Isometry3d& T = r.pose.T_world_body;
    for (const scan::SweepPoint& p : sweep.points) {
        reg.points_world.push_back((T * p.p_start).cast<float>());
        reg.intensities.push_back(p.intensity);
        reg.times.push_back(p.t);
    }
    reg.sweep = sweep;
    sweeps_.push_back(std::move(reg));
}

void LaserInertialOdometry::trackClocks(std::uint64_t ordinal, TimeNs t_start,
                                        const scan::SweepResult& r,
                                        const fusion::TrackingVerdict& verdict, bool relocating) {
    // Only matches the monitor trusted on the scan's own map: a lost map's are in another frame.
    const bool trusted = verdict.enters_map && verdict.fits_map && r.match.enough_matches &&
                         !r.first_sweep && !relocating;
    clocks_.addSweep(ordinal, t_start, Eigen::Quaterniond(r.pose.T_world_body.linear()), trusted);
    const ClockTrackerStats before = clocks_.stats();
    if (!clocks_.update(t_start)) return;
    const ClockTrackerStats& now = clocks_.stats();
    if (before.determined == 0)
        log().info(
            "clocks: tracked online from t={} ns: IMU {:+.2f} ms, encoder {:+.2f} ms "
            "(moving toward {:+.2f} / {:+.2f} ms)",
            t_start, now.imu_offset_s * 1e3, now.encoder_offset_s * 1e3, now.imu_target_s * 1e3,
            now.encoder_target_s * 1e3);
    if ((now.imu_at_bound && !before.imu_at_bound) ||
        (now.encoder_at_bound && !before.encoder_at_bound))
        log().warn(
            "clocks: an offset wants more than its bound (IMU {:+.2f} ms, encoder {:+.2f} "
            "ms; bounds {:.1f} / {:.1f} ms): device.yaml's latencies look wrong; measure "
            "them with `handscan calibrate`",
            now.imu_target_s * 1e3, now.encoder_target_s * 1e3, config_.clocks.imu_bound_s * 1e3,
            config_.clocks.encoder_bound_s * 1e3);
}

void LaserInertialOdometry::relevelAfterGap(TimeNs t) {
    if (imu_back_t_ == 0) imu_back_t_ = t;
    if (toSeconds(t - imu_back_t_) < config_.relevel_window_s) return;
    relevel_pending_ = false;
    // Sweeps holding a time before this were placed with the tilt still in: not placed.
    last_unknown_pose_t_ = std::max(last_unknown_pose_t_, t);
    const auto tilt = predictor_.relevel(imu_back_t_, t);
    if (!tilt.isOk()) {
        log().warn("after the IMU gap: {}", tilt.status().message());
        return;
    }
    log().info("after the IMU gap: attitude levelled from the accelerometer by {:.1f} deg",
               *tilt * 180.0 / M_PI);
}

void LaserInertialOdometry::relocalise(TimeNs t, scan::SweepResult& r) {
    const auto T_map_odom = relocaliser_.addSweep(*frozen_, t, r.pose.T_world_body, r.features);
    if (!T_map_odom) return;
    // The scan goes on in its own frame and map; the lost sweeps' map is dropped with them.
    odometry_ = std::move(frozen_);
    const Eigen::Isometry3d& C = *T_map_odom;
    predictor_.moveWorld(C);
    if (auto last = integrator_.lastScanPose()) {
        last->T_world_body = C * last->T_world_body;
        integrator_.setScanPose(*last);
    }
    r.pose.T_world_body = C * r.pose.T_world_body;
    r.T_world_prior = C * r.T_world_prior;
    const double moved_m = C.translation().norm();
    const double turned_deg = Eigen::AngleAxisd(C.linear()).angle() * 180.0 / M_PI;
    char detail[128];
    std::snprintf(detail, sizeof detail, "relocalised at %.2f s on the map: moved %.2f m, %.1f deg",
                  toSeconds(t), moved_m, turned_deg);
    monitor_.relocalised(t, detail);
    log().info("{}", detail);
}

void LaserInertialOdometry::feedBack(const scan::Sweep& sweep, const scan::SweepResult& r,
                                     bool trusted, const Matrix6d& visual_solved) {
    // Eqs. (23)-(27) simplified: the camera's and the laser's corrections are not weighed
    // against each other; the match (which kept the visual-inertial prior where the laser was
    // degenerate) is the pose, trusted in the directions either module solved.
    const bool with_visual = !visual_solved.isZero();
    last_laser_solved_world_ = trusted ? r.solved_projector_world : Matrix6d::Zero();
    if (trusted && with_visual) {
        const Matrix6d solved =
            scan::rangeProjector(r.solved_projector_world + visual_solved, 1e-3);
        if (!predictor_.correct(sweep.t_start, r.pose.T_world_body, solved).isOk())
            ++stats_.rejected;
        last_solved_world_ = solved;
        return;
    }
    if (trusted) {
        // Feedback to the IMU predictor only in the directions the matcher solved (section 8):
        // the eq. (21) subspace itself, in the predictor's world-axis coordinates, not the
        // per-axis mask (a degenerate corridor axis at 45 degrees to the world axes would
        // otherwise cost both horizontal axes, or leak into one of them).
        if (!predictor_.correct(sweep.t_start, r.pose.T_world_body, r.solved_projector_world)
                 .isOk())
            ++stats_.rejected;
        last_solved_world_ = r.solved_projector_world;
        return;
    }
    // A sweep that solved nothing (too few matches: an open field, a fog of noise; or a match
    // the tracking monitor refused) is still feedback: every direction is unsolved, so the pose
    // stays the prediction's and the velocity gets the motion prior instead of running on with
    // the IMU alone.
    if (!predictor_.correct(sweep.t_start, r.pose.T_world_body, visual_solved).isOk())
        ++stats_.rejected;
    last_solved_world_ = visual_solved;
}

Matrix6d LaserInertialOdometry::priorInformation(
    const std::optional<std::vector<scan::PosePrior>>& priors) const {
    Matrix6d info = Matrix6d::Zero();
    if (priors) {
        for (const scan::PosePrior& p : *priors) info += p.information;
        return info;
    }
    // Without a prior of ours the odometry composes its own (eq. 16) with these deviations.
    const auto& oc = config_.odometry;
    info.diagonal().head<3>().setConstant(1.0 / (oc.prior_sigma_rot_rad * oc.prior_sigma_rot_rad));
    info.diagonal().tail<3>().setConstant(1.0 / (oc.prior_sigma_trans_m * oc.prior_sigma_trans_m));
    return info;
}

Matrix6d LaserInertialOdometry::predictionInformation(const Eigen::Matrix3d& R_world_body,
                                                      const Matrix6d& solved_world) const {
    const double sr = config_.imu_prior_sigma_rot_rad, st = config_.imu_prior_sigma_trans_m;
    Matrix6d solved = Matrix6d::Zero();
    solved.diagonal().head<3>().setConstant(1.0 / (sr * sr));
    solved.diagonal().tail<3>().setConstant(1.0 / (st * st));
    // Every direction solved last time (the usual case): the prediction holds everywhere.
    if ((Matrix6d::Identity() - solved_world).norm() < 1e-6) return solved;
    // Eq. (18) with the prediction's own uncertainty: P I_solved P + (I - P) I_unsolved (I - P),
    // P the last feedback's solved subspace in the body tangent of the prior's error.
    const double su = config_.unsolved_prior_sigma_trans_m;
    Matrix6d unsolved = solved;
    unsolved.diagonal().tail<3>().setConstant(1.0 / (su * su));
    const Matrix6d P = scan::bodyToWorldAxes(solved_world, R_world_body.transpose());
    const Matrix6d Q = Matrix6d::Identity() - P;
    return P * solved * P + Q * unsolved * Q;
}

std::vector<PoseEstimate> LaserInertialOdometry::takePoses() {
    std::vector<PoseEstimate> out;
    out.swap(poses_);
    return out;
}

std::vector<PoseEstimate> LaserInertialOdometry::takeTrajectory() { return trajectory_.take(); }

std::vector<RegisteredSweep> LaserInertialOdometry::takeSweeps() {
    std::vector<RegisteredSweep> out;
    out.swap(sweeps_);
    return out;
}

}  // namespace handscan::lio
