#include "handscan/worker/visual_stage.hpp"

#include "handscan/core/log.hpp"
#include "handscan/scan/degeneracy.hpp"

namespace handscan::worker {

VisualStage::VisualStage(const Calibration& calibration, const vio::VioConfig& config)
    : vio_(calibration.tracking, config) {}

void VisualStage::frame(const Image& image, lio::LaserInertialOdometry& lio) {
    ++stats_.frames;
    if (!lio.aligned()) return;  // no IMU prediction before the gravity alignment
    const TimeNs t = image.t_host;
    if (t_prev_ && t <= *t_prev_) {
        ++stats_.errors;
        return;
    }
    auto T_now = lio.predictor().poseAt(t);
    if (!T_now) {
        ++stats_.errors;
        return;
    }
    const bool first = !t_prev_;
    std::optional<Eigen::Isometry3d> imu_prev_cur;
    if (first) {
        // The chain starts where the pipeline's output is (the map frame).
        auto start = lio.integratedPoseAt(t);
        vio_.setWorldPose(start ? start->T_world_body : *T_now);
    } else if (auto T_prev = lio.predictor().poseAt(*t_prev_)) {
        // eq. (10): T_{c-1}^c maps points of the previous frame into this one.
        imu_prev_cur = T_now->inverse() * *T_prev;
    }
    t_prev_ = t;
    // The depth map is seen from where the laser-inertial odometry puts the camera: the laser
    // points are in its frame, and the VIO's chain drifts away from it between matches.
    if (auto T_map = lio.integratedPoseAt(t)) vio_.setLaserFramePose(T_map->T_world_body);
    auto r = vio_.processFrame(image, imu_prev_cur);
    if (!r) {
        if (stats_.errors++ == 0) log().warn("tracking camera: {}", r.status().message());
        return;
    }
    if (stats_.processed++ == 0) stats_.t_first = t;
    stats_.keyframes += r->keyframe ? 1 : 0;
    stats_.features_sum += r->features;
    stats_.laser_depth_sum += r->with_laser_depth;
    stats_.triangulated_sum += r->triangulated;
    solved_now_ = r->solved_dof_mask;
    if (first) return;  // a first frame has nothing to solve against
    if (r->solved_dof_mask == 0) {
        // Bypassed (dark, texture-less): from this very frame, nothing goes on.
        if (!bypassedNow()) bypassed_.push_back({t, 0, 0});
        ++bypassed_.back().frames;
        return;
    }
    if (bypassedNow()) bypassed_.back().t_end = t;
    ++stats_.used;
    stats_.all_solved += r->solved_dof_mask == scan::kAllDof ? 1 : 0;
    lio.addVisualPose(r->pose(),
                      scan::bodyToWorldAxes(r->degeneracy.projection, r->T_world_cam.linear()));
}

void VisualStage::sweep(const lio::RegisteredSweep& sweep) {
    if (sweep.points_world.empty() || !sweep.tracking.enters_map) return;
    // In the laser-inertial odometry's frame, like the frames' setLaserFramePose.
    std::vector<Eigen::Vector3d> points;
    points.reserve(sweep.points_world.size());
    for (const Eigen::Vector3f& p : sweep.points_world) points.push_back(p.cast<double>());
    vio_.addLaserPoints(sweep.times.empty() ? sweep.sweep.t_start : sweep.times.back(), points);
}

}  // namespace handscan::worker
