#include "handscan/vio/visual_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace handscan::vio {

PoseEstimate VioFrameResult::pose() const {
    PoseEstimate p;
    p.t_host = t;
    p.T_world_body = T_world_cam;
    p.solved_dof_mask = solved_dof_mask;
    p.source = PoseSource::kVisualOdometry;
    return p;
}

VisualInertialOdometry::VisualInertialOdometry(const CameraIntrinsics& camera,
                                               const VioConfig& config)
    : config_(config),
      camera_(camera),
      tracker_(config.tracker),
      depth_(config.depth),
      estimator_(config.motion) {}

void VisualInertialOdometry::reset() {
    tracker_.reset();
    tracks_.clear();
    started_ = false;
    prev_xbar_.clear();
    T_l_prev_ = Eigen::Isometry3d::Identity();
}

Result<VioFrameResult> VisualInertialOdometry::processFrame(
    const Image& image, const std::optional<Eigen::Isometry3d>& imu_prev_cur) {
    if (image.format != PixelFormat::kGrey8) {
        return Status(StatusCode::kUnsupported,
                      "vio: tracking camera frame " + std::to_string(image.sequence) +
                          " is not GREY; set tracking_camera.format: GREY in device.yaml");
    }
    if (image.width <= 0 || image.height <= 0 || image.stride_bytes < image.width ||
        image.data.size() <
            static_cast<std::size_t>(image.stride_bytes) * static_cast<std::size_t>(image.height)) {
        return Status(StatusCode::kInvalidArgument,
                      "vio: tracking camera frame " + std::to_string(image.sequence) +
                          " is shorter than its width x height; frame dropped");
    }
    const cv::Mat grey(image.height, image.width, CV_8UC1,
                       const_cast<std::uint8_t*>(image.data.data()),  // read only below
                       static_cast<std::size_t>(image.stride_bytes));
    return processFrame(image.t_host, grey, imu_prev_cur);
}

