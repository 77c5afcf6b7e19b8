#include "handscan/scan/degeneracy.hpp"

#include <Eigen/Eigenvalues>

namespace handscan::scan {

DegeneracyAnalysis analyzeDegeneracy(const Matrix6d& JtJ, double eigenvalue_threshold,
                                     double axis_fraction) {
    DegeneracyAnalysis a;
    const Eigen::SelfAdjointEigenSolver<Matrix6d> solver(0.5 * (JtJ + JtJ.transpose()));
    // Eigen sorts increasing; the paper's V lists v_1..v_6 in decreasing order.
    for (int i = 0; i < 6; ++i) {
        a.eigenvalues[i] = solver.eigenvalues()[5 - i];
        a.V.row(i) = solver.eigenvectors().col(5 - i).transpose();
    }
    a.well_conditioned = 0;
    Matrix6d Vbar = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
        if (a.eigenvalues[i] >= eigenvalue_threshold) {
            Vbar.row(i) = a.V.row(i);
            ++a.well_conditioned;
        }
    }
    // V is orthonormal, so V^{-1} = V^T (eq. 21).
    a.projection = a.V.transpose() * Vbar;
    a.solved_dof_mask = maskFromProjector(a.projection, axis_fraction);
    return a;
}

Matrix6d rangeProjector(const Matrix6d& M, double min_eigenvalue) {
    const Eigen::SelfAdjointEigenSolver<Matrix6d> solver(0.5 * (M + M.transpose()));
    Matrix6d P = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
        if (solver.eigenvalues()[i] >= min_eigenvalue) {
            const Vector6d v = solver.eigenvectors().col(i);
            P += v * v.transpose();
        }
    }
    return P;
}

std::uint8_t maskFromProjector(const Matrix6d& P, double axis_fraction) {
    std::uint8_t mask = 0;
    for (int d = 0; d < 6; ++d) {
        // For an orthogonal projector |P e_d|^2 = e_d^T P e_d.
        if (P.col(d).squaredNorm() >= axis_fraction) {
            mask |= static_cast<std::uint8_t>(1U << d);
        }
    }
    return mask;
}

Matrix6d bodyToWorldAxes(const Matrix6d& M_body, const Eigen::Matrix3d& R_world_body) {
    Matrix6d D = Matrix6d::Zero();
    D.topLeftCorner<3, 3>() = R_world_body;
    D.bottomRightCorner<3, 3>() = R_world_body;
    return D * M_body * D.transpose();
}

}  // namespace handscan::scan
