#include "handscan/imu/dof_projector.hpp"

#include <Eigen/Eigenvalues>

namespace handscan::imu {

Matrix6d projectorFromMask(std::uint8_t solved_dof_mask) {
    Matrix6d P = Matrix6d::Zero();
    for (int i = 0; i < 6; ++i) {
        if (solved_dof_mask & (1u << i)) P(i, i) = 1.0;
    }
    return P;
}

Matrix6d projectorFromEigenvectors(const Matrix6d& V, int well_conditioned) {
    Matrix6d V_bar = Matrix6d::Zero();
    for (int i = 0; i < well_conditioned && i < 6; ++i) V_bar.row(i) = V.row(i);
    return V.inverse() * V_bar;  // eq. (21)
}

std::uint8_t maskFromProjector(const Matrix6d& P, double tolerance) {
    std::uint8_t mask = 0;
    for (int i = 0; i < 6; ++i) {
        const Vector6d e = Vector6d::Unit(i);
        if ((P * e - e).norm() <= tolerance) mask = static_cast<std::uint8_t>(mask | (1u << i));
    }
    return mask;
}

Eigen::Matrix3d unsolvedTranslation(const Matrix6d& P) {
    const Eigen::Matrix3d S = P.bottomRightCorner<3, 3>();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(0.5 * (S + S.transpose()));
    Eigen::Matrix3d U = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) {
        if (es.eigenvalues()(i) < 0.5)
            U += es.eigenvectors().col(i) * es.eigenvectors().col(i).transpose();
    }
    return U;
}

}  // namespace handscan::imu
