#include "handscan/core/se3.hpp"

#include <gtest/gtest.h>

#include <random>

namespace handscan {
namespace {

Vector6d randomTwist(std::mt19937& rng, double rot_scale, double trans_scale) {
    std::normal_distribution<double> n(0.0, 1.0);
    Vector6d xi;
    for (int i = 0; i < 3; ++i) xi[i] = rot_scale * n(rng);
    for (int i = 3; i < 6; ++i) xi[i] = trans_scale * n(rng);
    return xi;
}

TEST(Se3, ExpLogRoundTripSO3IncludingTinyAndNearPi) {
    std::mt19937 rng(1);
    for (double scale : {1e-9, 1e-4, 0.3, 1.0, 1.7}) {
        for (int i = 0; i < 200; ++i) {
            Vector6d xi = randomTwist(rng, scale, 0.0);
            Eigen::Vector3d w = xi.head<3>();
            if (w.norm() > M_PI - 1e-6) w *= (M_PI - 1e-3) / w.norm();
            EXPECT_LT((logSO3(expSO3(w)) - w).norm(), 1e-9 + 1e-9 * w.norm()) << w.transpose();
        }
    }
    // Exactly pi about a unit axis: log returns an angle of pi (sign of the axis is free).
    const Eigen::Vector3d axis = Eigen::Vector3d(1, 2, 3).normalized();
    EXPECT_NEAR(logSO3(expSO3(M_PI * axis)).norm(), M_PI, 1e-9);
}

TEST(Se3, ExpMatchesEigenAngleAxis) {
    const Eigen::Vector3d w(0.3, -0.2, 1.1);
    const Eigen::Matrix3d ref = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
    EXPECT_LT((expSO3(w) - ref).norm(), 1e-12);
}

TEST(Se3, ExpLogRoundTripSE3) {
    std::mt19937 rng(2);
    for (int i = 0; i < 500; ++i) {
        const Vector6d xi = randomTwist(rng, 0.8, 5.0);
        if (xi.head<3>().norm() > 3.0) continue;
        EXPECT_LT((logSE3(expSE3(xi)) - xi).norm(), 1e-9);
    }
}

TEST(Se3, ExpSE3IsAGroupHomomorphismAlongOneTwist) {
    // exp((a+b) xi) = exp(a xi) exp(b xi) for the same twist.
    const Vector6d xi = (Vector6d() << 0.2, -0.5, 0.9, 1.0, 2.0, -3.0).finished();
    const Eigen::Isometry3d lhs = expSE3(0.7 * xi);
    const Eigen::Isometry3d rhs = expSE3(0.3 * xi) * expSE3(0.4 * xi);
    EXPECT_LT((lhs.matrix() - rhs.matrix()).norm(), 1e-12);
}

TEST(Se3, LeftJacobianMatchesNumericDerivative) {
    // exp(w + dw) ~ exp(J_l(w) dw) exp(w)
    const Eigen::Vector3d w(0.4, -1.2, 0.7);
    const Eigen::Matrix3d Jl = leftJacobianSO3(w);
    const double h = 1e-6;
    for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d dw = Eigen::Vector3d::Zero();
        dw[k] = h;
        const Eigen::Vector3d numeric = logSO3(expSO3(w + dw) * expSO3(w).transpose()) / h;
        EXPECT_LT((numeric - Jl.col(k)).norm(), 1e-5);
    }
    EXPECT_LT((leftJacobianInvSO3(w) * Jl - Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(Se3, InterpolateEndpointsAndMidpoint) {
    const Eigen::Isometry3d a = expSE3((Vector6d() << 0.1, 0.2, 0.3, 1, 2, 3).finished());
    const Eigen::Isometry3d b = expSE3((Vector6d() << -0.4, 0.5, 1.0, -1, 0, 4).finished());
    EXPECT_LT((interpolate(a, b, 0.0).matrix() - a.matrix()).norm(), 1e-12);
    EXPECT_LT((interpolate(a, b, 1.0).matrix() - b.matrix()).norm(), 1e-12);
    const Eigen::Isometry3d m = interpolate(a, b, 0.5);
    EXPECT_NEAR(rotationAngle(a.linear(), m.linear()), rotationAngle(m.linear(), b.linear()),
                1e-12);
    EXPECT_LT((m.translation() - 0.5 * (a.translation() + b.translation())).norm(), 1e-12);
}

TEST(Se3, SkewIsCrossProduct) {
    const Eigen::Vector3d a(1, -2, 3), b(0.5, 4, -1);
    EXPECT_LT((skew(a) * b - a.cross(b)).norm(), 1e-15);
}

}  // namespace
}  // namespace handscan
