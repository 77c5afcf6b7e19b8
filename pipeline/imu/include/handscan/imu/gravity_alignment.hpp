// Gravity alignment from a static start. The scanner is held still for a moment before the scan;
// while it is, the accelerometer measures only -R^T g (eq. (4) with a = 0, omega = 0) and the
// gyro only its bias (eq. (3) with omega = 0). StaticStartAligner watches the stream in short
// blocks; a block is static when its mean rate and mean specific force stay close to those of the
// static run so far and its spread is below a vibration bound (a hand's tremor or a drone's rotors
// shake the readings but leave the block means still). Once the run is long enough it returns
// roll/pitch from the mean specific force and the gyro bias as the mean rate. Yaw is unobservable
// and set so that R_world_imu is the smallest rotation taking the measured "up" onto +z. The
// accelerometer bias is observable only along gravity (as the norm error): that component is taken
// as the initial accel bias and reported as `accel_norm_error_mps2`; the horizontal part only tilts
// the levelled frame.
#pragma once

#include <optional>

#include "handscan/core/samples.hpp"
#include "handscan/imu/nav_state.hpp"

namespace handscan::imu {

struct GravityAlignmentConfig {
    double min_static_s = 1.0;         // static interval needed before aligning
    double block_s = 0.25;             // block length of the stillness test
    double max_gyro_dev_radps = 0.02;  // |block mean rate - run mean| (MTi-20 noise ~0.002)
    double max_accel_dev_mps2 = 0.15;  // |block mean force - run mean|
    double max_gyro_std_radps = 0.2;   // per-block spread (vibration) bounds
    double max_accel_std_mps2 = 2.0;
    double max_norm_error_mps2 = 0.6;  // ||mean f| - g| bound: rejects a moving "static" run
    double gravity_mps2 = 9.81;
};

struct GravityAlignment {
    TimeNs t_start = 0;  // first and last sample of the static interval
    TimeNs t_end = 0;
    Eigen::Matrix3d R_world_imu = Eigen::Matrix3d::Identity();
    ImuBiases biases;  // gyro bias = mean static rate, accel bias along gravity
    Eigen::Vector3d mean_specific_force_imu = Eigen::Vector3d::Zero();
    double accel_norm_error_mps2 = 0.0;  // |mean f| - g
    std::size_t samples = 0;
};

// Roll/pitch from a mean specific force: the smallest rotation taking f onto +z.
Eigen::Matrix3d levelRotationFromSpecificForce(const Eigen::Vector3d& f_imu);

class StaticStartAligner {
public:
    explicit StaticStartAligner(GravityAlignmentConfig config = {}) : config_(config) {}
    // Feeds one sample; returns the alignment once a long enough static interval was seen.
    std::optional<GravityAlignment> add(const ImuSample& s);
    void reset();

private:
    struct Sums {
        TimeNs t_first = 0, t_last = 0;
        std::size_t n = 0;
        Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), accel = Eigen::Vector3d::Zero();
        Eigen::Vector3d gyro_sq = Eigen::Vector3d::Zero(), accel_sq = Eigen::Vector3d::Zero();
        void add(const ImuSample& s);
        void add(const Sums& o);
    };
    bool blockIsStatic() const;
    GravityAlignment estimate() const;

    GravityAlignmentConfig config_;
    Sums block_;  // the block being filled
    Sums run_;    // the static blocks so far
};

}  // namespace handscan::imu
