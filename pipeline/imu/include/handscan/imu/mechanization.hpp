// IMU mechanization (paper section 4.1): integrate eq. (3) for orientation, then the resulting
// orientation with eq. (4) twice for velocity and translation. One step spans two consecutive
// samples and uses the midpoint (trapezoidal) rule on SO(3): the rotation increment is the exact
// exponential of the mean bias-corrected rate, and the world acceleration is the mean of the
// specific forces rotated by the start and end orientations plus gravity. At 200 Hz this is
// second-order accurate, unlike a first-order Euler step.
//
// The lever arm: the paper models motion in the camera (body) frame {C}, which adds the
// centrifugal term -t ||omega||^2 to eq. (4). We integrate the IMU frame and compose the rigid
// extrinsic T_imu_body afterwards (bodyPose / bodyVelocity), which is the exact rigid-body relation
// - centripetal omega x (omega x r) and tangential omega_dot x r - without differentiating the
// gyro. specificForceAtBody() gives eq. (4) expressed at {C} for modules that need it.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "handscan/core/samples.hpp"
#include "handscan/imu/nav_state.hpp"

namespace handscan::imu {

// The bias-corrected measurement pair of one step.
struct ImuReading {
    Eigen::Vector3d gyro_radps = Eigen::Vector3d::Zero();
    Eigen::Vector3d accel_mps2 = Eigen::Vector3d::Zero();
};

ImuReading correctBiases(const ImuSample& s, const ImuBiases& b);
// Linear interpolation of two readings (sample at t between a at ta and b at tb).
ImuReading lerp(const ImuReading& a, const ImuReading& b, double s);

// One midpoint step from x (at reading r0) over dt_s to reading r1. Gravity in {W}.
NavState integrateStep(const NavState& x, const ImuReading& r0, const ImuReading& r1, double dt_s,
                       const Eigen::Vector3d& gravity_world);

// integrateStep, except across a gap longer than `max_gap_s` (the link lost): the readings at
// its two edges say nothing about the motion in between, and integrating them would turn and
// push the state by whatever the hand did at the edges for the whole gap (a 0.3 rad/s sway held
// for 2 s: 34 degrees of attitude, with gravity leaking into the velocity). Across a gap the
// attitude and the velocity are held (constant velocity); the scan matcher corrects the rest.
NavState integrateOrHold(const NavState& x, const ImuReading& r0, const ImuReading& r1, double dt_s,
                         const Eigen::Vector3d& gravity_world, double max_gap_s);

// Pose and velocity of the body frame given the IMU state and the extrinsic T_imu_body
// (= T_cam_imu^-1 from the camchain). omega_imu is the bias-corrected rate.
Eigen::Isometry3d bodyPose(const NavState& x, const Eigen::Isometry3d& T_imu_body);
Eigen::Vector3d bodyVelocity(const NavState& x, const Eigen::Vector3d& omega_imu,
                             const Eigen::Isometry3d& T_imu_body);

// Eq. (4) at the body origin, in {C}: the specific force the IMU would measure if it sat at the
// body origin. r_imu_body is the body origin in {I}; the centripetal term omega x (omega x r)
// is the paper's -t||omega||^2 term in full, omega_dot x r the tangential one it neglects.
Eigen::Vector3d specificForceAtBody(const Eigen::Vector3d& f_imu, const Eigen::Vector3d& omega_imu,
                                    const Eigen::Vector3d& omega_dot_imu,
                                    const Eigen::Isometry3d& T_imu_body);

}  // namespace handscan::imu
