// The Xsens MTi-20's inertial sensors: specific force and angular rate at the IMU's own pose
// (lever arm from the camchain's T_cam_imu), gravity, white noise with the datasheet noise
// densities, bias random walks and turn-on biases. Output samples are on the IMU's own clock
// (200 Hz of its crystal, which drifts against the host).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "handscan/sim/random.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {

// Defaults: MTi 10-series (MTi-20) datasheet - gyroscope noise density 0.03 deg/s/sqrt(Hz),
// in-run bias stability 18 deg/h; accelerometer noise density 80 ug/sqrt(Hz), in-run bias
// stability 40 ug. The random walks are sized so the bias wanders by about the in-run stability
// over 100 s. Outputs clip at the full scale (450 deg/s, 200 m/s^2).
struct ImuNoise {
    double gyro_noise_density = 0.03 * 0.017453292519943295;                     // rad/s/sqrt(Hz)
    double accel_noise_density = 80e-6 * 9.80665;                                // m/s^2/sqrt(Hz)
    double gyro_bias_random_walk = 18.0 / 3600.0 * 0.017453292519943295 / 10.0;  // rad/s^2/sqrt(Hz)
    double accel_bias_random_walk = 40e-6 * 9.80665 / 10.0;                      // m/s^3/sqrt(Hz)
    double gyro_turn_on_bias = 0.2 * 0.017453292519943295;  // rad/s, per-axis sigma
    double accel_turn_on_bias = 0.02;                       // m/s^2, per-axis sigma
    double gyro_range = 450.0 * 0.017453292519943295;       // rad/s
    double accel_range = 200.0;                             // m/s^2
    double gravity = 9.80665;                               // m/s^2
};

struct ImuMeasurement {
    double t = 0.0;                                   // simulation time of the sample
    Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // specific force in {I}, m/s^2
    Eigen::Vector3d gyro = Eigen::Vector3d::Zero();   // rad/s in {I}
    Eigen::Vector3d true_accel = Eigen::Vector3d::Zero();
    Eigen::Vector3d true_gyro = Eigen::Vector3d::Zero();
};

class ImuModel {
public:
    ImuModel(const ImuNoise& noise, const Eigen::Isometry3d& T_cam_imu, double rate_hz, Rng rng);

    // Noise-free specific force and rate of the IMU for the body state.
    void ideal(const BodyState& s, Eigen::Vector3d& accel_imu, Eigen::Vector3d& gyro_imu) const;
    // One sample: ideal + bias + white noise; advances the bias random walks by one period.
    ImuMeasurement sample(const BodyState& s);

    const Eigen::Vector3d& gyroBias() const { return bg_; }
    const Eigen::Vector3d& accelBias() const { return ba_; }

private:
    ImuNoise n_;
    Eigen::Matrix3d R_ci_;
    Eigen::Vector3d t_ci_;
    double dt_;
    Rng rng_;
    Eigen::Vector3d bg_, ba_;
};

}  // namespace handscan::sim
