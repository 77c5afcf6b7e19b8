// The simulated MTi-20: a stationary IMU reads gravity; white noise and bias random walk match
// the configured densities (Allan deviation); the lever arm adds the centripetal acceleration.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "handscan/sim/imu_model.hpp"

namespace handscan::sim {
namespace {

Eigen::Isometry3d camImu() {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() << 0, -1, 0, 0, 0, -1, 1, 0, 0;  // config/camchain.yaml
    T.translation() = Eigen::Vector3d(0.02, 0.03, -0.04);
    return T;
}

BodyState still(const Eigen::Matrix3d& R) {
    BodyState s;
    s.T_world_body.linear() = R;
    s.T_world_body.translation() = Eigen::Vector3d(1, 2, 1.3);
    return s;
}

// Overlapping Allan deviation of x (sampled every dt) at cluster time tau (IEEE Std 952).
double allanDeviation(const std::vector<double>& x, double dt, double tau) {
    const auto m = static_cast<std::size_t>(std::lround(tau / dt));
    std::vector<double> theta(x.size() + 1, 0.0);  // integral of x
    for (std::size_t i = 0; i < x.size(); ++i) theta[i + 1] = theta[i] + x[i] * dt;
    double sum = 0.0;
    const std::size_t n = theta.size() - 2 * m;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = theta[i + 2 * m] - 2.0 * theta[i + m] + theta[i];
        sum += d * d;
    }
    return std::sqrt(sum / (2.0 * tau * tau * static_cast<double>(n)));
}

TEST(ImuModelTest, StationaryImuReadsGravity) {
    const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(-1.1, Eigen::Vector3d::UnitZ()))
                                  .toRotationMatrix();
    ImuNoise n;
    ImuModel imu(n, camImu(), 200.0, Rng(7, "imu"));
    const BodyState s = still(R);
    Eigen::Vector3d sum_a = Eigen::Vector3d::Zero(), sum_g = Eigen::Vector3d::Zero();
    const int N = 4000;
    for (int i = 0; i < N; ++i) {
        const ImuMeasurement m = imu.sample(s);
        sum_a += m.accel;
        sum_g += m.gyro;
    }
    const Eigen::Matrix3d R_wi = R * camImu().linear();
    const Eigen::Vector3d expect =
        R_wi.transpose() * Eigen::Vector3d(0, 0, n.gravity);  // specific force points up
    const Eigen::Vector3d mean_a = sum_a / N;
    // Within turn-on bias (0.02 m/s^2 per axis, 5 sigma) of gravity in the IMU frame.
    EXPECT_LT((mean_a - expect).norm(), 0.1);
    EXPECT_NEAR(mean_a.norm(), 9.80665, 0.1);
    EXPECT_LT((sum_g / N).norm(), 5 * n.gyro_turn_on_bias * std::sqrt(3.0));
    // Noise-free model: exactly gravity, exactly zero rate.
    Eigen::Vector3d a, g;
    imu.ideal(s, a, g);
    EXPECT_LT((a - expect).norm(), 1e-12);
    EXPECT_LT(g.norm(), 1e-15);
}

TEST(ImuModelTest, WhiteNoiseMatchesDatasheetDensityByAllanDeviation) {
    ImuNoise n;
    n.gyro_bias_random_walk = n.accel_bias_random_walk = 0.0;
    n.gyro_turn_on_bias = n.accel_turn_on_bias = 0.0;
    ImuModel imu(n, camImu(), 200.0, Rng(11, "imu"));
    const BodyState s = still(Eigen::Matrix3d::Identity());
    std::vector<double> gx, ay;
    for (int i = 0; i < 200 * 1000; ++i) {
        const ImuMeasurement m = imu.sample(s);
        gx.push_back(m.gyro.x());
        ay.push_back(m.accel.y() - m.true_accel.y());
    }
    for (double tau : {0.1, 1.0, 10.0}) {
        // White noise of density N: ADEV(tau) = N / sqrt(tau).
        EXPECT_NEAR(allanDeviation(gx, 0.005, tau) / (n.gyro_noise_density / std::sqrt(tau)), 1.0,
                    0.12)
            << tau;
        EXPECT_NEAR(allanDeviation(ay, 0.005, tau) / (n.accel_noise_density / std::sqrt(tau)), 1.0,
                    0.12)
            << tau;
    }
}

TEST(ImuModelTest, BiasRandomWalkMatchesDensityByAllanDeviation) {
    ImuNoise n;
    n.gyro_noise_density = n.accel_noise_density = 0.0;
    n.gyro_turn_on_bias = n.accel_turn_on_bias = 0.0;
    ImuModel imu(n, camImu(), 200.0, Rng(13, "imu"));
    const BodyState s = still(Eigen::Matrix3d::Identity());
    std::vector<double> gz, az;
    for (int i = 0; i < 200 * 2000; ++i) {
        const ImuMeasurement m = imu.sample(s);
        gz.push_back(m.gyro.z());
        az.push_back(m.accel.z() - m.true_accel.z());
    }
    for (double tau : {1.0, 10.0}) {
        // Rate random walk K: ADEV(tau) = K sqrt(tau / 3).
        EXPECT_NEAR(allanDeviation(gz, 0.005, tau) / (n.gyro_bias_random_walk * std::sqrt(tau / 3)),
                    1.0, 0.15)
            << tau;
        EXPECT_NEAR(
            allanDeviation(az, 0.005, tau) / (n.accel_bias_random_walk * std::sqrt(tau / 3)), 1.0,
            0.15)
            << tau;
    }
}

TEST(ImuModelTest, LeverArmAddsCentripetalAcceleration) {
    ImuNoise n;
    ImuModel imu(n, camImu(), 200.0, Rng(1, "imu"));
    BodyState s = still(Eigen::Matrix3d::Identity());
    s.omega_body = Eigen::Vector3d(0, 0, 3.0);  // about the camera's optical axis
    Eigen::Vector3d a0, g0, a1, g1;
    imu.ideal(still(Eigen::Matrix3d::Identity()), a0, g0);
    imu.ideal(s, a1, g1);
    const Eigen::Vector3d r = camImu().translation();
    const Eigen::Vector3d centripetal_c = s.omega_body.cross(s.omega_body.cross(r));
    EXPECT_LT(((a1 - a0) - camImu().linear().transpose() * centripetal_c).norm(), 1e-12);
    EXPECT_NEAR((a1 - a0).norm(), 9.0 * std::hypot(r.x(), r.y()), 1e-12);
    EXPECT_LT((g1 - camImu().linear().transpose() * s.omega_body).norm(), 1e-15);
}

}  // namespace
}  // namespace handscan::sim
