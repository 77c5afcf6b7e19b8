// Ground-truth motion of the rig's body frame {C} (the tracking camera: x right, y down,
// z forward) in the gravity-aligned world {W} (z up). A trajectory is a uniform cubic B-spline
// (C2) over position and Z-Y-X Euler angles of a "device" frame {F} (x forward, y left, z up;
// R_W_C = R_W_F(yaw, pitch, roll) * R_F_C), so velocity, acceleration, angular velocity and
// angular acceleration are exact derivatives of the spline: the IMU and the ground truth agree
// to machine precision.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::sim {

struct Scene;

using Vector6d = Eigen::Matrix<double, 6, 1>;

struct BodyState {
    double t = 0.0;  // seconds since the start
    Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
    Eigen::Vector3d v_world = Eigen::Vector3d::Zero();     // m/s of the {C} origin
    Eigen::Vector3d a_world = Eigen::Vector3d::Zero();     // m/s^2 of the {C} origin
    Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();  // rad/s, in {C}
    Eigen::Vector3d alpha_body = Eigen::Vector3d::Zero();  // rad/s^2, in {C}
};

class Trajectory {
public:
    Trajectory() = default;
    // Control points (x, y, z, yaw, pitch, roll) at spacing dt; control point i sits at time i*dt.
    // `duration` < 0: up to the last control point; otherwise the motion ends there and control
    // points beyond it only shape the end (no clamping artefact in the last knot interval).
    Trajectory(double dt, std::vector<Vector6d> control, double duration = -1.0);

    BodyState at(double t) const;
    double duration() const;
    double knotSpacing() const { return dt_; }
    const std::vector<Vector6d>& controlPoints() const { return c_; }
    // Largest |omega| over the trajectory, sampled every `step` seconds (rad/s).
    double peakAngularRate(double step = 0.005) const;
    // Path length of the {C} origin (m).
    double pathLength(double step = 0.01) const;

    // R_F_C: the camera axes expressed in the device frame.
    static Eigen::Matrix3d deviceFromCamera();

private:
    double dt_ = 0.01;
    std::vector<Vector6d> c_;
    double duration_ = 0.0;
};

enum class MotionStyle { kWalk, kAggressive };

struct WalkOptions {
    double duration_s = 60.0;
    double still_start_s = 3.0;  // operator holds the device still while it initialises
    double still_end_s = 2.0;
    double speed_min_mps = 0.5;
    double speed_max_mps = 1.5;
    double lateral_accel_mps2 = 0.8;  // walkers slow down in turns
    double peak_rate_dps = 370.0;     // aggressive only: paper Figure 30
    MotionStyle style = MotionStyle::kWalk;
    std::uint64_t seed = 1;
    // Where on the loop the walk starts, as a fraction of one lap from the loop's first point
    // (another session through the same scene).
    double start_fraction = 0.0;
};

struct WalkPlan {
    Trajectory trajectory;
    int laps = 1;
    bool closed = true;  // false when the duration is too short to close the loop
    double cruise_speed_mps = 0.0;
};

// Handheld walk along the scene's loop: still start, walk (with gait bounce, hand sway and slow
// looking-around; violent rotations for kAggressive), back to the start, still end.
WalkPlan makeWalk(const std::vector<Eigen::Vector3d>& loop, const WalkOptions& options);

// A user trajectory in TUM format (`t x y z qx qy qz qw`, pose of {C} in {W}); times are shifted
// to start at 0. Errors name the file and line.
Result<Trajectory> loadTum(const std::string& path);

}  // namespace handscan::sim
