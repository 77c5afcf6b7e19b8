// The online clock tracker in a closed loop: a synthetic hand-held motion, a gyro stamped late, an
// encoder stamped off (a turn of every sweep about the shaft at 1 rev/s), and sweep poses as the
// scan matcher reports them with the tracker's current offsets applied. The offsets must converge
// to the truth, stay in their bounds, move in bounded steps, and not move where the motion does
// not determine them.
#include "handscan/lio/clock_tracker.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "../imu/synthetic_motion.hpp"

namespace handscan::lio {
namespace {

const Eigen::Vector3d kAxis = Eigen::Vector3d::UnitZ();
constexpr double kShaftRadps = 2.0 * M_PI;  // 1 rev/s

using Motion = std::function<Eigen::Matrix3d(double)>;

Motion handHeld() {
    return [](double t) { return imu::testing::SyntheticMotion().R(t); };
}

// Runs `seconds` of samples through `c`; returns the largest step of either applied offset.
double walk(ClockTracker& c, const Motion& R, double imu_late_s, double encoder_late_s,
            double seconds) {
    double largest_step = 0.0;
    double imu_before = 0.0, encoder_before = 0.0;
    const double h = 1e-4;
    for (int i = 0; i * 0.005 <= seconds; ++i) {
        const double t = 0.005 * i;
        ImuSample s;
        s.t_host = fromSeconds(t + imu_late_s);
        s.gyro_radps_imu = logSO3(R(t - h).transpose() * R(t + h)) / (2.0 * h);
        c.addImu(s);
        EncoderSample e;
        e.t_host = fromSeconds(t + encoder_late_s);
        e.angle_rad = kShaftRadps * t;
        e.speed_radps = kShaftRadps;
        c.addEncoder(e);
        if (i % 100 != 0 || i == 0) continue;
        // A late encoder stamp reads the angle of an earlier instant: the sweep is turned back by
        // w * late, less what the tracker's offset already took out (an offset o turns it by
        // w * o the other way), so the body the laser implies is turned by eps - applied.
        const double remaining = kShaftRadps * (encoder_late_s - toSeconds(c.encoderOffset()));
        const Eigen::Matrix3d q =
            R(t) * Eigen::AngleAxisd(-remaining, kAxis).toRotationMatrix().transpose();
        c.addSweep(static_cast<std::uint64_t>(i / 100), fromSeconds(t), Eigen::Quaterniond(q),
                   true);
        c.update(fromSeconds(t));
        largest_step = std::max({largest_step, std::abs(c.stats().imu_offset_s - imu_before),
                                 std::abs(c.stats().encoder_offset_s - encoder_before)});
        imu_before = c.stats().imu_offset_s;
        encoder_before = c.stats().encoder_offset_s;
    }
    return largest_step;
}

TEST(ClockTracker, FollowsLateImuAndEncoderClocks) {
    ClockTracker c({}, Eigen::Matrix3d::Identity(), kAxis);
    const double step = walk(c, handHeld(), 0.0025, 0.0015, 40.0);
    EXPECT_NEAR(c.stats().imu_offset_s * 1e3, 2.5, 0.1);
    EXPECT_NEAR(c.stats().encoder_offset_s * 1e3, 1.5, 0.05);
    EXPECT_NEAR(c.stats().shaft_speed_radps, kShaftRadps, 1e-6);
    EXPECT_FALSE(c.stats().imu_at_bound);
    EXPECT_FALSE(c.stats().encoder_at_bound);
    EXPECT_GT(c.stats().determined, 0u);
    EXPECT_LE(step, ClockTrackerConfig{}.max_step_s + 1e-12);
}

TEST(ClockTracker, StaysWithinItsBoundsAndSaysSo) {
    ClockTrackerConfig config;
    config.encoder_bound_s = 0.002;
    ClockTracker c(config, Eigen::Matrix3d::Identity(), kAxis);
    walk(c, handHeld(), 0.0, 0.004, 30.0);
    EXPECT_NEAR(c.stats().encoder_offset_s, 0.002, 1e-9);
    EXPECT_TRUE(c.stats().encoder_at_bound);
    EXPECT_NEAR(c.stats().encoder_target_s * 1e3, 4.0, 0.2);  // what it wanted, reported
}

TEST(ClockTracker, TurningOnlyAboutTheShaftLeavesTheEncoderAlone) {
    // Every rotation about the shaft axis commutes with a turn about it: the sweeps' turn is not
    // observable, and the tracker must not invent one (the IMU's clock still is: the rate varies).
    ClockTracker c({}, Eigen::Matrix3d::Identity(), kAxis);
    const Motion about_shaft = [](double t) {
        return Eigen::Matrix3d(
            Eigen::AngleAxisd(0.8 * std::sin(0.7 * t) + 0.3 * std::sin(2.3 * t), kAxis));
    };
    walk(c, about_shaft, 0.002, 0.0015, 30.0);
    EXPECT_EQ(c.stats().encoder_offset_s, 0.0);
    EXPECT_GT(c.stats().turn_std_rad, ClockTrackerConfig{}.max_turn_std_rad);
    EXPECT_NEAR(c.stats().imu_offset_s * 1e3, 2.0, 0.1);
}

TEST(ClockTracker, StartsFromThePreviousScansOffsetsWithinTheBounds) {
    ClockTrackerConfig config;
    config.start_imu_offset_s = -0.002;
    config.start_encoder_offset_s = 0.009;  // beyond the 5 ms bound
    ClockTracker c(config, Eigen::Matrix3d::Identity(), kAxis);
    EXPECT_EQ(c.imuOffset(), fromSeconds(-0.002));
    EXPECT_EQ(c.encoderOffset(), fromSeconds(config.encoder_bound_s));
    // Already right: a walk with those clocks leaves the IMU's where it is.
    walk(c, handHeld(), -0.002, 0.0, 30.0);
    EXPECT_NEAR(c.stats().imu_offset_s * 1e3, -2.0, 0.1);
    EXPECT_NEAR(c.stats().encoder_offset_s * 1e3, 0.0, 0.05);
}

TEST(ClockTracker, ConfiguredClocksAreAppliedAndCentreTheBounds) {
    // A daemon that installed a new calibration keeps the drivers' stamps and configures the new
    // latencies as offsets from them: they apply from the first sample, and the bounds are about
    // them, not about the stamps.
    ClockTrackerConfig config;
    config.configured_imu_offset_s = config.start_imu_offset_s = 0.004;
    config.configured_encoder_offset_s = config.start_encoder_offset_s = 0.003;
    config.imu_bound_s = config.encoder_bound_s = 0.002;
    ClockTracker c(config, Eigen::Matrix3d::Identity(), kAxis);
    EXPECT_EQ(c.imuOffset(), fromSeconds(0.004));
    EXPECT_EQ(c.encoderOffset(), fromSeconds(0.003));
    walk(c, handHeld(), 0.005, 0.006, 30.0);
    EXPECT_NEAR(c.stats().imu_offset_s * 1e3, 5.0, 0.1);  // within 4 +- 2 ms
    EXPECT_FALSE(c.stats().imu_at_bound);
    EXPECT_NEAR(c.stats().encoder_offset_s, 0.005, 1e-9);  // 3 + 2 ms: held, and said
    EXPECT_TRUE(c.stats().encoder_at_bound);

    // Tracking off: the configured clocks are still the ones applied.
    config.enabled = false;
    ClockTracker off(config, Eigen::Matrix3d::Identity(), kAxis);
    walk(off, handHeld(), 0.005, 0.006, 10.0);
    EXPECT_EQ(off.imuOffset(), fromSeconds(0.004));
    EXPECT_EQ(off.encoderOffset(), fromSeconds(0.003));
}

TEST(ClockTracker, AStillScannerDeterminesNothing) {
    // On a tripod (or a table) the gyro reads only its noise: no rotation, no clock to see. The
    // solve has no information and must neither move the clocks nor claim a bound.
    ClockTracker c({}, Eigen::Matrix3d::Identity(), kAxis);
    const Motion still = [](double) { return Eigen::Matrix3d::Identity(); };
    walk(c, still, 0.002, 0.0015, 30.0);
    EXPECT_EQ(c.imuOffset(), 0);
    EXPECT_EQ(c.encoderOffset(), 0);
    EXPECT_FALSE(c.stats().imu_at_bound);
    EXPECT_FALSE(c.stats().encoder_at_bound);
    EXPECT_EQ(c.stats().determined, 0u);
}

TEST(ClockTracker, DisabledDoesNothing) {
    ClockTrackerConfig config;
    config.enabled = false;
    ClockTracker c(config, Eigen::Matrix3d::Identity(), kAxis);
    walk(c, handHeld(), 0.0025, 0.0015, 20.0);
    EXPECT_EQ(c.stats().solves, 0u);
    EXPECT_EQ(c.imuOffset(), 0);
    EXPECT_EQ(c.encoderOffset(), 0);
}

}  // namespace
}  // namespace handscan::lio
