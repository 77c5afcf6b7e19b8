// SO(3)/SE(3) exponential and logarithm maps and interpolation on Eigen types. Tangent vectors
// are ordered (rotation, translation) as in the paper's 6-DOF state [theta; t].
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace handscan {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// [w]x: the cross-product matrix.
Eigen::Matrix3d skew(const Eigen::Vector3d& w);

// exp: so(3) -> SO(3) (Rodrigues), stable near zero.
Eigen::Matrix3d expSO3(const Eigen::Vector3d& w);
// log: SO(3) -> so(3), stable near 0 and pi.
Eigen::Vector3d logSO3(const Eigen::Matrix3d& R);
// Left Jacobian of SO(3) and its inverse (used for the SE(3) translation part).
Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& w);
Eigen::Matrix3d leftJacobianInvSO3(const Eigen::Vector3d& w);

// exp: se(3) -> SE(3), xi = (w, v).
Eigen::Isometry3d expSE3(const Vector6d& xi);
// log: SE(3) -> se(3).
Vector6d logSE3(const Eigen::Isometry3d& T);

// Geodesic interpolation: a at s = 0, b at s = 1 (rotation by slerp, translation linear, which
// is what the sweep assembler needs for short intervals).
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s);

// Rotation angle between two rotations, radians.
double rotationAngle(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb);

// Re-orthonormalise a rotation matrix that accumulated round-off.
Eigen::Matrix3d orthonormalize(const Eigen::Matrix3d& R);

}  // namespace handscan
