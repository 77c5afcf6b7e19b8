// DegeneracyRemapper (section 8, Zhang, Kaess & Singh 2016): eigen-decompose J^T J of the scan
// matching problem, call directions with eigenvalues below a threshold degraded, and let the
// nonlinear iteration move only in the well-conditioned ones, x <- x + V^{-1} Vbar dx (eq. 21), so
// the prior (initial guess) is kept in the degraded directions.
#pragma once

#include <cstdint>

#include "handscan/core/se3.hpp"

namespace handscan::scan {

// Bits of the per-DOF solved mask, in the tangent order (rotation, translation) of se3.hpp and of
// PoseEstimate::solved_dof_mask.
enum DofBit : std::uint8_t {
    kRx = 1,
    kRy = 2,
    kRz = 4,
    kTx = 8,
    kTy = 16,
    kTz = 32,
    kAllDof = 0x3F
};

struct DegeneracyAnalysis {
    Vector6d eigenvalues = Vector6d::Zero();     // lambda_1 >= ... >= lambda_6
    Matrix6d V = Matrix6d::Identity();           // rows: eigenvectors v_1..v_6 (eq. 19)
    Matrix6d projection = Matrix6d::Identity();  // V^{-1} Vbar: projector onto solved directions
    int well_conditioned = 6;                    // h of eq. (19)
    std::uint8_t solved_dof_mask = kAllDof;      // DOF axes lying (mostly) in the solved subspace
};

// Bit i set when at least `axis_fraction` of axis e_i (squared norm of its projection) lies in
// the subspace of projector P.
std::uint8_t maskFromProjector(const Matrix6d& P, double axis_fraction = 0.5);

// The matcher perturbs the pose on the right, T exp(xi), so its projector acts on body-frame
// (rot, trans) increments. The IMU predictor takes feedback as world-axis increments
// (R <- exp(dtheta_w) R, t <- t + dt_w: dtheta_w = R dtheta_b, dt_w = R dt_b), so the same
// subspace in its coordinates is D P D^T with D = diag(R, R).
Matrix6d bodyToWorldAxes(const Matrix6d& M_body, const Eigen::Matrix3d& R_world_body);

// The orthogonal projector onto the eigenvectors of the symmetric `M` whose eigenvalues are at
// least `min_eigenvalue`. With M = P_a + P_b (two solved subspaces' projectors) and a small
// threshold it projects onto the union (span) of both: the directions either module solved.
Matrix6d rangeProjector(const Matrix6d& M, double min_eigenvalue);

// `JtJ` in the tangent order (rot, trans). A DOF axis e_i counts as solved when at least
// `axis_fraction` of it (squared norm of its projection) lies in the well-conditioned subspace.
DegeneracyAnalysis analyzeDegeneracy(const Matrix6d& JtJ, double eigenvalue_threshold,
                                     double axis_fraction = 0.5);

}  // namespace handscan::scan
