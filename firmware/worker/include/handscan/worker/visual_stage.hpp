// VisualStage: the visual-inertial odometry (pipeline/vio, section 5) between the IMU prediction
// and scan matching in the one worker (Figure 2). Per tracking-camera frame: the IMU-predicted
// motion since the previous frame (eq. 10) from the laser-inertial odometry's predictor, the VIO's
// pose, and that pose handed to the laser-inertial odometry (addVisualPose: the prior of scan
// matching, eq. 17, and the 200 Hz integration, section 7) unless the camera solved nothing.
// Per registered sweep: its points as the VIO's laser depth (5.3), in the laser-inertial
// odometry's frame; each frame's depth map is seen from the camera's pose there (its 200 Hz
// output), not from the VIO's own chain, which drifts from the map between matches.
//
// Automatic reconfiguration (section 8): a frame that solves no direction (dark, texture-less,
// covered lens) bypasses the module at once, and the laser-inertial odometry treats the hole in
// the visual poses as no visual solution; a frame that solves some directions is used in those
// only. The bypassed stretches are kept for stats.json.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/vio/visual_odometry.hpp"

namespace handscan::worker {

// A stretch of frames that solved no direction (the camera bypassed), times in the recording.
struct BypassInterval {
    TimeNs t_begin = 0;
    TimeNs t_end = 0;  // 0: still bypassed
    std::uint64_t frames = 0;
};

struct VisualStageStats {
    TimeNs t_first = 0;            // the first processed frame (after gravity alignment)
    std::uint64_t frames = 0;      // tracking frames received
    std::uint64_t processed = 0;   // run through the VIO (after gravity alignment)
    std::uint64_t used = 0;        // handed on (some direction solved)
    std::uint64_t all_solved = 0;  // all six directions solved
    std::uint64_t keyframes = 0;
    std::uint64_t errors = 0;      // frames refused (size, format) or without an IMU pose
    double features_sum = 0.0;     // tracked features, summed over the processed frames
    double laser_depth_sum = 0.0;  // of them with laser depth (eqs. 6-7)
    double triangulated_sum = 0.0;
};

class VisualStage {
public:
    // Throws std::invalid_argument when cam0 of the camchain cannot be undistorted.
    VisualStage(const Calibration& calibration, const vio::VioConfig& config = {});

    // One tracking-camera frame; its pose goes to `lio` unless the camera solved nothing.
    void frame(const Image& image, lio::LaserInertialOdometry& lio);
    // A registered sweep's points become laser depth.
    void sweep(const lio::RegisteredSweep& sweep);

    const VisualStageStats& stats() const { return stats_; }
    const std::vector<BypassInterval>& bypassed() const { return bypassed_; }
    bool bypassedNow() const { return !bypassed_.empty() && bypassed_.back().t_end == 0; }
    // The last processed frame's solved directions (world axes, scan::DofBit order).
    std::uint8_t solvedNow() const { return solved_now_; }

private:
    vio::VisualInertialOdometry vio_;
    std::optional<TimeNs> t_prev_;
    std::vector<BypassInterval> bypassed_;
    VisualStageStats stats_;
    std::uint8_t solved_now_ = 0;
    std::uint64_t warned_ = 0;
};

}  // namespace handscan::worker