Result<VioFrameResult> VisualInertialOdometry::processFrame(
    TimeNs t, const cv::Mat& grey, const std::optional<Eigen::Isometry3d>& imu_prev_cur) {
    if (grey.type() != CV_8UC1 || grey.cols != camera_.width() || grey.rows != camera_.height()) {
        return Status(StatusCode::kInvalidArgument,
                      "vio: frame is " + std::to_string(grey.cols) + "x" +
                          std::to_string(grey.rows) + " (type " + std::to_string(grey.type()) +
                          "), camchain cam0 says " + std::to_string(camera_.width()) + "x" +
                          std::to_string(camera_.height()) + " grey; frame dropped");
    }
    VioFrameResult out;
    out.t = t;
    if (pending_world_) {
        if (started_) reset();
        T_world_cam_ = *pending_world_;
        pending_world_.reset();
    }
    // Where the IMU's rotation since the last frame moves each feature (eq. 10's T_{c-1}^c
    // without its translation, whose effect needs depth and is small at 50 Hz).
    const std::vector<cv::Point2f>* predicted = nullptr;
    if (started_ && imu_prev_cur && prev_xbar_.size() == tracker_.features().size()) {
        std::vector<Eigen::Vector3d> rays;
        rays.reserve(prev_xbar_.size());
        for (const Eigen::Vector2d& x : prev_xbar_)
            rays.push_back(imu_prev_cur->linear() * Eigen::Vector3d(x.x(), x.y(), 1.0));
        camera_.project(rays, predicted_px_);
        const auto& feats = tracker_.features();
        for (std::size_t i = 0; i < feats.size(); ++i) {
            const cv::Point2f& p = predicted_px_[i];
            if (!(p.x >= 0.0f && p.y >= 0.0f && p.x <= static_cast<float>(camera_.width() - 1) &&
                  p.y <= static_cast<float>(camera_.height() - 1)))
                predicted_px_[i] = feats[i].px;  // leaves the image: searched where it was
        }
        predicted = &predicted_px_;
    }
    const TrackerFrameStats stats = tracker_.track(grey, predicted);
    out.detected = stats.detected;
    const double focal = camera_.focalLength();
    // Normalised coordinates of every feature, in the tracker's order (kept through drop()).
    std::vector<cv::Point2f> px;
    px.reserve(tracker_.features().size());
    for (const TrackedFeature& f : tracker_.features()) px.push_back(f.px);
    std::vector<Eigen::Vector2d> xbar;
    camera_.undistort(px, xbar);

    if (started_) {
        // eq. (10): the IMU prediction from the key-frame, T_l^c = T_{c-1}^c T_l^{c-1}.
        const Eigen::Isometry3d T_init =
            imu_prev_cur ? Eigen::Isometry3d(*imu_prev_cur * T_l_prev_) : T_l_prev_;
        std::vector<FeatureConstraint> constraints;
        std::vector<std::uint64_t> ids;
        const auto& feats = tracker_.features();
        for (std::size_t i = 0; i < feats.size(); ++i) {
            auto it = tracks_.find(feats[i].id);
            if (it == tracks_.end() || !it->second.in_keyframe) continue;
            it->second.constraint.xbar_c = xbar[i];
            constraints.push_back(it->second.constraint);
            ids.push_back(feats[i].id);
        }
        std::optional<ImuMotionPrior> prior;
        if (imu_prev_cur) {
            // eq. (11): Sigma from the time since the key-frame (at least one frame's worth).
            const double dt = std::max(1e-2, toSeconds(t - keyframe_t_));
            ImuMotionPrior p;
            p.T_l_c = T_init;
            const double sr = config_.imu_sigma_rot_rad_per_s * dt;
            const double st = config_.imu_sigma_trans_m_per_s * dt;
            p.information.diagonal() << Eigen::Vector3d::Constant(1.0 / (sr * sr)),
                Eigen::Vector3d::Constant(1.0 / (st * st));
            prior = p;
        }
        const MotionResult m = estimator_.estimate(constraints, T_init, prior, focal);
        std::vector<std::uint64_t> outliers;
        for (std::size_t i = 0; i < constraints.size(); ++i) {
            if (!m.inlier[i]) {
                outliers.push_back(ids[i]);
                tracks_.erase(ids[i]);
                continue;
            }
            const int kind = tracks_[ids[i]].depth_kind;
            (kind == 1   ? out.with_laser_depth
             : kind == 2 ? out.triangulated
                         : out.without_depth) += 1;
        }
        if (!outliers.empty()) {
            // drop() keeps the order of the others: filter xbar alongside.
            std::size_t kept_xbar = 0;
            for (std::size_t i = 0; i < feats.size(); ++i) {
                if (std::find(outliers.begin(), outliers.end(), feats[i].id) == outliers.end())
                    xbar[kept_xbar++] = xbar[i];
            }
            xbar.resize(kept_xbar);
            tracker_.drop(outliers);
        }
        out.outliers = static_cast<int>(outliers.size());
        out.rms_px = m.rms_px;
        out.degeneracy = m.degeneracy;
        out.T_l_c = m.T_l_c;
        T_l_prev_ = m.T_l_c;
        T_world_cam_ = T_world_keyframe_ * m.T_l_c.inverse();
        out.solved_dof_mask = scan::maskFromProjector(
            scan::bodyToWorldAxes(m.degeneracy.projection, T_world_cam_.linear()));

        // Key-frame (5.1): too many of its features lost, or the image moved too far from it.
        const int kept = m.inliers;
        bool new_keyframe = kept < (1.0 - config_.keyframe_max_lost_fraction) * keyframe_features_;
        if (!new_keyframe && kept > 0) {
            std::vector<float> shift;
            for (const TrackedFeature& f : tracker_.features()) {
                auto it = tracks_.find(f.id);
                if (it == tracks_.end() || !it->second.in_keyframe) continue;
                const cv::Point2f d = f.px - it->second.keyframe_px;
                shift.push_back(std::sqrt(d.dot(d)));
            }
            if (!shift.empty()) {
                const auto mid = shift.begin() + static_cast<std::ptrdiff_t>(shift.size() / 2);
                std::nth_element(shift.begin(), mid, shift.end());
                new_keyframe = shift[shift.size() / 2] >
                               (1.0 - config_.keyframe_min_overlap) * camera_.width();
            }
        }
        out.keyframe = new_keyframe;
    } else {
        out.keyframe = true;
        out.degeneracy = scan::analyzeDegeneracy(Matrix6d::Zero(), 1.0);  // nothing solved yet
    }

    // First sightings (for triangulation) in the pose just estimated.
    const auto& feats = tracker_.features();
    for (std::size_t i = 0; i < feats.size(); ++i) {
        if (tracks_.count(feats[i].id) != 0) continue;
        Track tr;
        tr.first_origin_world = T_world_cam_.translation();
        tr.first_ray_world =
            T_world_cam_.linear() * Eigen::Vector3d(xbar[i].x(), xbar[i].y(), 1.0).normalized();
        tracks_.emplace(feats[i].id, tr);
    }
    if (out.keyframe) startKeyframe(t, xbar);
    laser_frame_pose_.reset();
    prev_xbar_ = std::move(xbar);  // the features' normalised coordinates, in the tracker's order
    started_ = true;
    out.T_world_cam = T_world_cam_;
    out.features = static_cast<int>(feats.size());
    return out;
}

