// VisualInertialOdometry (section 5, Figure 4): one tracking-camera frame at a time. Features are
// tracked (FeatureTracker), the motion from the last key-frame is estimated from them and the IMU
// prediction (MotionEstimator, eqs. 6-11), and a new key-frame starts when too many of the
// key-frame's features were lost or the image moved too far from it (5.1). Depth is associated
// at key-frames only (5.1): from the laser depth map (DepthMap, 5.3), else by triangulating the
// feature's first observation against the current one when the two rays are far enough apart
// (a two-view midpoint, not the paper's per-frame Bayesian depth filter), else the feature is
// used without depth (eq. 8).
//
// Poses: the body is the tracking camera {C}. The caller gives the IMU-predicted motion between
// consecutive frames (T_{c-1}^c of eq. 10, from ImuPredictor poses at both frame times) and the
// laser points registered in {W}; the VIO chains its poses from `T_world_cam` of the first frame.
// A key-frame's depth map is seen from the frame's pose in {W} where the caller gives it
// (setLaserFramePose), else from the chain's.
#pragma once

#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/vio/depth_map.hpp"
#include "handscan/vio/feature_tracker.hpp"
#include "handscan/vio/motion_estimator.hpp"
#include "handscan/vio/pixel_undistorter.hpp"

namespace handscan::vio {

struct VioConfig {
    FeatureTrackerConfig tracker;
    DepthMapConfig depth;
    MotionEstimatorConfig motion;
    // Key-frame (5.1): more than this fraction of the key-frame's features lost ...
    double keyframe_max_lost_fraction = 0.3;
    // ... or the image overlap below this: the key-frame features' median displacement since
    // the key-frame, as a fraction of the image width, above 1 - overlap.
    double keyframe_min_overlap = 0.8;
    // Triangulation: the two rays at least this far apart (and the point in front of both).
    double triangulation_min_parallax_rad = 0.05;
    double triangulation_max_depth_m = 30.0;
    // IMU prior information (eq. 11, Sigma): standard deviations of the predicted motion from
    // the key-frame, per second since it (the IMU drifts with time).
    double imu_sigma_rot_rad_per_s = 0.01;
    double imu_sigma_trans_m_per_s = 0.05;
};

// One frame's outcome.
struct VioFrameResult {
    TimeNs t = 0;
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_l_c = Eigen::Isometry3d::Identity();  // key-frame -> frame (eq. 5)
    scan::DegeneracyAnalysis degeneracy;  // camera constraints, body tangent (section 8)
    std::uint8_t solved_dof_mask = 0;     // world-axis DOFs (scan::DofBit order) solved
    bool keyframe = false;                // this frame became the new key-frame
    int features = 0;                     // tracked in this frame
    int with_laser_depth = 0;             // constraints by kind (eqs. 6-7 or 8)
    int triangulated = 0;
    int without_depth = 0;
    int outliers = 0;
    int detected = 0;
    double rms_px = 0.0;

    PoseEstimate pose() const;
};

class VisualInertialOdometry {
public:
    // Throws std::invalid_argument at start-up when cam0 cannot be undistorted.
    VisualInertialOdometry(const CameraIntrinsics& camera, const VioConfig& config = {});

    // Laser points registered in {W}, measured at about t.
    void addLaserPoints(TimeNs t, const std::vector<Eigen::Vector3d>& points_world) {
        depth_.addPoints(t, points_world);
    }
    // The pose of the next frame (the first, or after a reset); later frames chain from it.
    void setWorldPose(const Eigen::Isometry3d& T_world_cam) { pending_world_ = T_world_cam; }
    // The next frame's pose in {W}, the frame of the laser points, where the caller knows it
    // better than the VIO's own chain (the laser-inertial odometry's pose: the chain drifts away
    // from the map the points were registered in, and a depth map seen from the chain's pose
    // would give features the depth of their neighbours). Without it the chain's pose is used.
    void setLaserFramePose(const Eigen::Isometry3d& T_world_cam) {
        laser_frame_pose_ = T_world_cam;
    }

    // One frame (CV_8UC1, the camera's resolution). `imu_prev_cur`: T_{c-1}^c predicted by the
    // IMU (X_c = T X_{c-1}); without it the motion since the last frame is assumed zero.
    Result<VioFrameResult> processFrame(TimeNs t, const cv::Mat& grey,
                                        const std::optional<Eigen::Isometry3d>& imu_prev_cur);
    // The same from a driver's Image (GREY only: the tracking camera's format).
    Result<VioFrameResult> processFrame(const Image& image,
                                        const std::optional<Eigen::Isometry3d>& imu_prev_cur);

    void reset();
    const FeatureTracker& tracker() const { return tracker_; }
    const DepthMap& depthMap() const { return depth_; }
    const PixelUndistorter& camera() const { return camera_; }

private:
    // What the VIO knows of a feature: its key-frame constraint and its first sighting.
    struct Track {
        bool in_keyframe = false;  // has a key-frame observation (usable in eqs. 6-8)
        FeatureConstraint constraint;
        int depth_kind = 0;  // 0 none, 1 laser, 2 triangulated
        Eigen::Vector3d first_origin_world = Eigen::Vector3d::Zero();
        Eigen::Vector3d first_ray_world = Eigen::Vector3d::UnitZ();
        cv::Point2f keyframe_px;
    };

    void startKeyframe(TimeNs t, const std::vector<Eigen::Vector2d>& xbar);
    std::optional<double> triangulate(const Track& track, const Eigen::Vector3d& ray_cam) const;

    VioConfig config_;
    PixelUndistorter camera_;
    FeatureTracker tracker_;
    DepthMap depth_;
    MotionEstimator estimator_;
    std::unordered_map<std::uint64_t, Track> tracks_;
    std::vector<Eigen::Vector2d> prev_xbar_;  // last frame's features, normalised
    std::vector<cv::Point2f> predicted_px_;   // scratch: their predicted pixels
    std::optional<Eigen::Isometry3d> pending_world_;
    std::optional<Eigen::Isometry3d> laser_frame_pose_;  // of the next frame only
    bool started_ = false;
    TimeNs keyframe_t_ = 0;
    int keyframe_features_ = 0;
    Eigen::Isometry3d T_world_keyframe_ = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_l_prev_ = Eigen::Isometry3d::Identity();  // T_l^{c-1}
    Eigen::Isometry3d T_world_cam_ = Eigen::Isometry3d::Identity();
};

}  // namespace handscan::vio
