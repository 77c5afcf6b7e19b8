// Transform integration (paper section 7, Figure 12). The scan-matching pose (1 Hz here, 5 Hz in
// the paper) warrants accuracy; the visual-inertial odometry (50 Hz) and the IMU prediction
// (200 Hz) are integrated "to the front" of it for a high-rate output:
//   T(t) = T_scan(t_s) * [T_vio(t_s)^-1 T_vio(t_v)] * [T_imu(t_v)^-1 T_imu(t)]
// where t_s is the newest scan-matching pose, t_v the newest VIO pose after it (if any), and
// T_imu the IMU prediction. Each bracket is a relative motion of the body, so the drift of the
// faster modules only acts since the last scan match. Every output carries the per-DOF status of
// that scan match (section 8), and kImuPrediction with no solved DOF before the first one.
#pragma once

#include <deque>
#include <optional>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/imu/imu_predictor.hpp"

namespace handscan::fusion {

class TransformIntegrator {
public:
    explicit TransformIntegrator(const imu::ImuPredictor& predictor) : predictor_(predictor) {}

    // The newest scan-matching result (T_world_body at the time it refers to, solved DOFs).
    void setScanPose(const PoseEstimate& scan);
    // A visual-inertial odometry pose (its own world frame; only increments are used).
    void setVisualPose(const PoseEstimate& vio);

    // The integrated body pose at time t (normally the newest IMU sample's time).
    Result<PoseEstimate> poseAt(TimeNs t) const;
    const std::optional<PoseEstimate>& lastScanPose() const { return scan_; }

private:
    // VIO pose at time t by interpolation of the kept VIO poses.
    std::optional<Eigen::Isometry3d> visualPoseAt(TimeNs t) const;

    const imu::ImuPredictor& predictor_;
    std::optional<PoseEstimate> scan_;
    std::deque<PoseEstimate> vio_;  // VIO poses since shortly before the last scan pose
};

}  // namespace handscan::fusion