void VisualInertialOdometry::startKeyframe(TimeNs t, const std::vector<Eigen::Vector2d>& xbar) {
    depth_.build(t, laser_frame_pose_.value_or(T_world_cam_));
    const auto& feats = tracker_.features();
    std::unordered_map<std::uint64_t, Track> kept;
    kept.reserve(feats.size());
    for (std::size_t i = 0; i < feats.size(); ++i) {
        auto it = tracks_.find(feats[i].id);
        if (it == tracks_.end()) continue;
        Track tr = it->second;
        const Eigen::Vector3d ray(xbar[i].x(), xbar[i].y(), 1.0);
        std::optional<double> depth = depth_.depthOf(xbar[i]);
        tr.depth_kind = depth ? 1 : 0;
        if (!depth) {
            depth = triangulate(tr, ray);
            if (depth) tr.depth_kind = 2;
        }
        tr.constraint.has_depth = depth.has_value();
        tr.constraint.X_l = depth ? Eigen::Vector3d(ray * *depth) : ray;
        tr.constraint.xbar_c = xbar[i];
        tr.keyframe_px = feats[i].px;
        tr.in_keyframe = true;
        kept.emplace(feats[i].id, tr);
    }
    tracks_ = std::move(kept);
    T_world_keyframe_ = T_world_cam_;
    T_l_prev_ = Eigen::Isometry3d::Identity();
    keyframe_t_ = t;
    keyframe_features_ = static_cast<int>(tracks_.size());
}

std::optional<double> VisualInertialOdometry::triangulate(const Track& track,
                                                          const Eigen::Vector3d& ray_cam) const {
    // Midpoint of the closest approach of the first sighting's ray and the current one.
    const Eigen::Vector3d o1 = track.first_origin_world;
    const Eigen::Vector3d d1 = track.first_ray_world;
    const Eigen::Vector3d o2 = T_world_cam_.translation();
    const Eigen::Vector3d d2 = T_world_cam_.linear() * ray_cam.normalized();
    const double c = d1.dot(d2);
    if (std::acos(std::clamp(c, -1.0, 1.0)) < config_.triangulation_min_parallax_rad)
        return std::nullopt;
    const Eigen::Vector3d w = o1 - o2;
    const double den = 1.0 - c * c;
    const double s1 = (c * d2.dot(w) - d1.dot(w)) / den;
    const double s2 = (d2.dot(w) - c * d1.dot(w)) / den;
    if (s1 <= 0.0 || s2 <= 0.0) return std::nullopt;
    const Eigen::Vector3d P = 0.5 * (o1 + s1 * d1 + o2 + s2 * d2);
    const double z = (T_world_cam_.inverse() * P).z();
    if (z <= config_.depth.min_depth_m || z > config_.triangulation_max_depth_m)
        return std::nullopt;
    return z;
}

}  // namespace handscan::vio
