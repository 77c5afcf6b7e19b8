#include "handscan/scan/surface_offset.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>

namespace handscan::scan {
namespace {

using Row = Eigen::Matrix<double, 1, 6>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;

// Quadric terms of in-plane coordinates (scaled by the cluster's extent for conditioning).
Row quadricRow(double u, double v) {
    Row r;
    r << 1.0, u, v, 0.5 * u * u, u * v, 0.5 * v * v;
    return r;
}

}  // namespace

std::optional<double> surfaceOffsetAt(const Eigen::Vector3d* points, int n,
                                      const Eigen::Vector3d& c, const Eigen::Vector3d& normal,
                                      const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                      const Eigen::Vector3d& query,
                                      const SurfaceOffsetLimits& limits) {
    constexpr int kTerms = 6;
    if (n <= kTerms) return std::nullopt;  // no redundancy: cannot tell a surface from noise
    double extent2 = 0.0;
    for (int i = 0; i < n; ++i) {
        const Eigen::Vector3d d = points[i] - c;
        extent2 = std::max(extent2, std::pow(t1.dot(d), 2) + std::pow(t2.dot(d), 2));
    }
    if (extent2 <= 0.0) return std::nullopt;
    const double s = 1.0 / std::sqrt(extent2);
    const auto row = [&](const Eigen::Vector3d& p) {
        const Eigen::Vector3d d = p - c;
        return quadricRow(s * t1.dot(d), s * t2.dot(d));
    };
    Matrix6 AtA = Matrix6::Zero();
    Vector6 Ath = Vector6::Zero();
    for (int i = 0; i < n; ++i) {
        const Row r = row(points[i]);
        AtA.noalias() += r.transpose() * r;
        Ath.noalias() += r.transpose() * normal.dot(points[i] - c);
    }
    const Eigen::LDLT<Matrix6> ldlt(AtA);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive() ||
        ldlt.vectorD().minCoeff() < 1e-6 * ldlt.vectorD().maxCoeff()) {
        return std::nullopt;  // points along one line: no curvature across it
    }
    const Row rq = row(query);
    const double leverage = rq * ldlt.solve(rq.transpose());
    if (!(leverage <= limits.max_leverage)) return std::nullopt;
    const Vector6 theta = ldlt.solve(Ath);
    double ss = 0.0;
    for (int i = 0; i < n; ++i)
        ss += std::pow(normal.dot(points[i] - c) - row(points[i]) * theta, 2);
    if (ss > limits.max_rms_m * limits.max_rms_m * (n - kTerms)) return std::nullopt;
    const double offset = rq * theta;
    if (!(std::abs(offset) <= limits.max_offset_m)) return std::nullopt;
    return offset;
}

}  // namespace handscan::scan
