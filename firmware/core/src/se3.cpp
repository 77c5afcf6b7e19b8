#include "handscan/core/se3.hpp"

#include <cmath>

namespace handscan {

Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
    Eigen::Matrix3d S;
    S << 0.0, -w.z(), w.y(), w.z(), 0.0, -w.x(), -w.y(), w.x(), 0.0;
    return S;
}

Eigen::Matrix3d expSO3(const Eigen::Vector3d& w) {
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    double a, b;  // R = I + a W + b W^2
    if (theta2 < 1e-12) {
        // Taylor series: sin(t)/t ~ 1 - t^2/6, (1-cos t)/t^2 ~ 1/2 - t^2/24
        a = 1.0 - theta2 / 6.0;
        b = 0.5 - theta2 / 24.0;
    } else {
        const double theta = std::sqrt(theta2);
        a = std::sin(theta) / theta;
        b = (1.0 - std::cos(theta)) / theta2;
    }
    return Eigen::Matrix3d::Identity() + a * W + b * W * W;
}

Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
    // Through the quaternion: robust for every angle including pi.
    Eigen::Quaterniond q(R);
    q.normalize();
    if (q.w() < 0.0) q.coeffs() = -q.coeffs();
    const Eigen::Vector3d v = q.vec();
    const double n = v.norm();
    if (n < 1e-12) return 2.0 * v;  // small angle: log ~ 2 q.vec
    const double theta = 2.0 * std::atan2(n, q.w());
    return theta / n * v;
}

Eigen::Matrix3d leftJacobianSO3(const Eigen::Vector3d& w) {
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    if (theta2 < 1e-10) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 6.0;
    const double theta = std::sqrt(theta2);
    return Eigen::Matrix3d::Identity() + (1.0 - std::cos(theta)) / theta2 * W +
           (theta - std::sin(theta)) / (theta2 * theta) * W * W;
}

Eigen::Matrix3d leftJacobianInvSO3(const Eigen::Vector3d& w) {
    const double theta2 = w.squaredNorm();
    const Eigen::Matrix3d W = skew(w);
    if (theta2 < 1e-10) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 12.0;
    const double theta = std::sqrt(theta2);
    const double half = 0.5 * theta;
    const double c = (1.0 - half * std::cos(half) / std::sin(half)) / theta2;
    return Eigen::Matrix3d::Identity() - 0.5 * W + c * W * W;
}

Eigen::Isometry3d expSE3(const Vector6d& xi) {
    const Eigen::Vector3d w = xi.head<3>();
    const Eigen::Vector3d v = xi.tail<3>();
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = expSO3(w);
    T.translation() = leftJacobianSO3(w) * v;
    return T;
}

Vector6d logSE3(const Eigen::Isometry3d& T) {
    Vector6d xi;
    const Eigen::Vector3d w = logSO3(T.linear());
    xi.head<3>() = w;
    xi.tail<3>() = leftJacobianInvSO3(w) * T.translation();
    return xi;
}

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double s) {
    const Eigen::Quaterniond qa(a.linear());
    const Eigen::Quaterniond qb(b.linear());
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = qa.slerp(s, qb).normalized().toRotationMatrix();
    T.translation() = (1.0 - s) * a.translation() + s * b.translation();
    return T;
}

double rotationAngle(const Eigen::Matrix3d& Ra, const Eigen::Matrix3d& Rb) {
    return logSO3(Ra.transpose() * Rb).norm();
}

Eigen::Matrix3d orthonormalize(const Eigen::Matrix3d& R) {
    return Eigen::Quaterniond(R).normalized().toRotationMatrix();
}

}  // namespace handscan
