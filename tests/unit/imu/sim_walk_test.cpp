// IMU prediction and feedback on the simulator's own handheld walk (office scene) with exact IMU
// readings (sim::ImuModel::ideal, plus constant biases where stated). This checks the frame
// conventions end to end - the camchain's T_cam_imu (IMU -> camera), the lever arm, gravity, the
// integration order - and the feedback loop on the motion the pipeline really sees.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "handscan/core/config.hpp"
#include "handscan/imu/imu_predictor.hpp"
#include "handscan/sim/imu_model.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::imu {
namespace {

constexpr double kDt = 0.005;  // 200 Hz

class ImuOnSimulatedWalk : public ::testing::Test {
protected:
    void SetUp() override {
        cal_ = loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
        sim::WalkOptions w;
        w.duration_s = 30.0;
        plan_ = sim::makeWalk(sim::buildScene("office").walk_loop, w);
        config_.gravity_mps2 = noise_.gravity;
    }
    // The exact IMU sample at time t (simulation seconds), plus constant biases.
    ImuSample sample(double t, const ImuBiases& b = {}) const {
        const sim::ImuModel model(noise_, T_cam_imu(), 200.0, sim::Rng(1, "imu"));
        ImuSample s;
        s.t_host = fromSeconds(t);
        model.ideal(plan_.trajectory.at(t), s.accel_mps2_imu, s.gyro_radps_imu);
        s.accel_mps2_imu += b.accel_mps2;
        s.gyro_radps_imu += b.gyro_radps;
        return s;
    }
    const Eigen::Isometry3d& T_cam_imu() const { return cal_.tracking.T_cam_imu; }
    Eigen::Isometry3d trueBody(double t) const { return plan_.trajectory.at(t).T_world_body; }
    // True IMU state: the IMU sits at T_cam_imu's translation in {C}; its velocity has the
    // lever-arm term omega x r.
    NavState trueImuState(double t) const {
        const sim::BodyState s = plan_.trajectory.at(t);
        const Eigen::Isometry3d T_wi = s.T_world_body * T_cam_imu();
        NavState x;
        x.t = fromSeconds(t);
        x.R_world_imu = T_wi.linear();
        x.p_world_imu = T_wi.translation();
        x.v_world_imu = s.v_world + s.T_world_body.linear() * s.omega_body.cross(T_cam_imu().translation());
        return x;
    }

    Calibration cal_;
    sim::WalkPlan plan_;
    sim::ImuNoise noise_;
    ImuPredictorConfig config_;
};

TEST_F(ImuOnSimulatedWalk, OneSecondFromTheTrueStateStaysWithinMillimetres) {
    double worst_p = 0.0, worst_r = 0.0;
    for (double t0 = 3.5; t0 < 26.0; t0 += 1.5) {
        ImuPredictor p(config_, T_cam_imu());
        p.initialize(trueImuState(t0), {});
        for (int k = 0; k <= 200; ++k) ASSERT_TRUE(p.addImu(sample(t0 + k * kDt)).isOk());
        auto T = p.poseAt(fromSeconds(t0 + 1.0));
        ASSERT_TRUE(T);
        const Eigen::Isometry3d truth = trueBody(t0 + 1.0);
        worst_p = std::max(worst_p, (T->translation() - truth.translation()).norm());
        worst_r = std::max(worst_r, logSO3(T->linear().transpose() * truth.linear()).norm());
    }
    std::printf("1 s from the true state on the office walk: worst %.2e m, %.2e rad\n", worst_p, worst_r);
    // Midpoint integration at 200 Hz of a walk (peak ~100 deg/s): sub-millimetre. A frame or
    // lever-arm mistake shows up as centimetres within the second.
    EXPECT_LT(worst_p, 1e-3);
    EXPECT_LT(worst_r, 1e-4);
}

// The real situation: static start with unknown accel bias (so the levelled world, which becomes
// the map frame, is tilted by b_horizontal / g), then scan-matching feedback every 0.5 s at the
// sweep starts, each arriving 0.5 s late, exact poses in that map frame. The feedback must learn
// the biases, the velocity and the gravity direction of the tilted frame so that the prediction
// over the next sweep stays within about a centimetre.
TEST_F(ImuOnSimulatedWalk, FeedbackInTheTiltedMapFrameKeepsSweepPredictionsWithinAboutACentimetre) {
    ImuBiases b;
    b.gyro_radps = Eigen::Vector3d(0.003, -0.002, 0.004);
    b.accel_mps2 = Eigen::Vector3d(0.03, -0.025, 0.02);  // the MTi-20's turn-on bias, ~1.5 sigma
    ImuPredictor p(config_, T_cam_imu());
    int next = 0;
    auto feedUntil = [&](double t) {
        for (; next * kDt <= t + 1e-9; ++next) ASSERT_TRUE(p.addImu(sample(next * kDt, b)).isOk());
    };
    feedUntil(2.0);
    ASSERT_TRUE(p.initialized());
    // The map frame: the predictor's world, fixed by the first sweep at t = 2 s.
    const Eigen::Isometry3d T_map_world = *p.poseAt(fromSeconds(2.0)) * trueBody(2.0).inverse();
    const double tilt = std::acos((T_map_world.linear() * Eigen::Vector3d::UnitZ()).z());
    EXPECT_GT(tilt, 1e-3);  // the horizontal bias did tilt it (~0.2 deg)
    std::vector<double> pred_err, vel_err;
    for (double t = 2.5; t <= 27.0; t += 0.5) {
        feedUntil(t + 0.5);
        const Eigen::Isometry3d truth = T_map_world * trueBody(t);
        if (t > 15.0) pred_err.push_back((p.poseAt(fromSeconds(t))->translation() - truth.translation()).norm());
        ASSERT_TRUE(p.correct(fromSeconds(t), truth, kAllDofs).isOk());
        if (t > 15.0) {
            const Eigen::Vector3d v_true = T_map_world.linear() * trueImuState(t).v_world_imu;
            vel_err.push_back((p.stateAt(fromSeconds(t))->v_world_imu - v_true).norm());
        }
    }
    double pmax = 0.0, vmax = 0.0;
    for (double e : pred_err) pmax = std::max(pmax, e);
    for (double e : vel_err) vmax = std::max(vmax, e);
    const Eigen::Vector3d g_map = T_map_world.linear() * Eigen::Vector3d(0, 0, -noise_.gravity);
    const double g_err = std::acos(std::clamp(p.gravity().normalized().dot(g_map.normalized()), -1.0, 1.0));
    std::printf("map tilt %.3f deg; after convergence: prediction error over a sweep max %.4f m, velocity error "
                "max %.4f m/s, gravity direction error %.3f deg; accel bias error %.4f m/s^2\n",
                tilt * 180 / M_PI, pmax, vmax, g_err * 180 / M_PI, (p.biases().accel_mps2 - b.accel_mps2).norm());
    // Measured < 0.1 mm: the 8 s window spans the turns that tell the tilt from the bias. With a
    // 4 s window 8.7 mm / 1.3 cm/s (after the 70 deg/s turn at 21 s, the part of the tilt the
    // body-frame bias had absorbed turns with the device); without the gravity refinement
    // 2.9 cm / 4.6 cm/s and the gravity direction unlearnt.
    EXPECT_LT(pmax, 0.005);
    EXPECT_LT(vmax, 0.005);
    EXPECT_LT(g_err, 0.1 * tilt);
}

}  // namespace
}  // namespace handscan::imu
