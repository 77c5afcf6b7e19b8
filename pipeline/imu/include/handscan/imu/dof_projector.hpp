// Which directions of a 6-DOF pose a module actually solved (section 8). A correction of the body
// pose is a tangent vector (rotation, translation) in world axes {W}, R <- exp(dtheta) R and
// t <- t + dt, ordered as the paper's state [theta; t]. The solved subspace is a 6x6 projector:
// V^-1 V_bar of eq. (21) for an eigenvector basis, or diag(mask) for the per-DOF bit mask carried
// by PoseEstimate (bit 0 = rx, 1 = ry, 2 = rz, 3 = tx, 4 = ty, 5 = tz, about/along world axes).
#pragma once

#include <cstdint>

#include "handscan/core/se3.hpp"

namespace handscan::imu {

constexpr std::uint8_t kAllDofs = 0x3F;
constexpr std::uint8_t kRotationDofs = 0x07;
constexpr std::uint8_t kTranslationDofs = 0x38;

// diag(mask) as a projector.
Matrix6d projectorFromMask(std::uint8_t solved_dof_mask);
// V^-1 V_bar of eq. (21): `V` has the eigenvectors of J^T J as rows, sorted by decreasing
// eigenvalue; the first `well_conditioned` of them span the solved subspace.
Matrix6d projectorFromEigenvectors(const Matrix6d& V, int well_conditioned);
// The world-axis DOFs a projector (nearly) contains: bit i set when e_i is within the subspace.
std::uint8_t maskFromProjector(const Matrix6d& P, double tolerance = 1e-3);
// The orthogonal projector onto the translation directions (world axes) a projector leaves
// unsolved: the eigenvectors of the symmetrized translation block with eigenvalue below 1/2 (the
// block of an eq. (21) projector whose eigenvectors mix rotation and translation is no projector
// itself).
Eigen::Matrix3d unsolvedTranslation(const Matrix6d& P);

}  // namespace handscan::imu
