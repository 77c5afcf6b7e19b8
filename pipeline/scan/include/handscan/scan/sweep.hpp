// One assembled sweep of the spinning laser: every Hokuyo step of a half (or full) shaft
// revolution as a 3D point in the body frame {C_m} at the sweep's first point (section 6.1:
// "we associate it with the camera coordinate system at the beginning of the scan"). Points keep
// their own time, range and the scan line they came from, because features (eq. 12) are computed
// along scan lines.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan::scan {

// The motion estimate the sweep assembler and the matcher use: the body pose {C} in the world
// at any time inside the buffered window (the IMU predictor's or the VIO's output).
using PoseAtFn = std::function<Eigen::Isometry3d(TimeNs)>;

struct SweepPoint {
    TimeNs t = 0;                                       // host time of this step
    Eigen::Vector3d p_start = Eigen::Vector3d::Zero();  // m, body frame at the sweep's start
    // m, body frame at this step's own time (before motion compensation): lets a consumer
    // re-place the point when the motion estimate is corrected after assembly (IMU feedback).
    Eigen::Vector3d p_body = Eigen::Vector3d::Zero();
    // The laser's centre when this step was measured, at the sweep's start and at the step's own
    // time like p_start and p_body: which side of a surface the sensor saw it from (thin walls,
    // see ScanMatcher).
    Eigen::Vector3d origin_start = Eigen::Vector3d::Zero();
    Eigen::Vector3d origin_body = Eigen::Vector3d::Zero();
    float range_m = 0.0F;    // measured range
    float intensity = 0.0F;  // raw intensity (0 when absent)
    std::uint16_t step = 0;  // index in the 2D scan (0..1080)
};

// The points of one 2D scan (or of the part of it inside this sweep), in step order.
struct ScanLine {
    std::size_t begin = 0;             // index into Sweep::points
    std::size_t end = 0;               // one past the last point
    double angle_increment_rad = 0.0;  // beam angle between consecutive steps
};

struct Sweep {
    TimeNs t_start = 0;       // time of the first point
    TimeNs t_end = 0;         // time of the last point
    std::uint64_t index = 0;  // running sweep number
    // Body pose at t_start according to the motion estimate used for assembly: the frame the
    // points are in, and the odometry the matcher's prior (eq. 16) is built from.
    Eigen::Isometry3d T_world_start_odom = Eigen::Isometry3d::Identity();
    std::vector<SweepPoint> points;
    std::vector<ScanLine> lines;

    bool empty() const { return points.empty(); }
};

}  // namespace handscan::scan
