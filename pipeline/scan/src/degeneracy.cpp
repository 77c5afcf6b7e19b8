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
    a.solved_dof_mask = 0;
    for (int d = 0; d < 6; ++d) {
        if (a.projection.col(d).squaredNorm() >= axis_fraction) {
            a.solved_dof_mask |= static_cast<std::uint8_t>(1U << d);
        }
    }
    return a;
}

}  // namespace handscan::scan
