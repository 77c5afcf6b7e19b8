#include "handscan/lio/laser_inertial_odometry.hpp"

#include "handscan/core/log.hpp"

namespace handscan::lio {

LaserInertialOdometry::LaserInertialOdometry(const LioConfig& config, const Calibration& calibration)
    : config_(config), predictor_(config.imu, calibration.T_camera_imu()), integrator_(predictor_) {
    // Points are placed with the predicted body motion at each step's own time (no rigid sweep).
    // A time the predictor cannot answer (before gravity alignment, beyond its history) is
    // remembered: a sweep containing it is not placed (see matchSweep).
    auto pose_at = [this](TimeNs t) -> Eigen::Isometry3d {
        auto T = predictor_.poseAt(t);
        if (T.isOk()) return *T;
        last_unknown_pose_t_ = std::max(last_unknown_pose_t_, t);
        return Eigen::Isometry3d::Identity();
    };
    assembler_ = std::make_unique<scan::SweepAssembler>(scan::SpinGeometry::fromCalibration(calibration),
                                                        config.assembler, pose_at);
    odometry_ = std::make_unique<scan::LaserOdometry>(config.odometry);
}

LaserInertialOdometry::~LaserInertialOdometry() = default;

void LaserInertialOdometry::addImu(const ImuSample& sample) {
    ++stats_.imu_samples;
    if (!predictor_.addImu(sample).isOk()) {
        ++stats_.rejected;
        return;
    }
    if (!predictor_.initialized()) return;
    // Transform integration (section 7): the latest scan-matching pose + prediction since.
    auto pose = integrator_.poseAt(sample.t_host);
    if (pose.isOk()) {
        poses_.push_back(*pose);
        ++stats_.poses_out;
    }
}

void LaserInertialOdometry::addEncoder(const EncoderSample& sample) {
    ++stats_.encoder_samples;
    if (!config_.laser_enabled) return;
    if (!assembler_->addEncoder(sample).isOk()) ++stats_.rejected;
    processSweeps();
}

void LaserInertialOdometry::addScan(const LaserScan& scan) {
    ++stats_.scans;
    if (!config_.laser_enabled) return;
    if (!assembler_->addScan(scan).isOk()) ++stats_.rejected;
    processSweeps();
}

void LaserInertialOdometry::finish() {
    if (!config_.laser_enabled) return;
    processSweeps();
    scan::Sweep last = assembler_->flush();
    if (!last.empty()) matchSweep(last);
}

void LaserInertialOdometry::processSweeps() {
    for (const scan::Sweep& sweep : assembler_->takeSweeps()) matchSweep(sweep);
}

void LaserInertialOdometry::matchSweep(const scan::Sweep& sweep) {
    // Without a motion estimate for every step (before gravity alignment) the sweep cannot be
    // placed: matching it would put a wrongly oriented copy of the scene into the map.
    if (!predictor_.initialized() || sweep.points.size() < 100 || sweep.t_start <= last_unknown_pose_t_) {
        ++stats_.unplaced_sweeps;
        return;
    }
    // The prior (eqs. 17-18): the predicted pose at the sweep's start; the odometry adds its
    // uncertainty since the last refined sweep.
    scan::SweepResult r = odometry_->process(sweep);
    ++stats_.sweeps;
    if (config_.imu_feedback && !r.first_sweep && r.match.enough_matches) {
        // Feedback to the IMU predictor only in the directions the matcher solved (section 8).
        if (!predictor_.correct(sweep.t_start, r.pose.T_world_body, r.pose.solved_dof_mask).isOk()) ++stats_.rejected;
    }
    PoseEstimate scan_pose = r.pose;
    scan_pose.t_host = sweep.t_start;
    scan_pose.source = PoseSource::kScanMatching;
    integrator_.setScanPose(scan_pose);

    RegisteredSweep reg;
    reg.result = r;
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

std::vector<PoseEstimate> LaserInertialOdometry::takePoses() {
    std::vector<PoseEstimate> out;
    out.swap(poses_);
    return out;
}

std::vector<RegisteredSweep> LaserInertialOdometry::takeSweeps() {
    std::vector<RegisteredSweep> out;
    out.swap(sweeps_);
    return out;
}

}  // namespace handscan::lio
