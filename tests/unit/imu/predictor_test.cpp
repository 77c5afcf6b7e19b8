// ImuPredictor: static-start alignment, queries at any time, bad input, and feedback from a
// scan matcher (bias convergence, DOF masks) on an analytic motion with known biases.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <cstdio>

#include "handscan/core/config.hpp"
#include "handscan/imu/imu_predictor.hpp"
#include "synthetic_motion.hpp"

namespace handscan::imu {
namespace {

using testing::SyntheticMotion;

constexpr double kDt = 0.005;  // 200 Hz

Eigen::Isometry3d camchainTCamImu() {
    // The rig's Kalibr camchain (config/camchain.yaml via calibration.yaml).
    return loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml")
        .tracking.T_cam_imu;
}

ImuBiases trueBiases() {
    ImuBiases b;
    b.gyro_radps = Eigen::Vector3d(0.010, -0.020, 0.015);
    b.accel_mps2 = Eigen::Vector3d(0.10, -0.05, 0.08);
    return b;
}

TEST(ImuPredictor, AlignsFromAStaticStartAndThenPredicts) {
    const Eigen::Matrix3d R0 = expSO3(Eigen::Vector3d(0.2, -0.15, 0.7));
    const ImuBiases b = trueBiases();
    const Calibration calibration =
        loadCalibration(std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml");
    ImuPredictor predictor({}, calibration);
    EXPECT_TRUE(
        (predictor.T_imu_body() * calibration.tracking.T_cam_imu).matrix().isIdentity(1e-12));
    // 1.5 s held still (tilted), then moving.
    for (int k = 0; k < 300; ++k) {
        ImuSample s;
        s.t_host = k * 5 * kNsPerMs;
        s.gyro_radps_imu = b.gyro_radps;
        s.accel_mps2_imu = R0.transpose() * Eigen::Vector3d(0, 0, 9.81);
        ASSERT_TRUE(predictor.addImu(s).isOk());
    }
    ASSERT_TRUE(predictor.initialized());
    ASSERT_TRUE(predictor.alignment().has_value());
    const GravityAlignment& a = *predictor.alignment();
    const Eigen::Vector3d up_true = R0.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_est = a.R_world_imu.transpose() * Eigen::Vector3d::UnitZ();
    EXPECT_LT((up_true - up_est).norm(), 1e-9);
    EXPECT_LT((a.biases.gyro_radps - b.gyro_radps).norm(), 1e-12);
    EXPECT_LT((predictor.biases().gyro_radps - b.gyro_radps).norm(), 1e-12);
    // Still: the prediction stays put.
    auto x = predictor.stateAt(predictor.newestTime());
    ASSERT_TRUE(x);
    EXPECT_LT(x->p_world_imu.norm(), 1e-9);
    // Before alignment nothing is known.
    EXPECT_FALSE(predictor.poseAt(0).isOk());
}

TEST(ImuPredictor, NoAlignmentWhileMoving) {
    const SyntheticMotion m;
    ImuPredictor predictor({}, Eigen::Isometry3d::Identity());
    for (int k = 0; k < 1000; ++k) ASSERT_TRUE(predictor.addImu(m.sample(k * kDt)).isOk());
    EXPECT_FALSE(predictor.initialized());
}

class PredictorOnMotion : public ::testing::Test {
protected:
    void SetUp() override {
        T_cam_imu_ = camchainTCamImu();
        predictor_ = std::make_unique<ImuPredictor>(ImuPredictorConfig{}, T_cam_imu_);
    }
    Eigen::Isometry3d trueBody(double t) const {
        return m_.state(t).T_world_imu() * T_cam_imu_.inverse();
    }
    void feed(int from, int to, const ImuBiases& b = {}) {
        for (int k = from; k < to; ++k)
            ASSERT_TRUE(predictor_->addImu(m_.sample(k * kDt, b)).isOk());
    }
    SyntheticMotion m_;
    Eigen::Isometry3d T_cam_imu_;
    std::unique_ptr<ImuPredictor> predictor_;
};

TEST_F(PredictorOnMotion, PoseAtAnyTimeInsideTheHistory) {
    predictor_->initialize(m_.state(0.0), {});
    feed(0, 400);
    for (double t : {0.0025, 0.5, 1.2345, 1.99}) {
        auto T = predictor_->poseAt(fromSeconds(t));
        ASSERT_TRUE(T) << T.status().message();
        EXPECT_LT((T->translation() - trueBody(t).translation()).norm(), 1e-4) << t;
        EXPECT_LT(rotationAngle(T->linear(), trueBody(t).linear()), 1e-5) << t;
    }
    // Short extrapolation is allowed, long is an error naming the history.
    EXPECT_TRUE(predictor_->poseAt(fromSeconds(1.995 + 0.02)).isOk());
    const auto far = predictor_->poseAt(fromSeconds(3.0));
    ASSERT_FALSE(far.isOk());
    EXPECT_NE(far.status().message().find("outside the IMU history"), std::string::npos);
    auto p = predictor_->predict(fromSeconds(1.0));
    ASSERT_TRUE(p);
    EXPECT_EQ(p->source, PoseSource::kImuPrediction);
    EXPECT_EQ(p->solved_dof_mask, 0);
}

TEST_F(PredictorOnMotion, BadSamplesAreDroppedAndThePredictionGoesOn) {
    predictor_->initialize(m_.state(0.0), {});
    feed(0, 100);
    ImuSample bad = m_.sample(100 * kDt);
    bad.accel_mps2_imu.x() = std::nan("");
    EXPECT_EQ(predictor_->addImu(bad).code(), StatusCode::kInvalidArgument);
    const Status old = predictor_->addImu(m_.sample(50 * kDt));
    EXPECT_EQ(old.code(), StatusCode::kInvalidArgument);
    EXPECT_NE(old.message().find("not newer"), std::string::npos);
    feed(101, 200);
    EXPECT_EQ(predictor_->stats().rejected_samples, 2u);
    auto T = predictor_->poseAt(fromSeconds(199 * kDt));
    ASSERT_TRUE(T);
    EXPECT_LT((T->translation() - trueBody(199 * kDt).translation()).norm(), 1e-3);
    // Feedback from outside the history is refused with a reason.
    const Status s = predictor_->correct(fromSeconds(5.0), trueBody(5.0), kAllDofs);
    EXPECT_EQ(s.code(), StatusCode::kNotFound);
}

TEST_F(PredictorOnMotion, FeedbackConvergesToTheTrueBiases) {
    const ImuBiases b = trueBiases();
    predictor_->initialize(m_.state(0.0), {});  // biases unknown
    int next = 0;
    auto feedUntil = [&](double t) {
        for (; next * kDt <= t + 1e-9; ++next)
            ASSERT_TRUE(predictor_->addImu(m_.sample(next * kDt, b)).isOk());
    };
    // A scan match every second (its pose refers to the sweep time, which falls between IMU
    // samples), arriving 0.3 s later.
    for (int sweep = 1; sweep <= 30; ++sweep) {
        const double t = sweep * 1.0 + 0.0021;
        feedUntil(t + 0.3);
        const Status s = predictor_->correct(fromSeconds(t), trueBody(t), kAllDofs);
        ASSERT_TRUE(s.isOk()) << s.message();
        // The pose at the feedback time is now the feedback.
        EXPECT_LT(
            (predictor_->poseAt(fromSeconds(t))->translation() - trueBody(t).translation()).norm(),
            1e-9);
    }
    const ImuBiases& e = predictor_->biases();
    // The accelerometer bias (body frame) and the horizontal gravity correction (world frame) are
    // told apart only by rotation, so what must converge is the acceleration error they make
    // together at the current attitude: R (b_true - b_est) + (g_est - g_true).
    const double t_last = 30.0021;
    const Eigen::Vector3d accel_err =
        m_.R(t_last) * (b.accel_mps2 - e.accel_mps2) + (predictor_->gravity() - gravityWorld(9.81));
    std::printf(
        "biases after 30 feedbacks: gyro err %.2e rad/s, accel bias err %.2e m/s^2, gravity err "
        "%.2e m/s^2, "
        "acceleration err %.2e m/s^2\n",
        (e.gyro_radps - b.gyro_radps).norm(), (e.accel_mps2 - b.accel_mps2).norm(),
        (predictor_->gravity() - gravityWorld(9.81)).norm(), accel_err.norm());
    EXPECT_LT((e.gyro_radps - b.gyro_radps).norm(), 2e-4);
    EXPECT_LT(accel_err.norm(), 5e-3);
    EXPECT_LT((e.accel_mps2 - b.accel_mps2).norm(), 0.05);  // the split itself: within the tilt
    // The samples after the last feedback were re-integrated: 0.3 s later the prediction is close.
    const double t_end = 30.3021;
    auto T = predictor_->poseAt(fromSeconds(t_end));
    ASSERT_TRUE(T);
    EXPECT_LT((T->translation() - trueBody(t_end).translation()).norm(), 2e-3);
    // And 1 s of pure prediction from there stays within a centimetre (it drifted by decimetres
    // with the uncorrected biases).
    feedUntil(31.3);
    auto T1 = predictor_->poseAt(fromSeconds(31.3));
    ASSERT_TRUE(T1);
    EXPECT_LT((T1->translation() - trueBody(31.3).translation()).norm(), 0.01);
    // Queries just before a feedback time keep the earlier prediction (history is not rewritten).
    EXPECT_TRUE(predictor_->poseAt(fromSeconds(30.0021) - 1000).isOk());
}

TEST_F(PredictorOnMotion, FeedbackOnlyActsInTheSolvedDofs) {
    predictor_->initialize(m_.state(0.0), {});
    int next = 0;
    auto feedUntil = [&](double t) {
        for (; next * kDt <= t + 1e-9; ++next)
            ASSERT_TRUE(predictor_->addImu(m_.sample(next * kDt, trueBiases())).isOk());
    };
    // A matcher degenerate in tz and rz (e.g. a long flat floor seen from above... in world
    // axes) returns garbage there: +1 m in z and +10 deg of yaw.
    const std::uint8_t mask = kAllDofs & ~(1u << 2) & ~(1u << 5);
    for (int sweep = 1; sweep <= 8; ++sweep) {
        const double t = sweep * 1.0 + (sweep % 2 ? 0.0 : 0.0033);  // on and between samples
        feedUntil(t + 0.2);
        const NavState before = *predictor_->stateAt(fromSeconds(t));
        const Eigen::Isometry3d body_before = *predictor_->poseAt(fromSeconds(t));
        Eigen::Isometry3d garbage = trueBody(t);
        garbage.translation().z() += 1.0;
        garbage.linear() = expSO3(Eigen::Vector3d(0, 0, 10.0 * M_PI / 180.0)) * garbage.linear();
        ASSERT_TRUE(predictor_->correct(fromSeconds(t), garbage, mask).isOk());
        const NavState after = *predictor_->stateAt(fromSeconds(t));
        const Eigen::Isometry3d body_after = *predictor_->poseAt(fromSeconds(t));
        const NavState truth = m_.state(t);
        // Unsolved: the body's z and yaw untouched; solved: the body's x, y are the truth.
        EXPECT_NEAR(body_after.translation().z(), body_before.translation().z(), 1e-9);
        EXPECT_LT((body_after.translation() - trueBody(t).translation()).head<2>().norm(), 1e-9);
        const Eigen::Vector3d dtheta = logSO3(after.R_world_imu * before.R_world_imu.transpose());
        EXPECT_NEAR(dtheta.z(), 0.0, 1e-9);
        // Solved rotation DOFs: the truth's roll/pitch up to the coupling with the held yaw.
        EXPECT_LT(std::abs(logSO3(truth.R_world_imu * after.R_world_imu.transpose()).x()), 0.02);
        EXPECT_LT(std::abs(logSO3(truth.R_world_imu * after.R_world_imu.transpose()).y()), 0.02);
    }
    // The rotation feedback in x, y still observes the gyro bias (partly: yaw is held).
    EXPECT_LT(predictor_->biases().gyro_radps.norm(), 0.1);
}

// A scan matcher occasionally slips (a corridor seen along its axis: one sweep lands 15 cm off,
// the next snaps back). The pose follows the feedback, but the velocity must keep following the
// IMU: with unweighted rows the slip became a 0.26 m/s velocity error that rang for seconds.
TEST_F(PredictorOnMotion, AMatcherSlipDoesNotRingTheVelocity) {
    predictor_->initialize(m_.state(0.0), {});
    int next = 0;
    auto feedUntil = [&](double t) {
        for (; next * kDt <= t + 1e-9; ++next)
            ASSERT_TRUE(predictor_->addImu(m_.sample(next * kDt, trueBiases())).isOk());
    };
    double worst_v = 0.0, worst_after = 0.0;
    for (int sweep = 1; sweep <= 40; ++sweep) {
        const double t = sweep * 0.5 + 0.0013;
        feedUntil(t + 0.5);
        Eigen::Isometry3d fed = trueBody(t);
        if (sweep == 30) fed.translation() += Eigen::Vector3d(0.15, 0.0, 0.0);  // the slip
        ASSERT_TRUE(predictor_->correct(fromSeconds(t), fed, kAllDofs).isOk());
        const double v_err =
            (predictor_->stateAt(fromSeconds(t))->v_world_imu - m_.state(t).v_world_imu).norm();
        if (sweep >= 20 && sweep < 30) worst_v = std::max(worst_v, v_err);
        if (sweep >= 30) worst_after = std::max(worst_after, v_err);
    }
    std::printf("velocity error before the slip %.4f m/s, from the slip on %.4f m/s\n", worst_v,
                worst_after);
    EXPECT_LT(worst_v, 0.01);      // still converging from zero biases: 6 mm/s
    EXPECT_LT(worst_after, 0.02);  // 4 mm/s (the unweighted estimator: 0.26 m/s)
    // And the biases were not thrown off.
    EXPECT_LT((predictor_->biases().gyro_radps - trueBiases().gyro_radps).norm(), 1e-3);
}

// Feedback degenerate along a direction that is no world axis (a corridor at 45 degrees): with
// the eq. (21) projector, the position along it stays the prediction's and the velocity along it
// is the motion prior's (unsolved_motion_prior.hpp), however wrong the matcher's value there: a
// twin predictor fed the truth ends in exactly the same state. Across it they follow the feedback.
TEST_F(PredictorOnMotion, FeedbackInADiagonalDegenerateDirectionIsIgnored) {
    predictor_->initialize(m_.state(0.0), {});
    ImuPredictor twin(ImuPredictorConfig{}, T_cam_imu_);
    twin.initialize(m_.state(0.0), {});
    int next = 0;
    auto feedUntil = [&](double t) {
        for (; next * kDt <= t + 1e-9; ++next) {
            ASSERT_TRUE(predictor_->addImu(m_.sample(next * kDt, trueBiases())).isOk());
            ASSERT_TRUE(twin.addImu(m_.sample(next * kDt, trueBiases())).isOk());
        }
    };
    const Eigen::Vector3d d = Eigen::Vector3d(1.0, 1.0, 0.0).normalized();
    Matrix6d P = Matrix6d::Identity();
    P.bottomRightCorner<3, 3>() -= d * d.transpose();
    EXPECT_LT((unsolvedTranslation(P) - d * d.transpose()).norm(), 1e-12);
    for (int sweep = 1; sweep <= 10; ++sweep) {
        const double t = sweep * 0.5;
        feedUntil(t + 0.3);
        const Eigen::Isometry3d before = *predictor_->poseAt(fromSeconds(t));
        Eigen::Isometry3d garbage = trueBody(t);
        garbage.translation() += 0.7 * d;
        ASSERT_TRUE(predictor_->correct(fromSeconds(t), garbage, P).isOk());
        ASSERT_TRUE(twin.correct(fromSeconds(t), trueBody(t), P).isOk());
        const Eigen::Isometry3d after = *predictor_->poseAt(fromSeconds(t));
        const Eigen::Vector3d v_after = predictor_->stateAt(fromSeconds(t))->v_world_imu;
        EXPECT_NEAR(d.dot(after.translation()), d.dot(before.translation()), 1e-9);
        EXPECT_LT((after.translation() - twin.poseAt(fromSeconds(t))->translation()).norm(), 1e-9);
        EXPECT_LT((v_after - twin.stateAt(fromSeconds(t))->v_world_imu).norm(), 1e-9);
        const Eigen::Vector3d across = (after.translation() - trueBody(t).translation()) -
                                       d * d.dot(after.translation() - trueBody(t).translation());
        EXPECT_LT(across.norm(), 1e-9);
    }
}

// The motion prior on its own, in a closed loop with a simulated IMU: along the unsolved x axis
// the IMU's velocity carries a world-fixed 0.05 m/s^2 tilt error (minus the gravity correction
// the prior handed back so far).
class PriorLoop {
public:
    explicit PriorLoop(double tilt) : tilt_(tilt) { along_x_(0, 0) = 1.0; }
    UnsolvedMotionPrior prior;
    Eigen::Vector3d v = Eigen::Vector3d(1.4, 0.1, 0.0);
    Eigen::Vector3d gravity_correction = Eigen::Vector3d::Zero();
    double t = 1.0;
    // One feedback 0.5 s later; the IMU integrated the true acceleration plus the tilt error.
    void step(double true_accel, bool x_solved = false) {
        t += 0.5;
        Eigen::Vector3d imu =
            v + Eigen::Vector3d(true_accel + tilt_ + gravity_correction.x(), 0.0, 0.0) * 0.5;
        imu.y() = 0.05;  // a solved direction: passes
        v = prior.apply(fromSeconds(t), imu, x_solved ? Eigen::Matrix3d::Zero() : along_x_);
        gravity_correction += prior.gravityStep();
        EXPECT_DOUBLE_EQ(v.y(), 0.05);
    }

private:
    double tilt_;
    Eigen::Matrix3d along_x_ = Eigen::Matrix3d::Zero();
};

// A tunnel from the start (x never solved): the tilt is learnt and the walking speed held
// (decaying slowly), while a real manoeuvre (1 m/s^2 for 2 s) passes.
TEST(UnsolvedMotionPrior, NeverSolvedHoldsTheWalkLearnsTheTiltAndPassesManoeuvres) {
    PriorLoop loop(0.05);
    while (loop.t < 40.0) loop.step(0.0);
    const double before = loop.v.x();
    for (int k = 0; k < 4; ++k) loop.step(1.0);  // a turn: +2 m/s in 2 s
    std::printf("after 40 s: tilt learnt %.4f m/s^2, speed %.3f m/s; the turn added %.3f m/s\n",
                loop.prior.accelError().x(), before, loop.v.x() - before);
    // Decay 60 s alone: 1.4 e^-2/3 = 0.72; without the tilt tracking it would have run 2 m/s off.
    EXPECT_NEAR(loop.prior.accelError().x(), 0.05, 0.015);  // 0.059: it also took some decay
    EXPECT_NEAR(loop.gravity_correction.x(), -loop.prior.accelError().x(), 1e-12);
    EXPECT_GT(before, 0.5);
    EXPECT_LT(before, 1.5);
    EXPECT_GT(loop.v.x() - before, 1.8);
    EXPECT_EQ(loop.prior.held(), loop.v);
    // Without the prior the IMU's value is kept.
    UnsolvedMotionPriorConfig c;
    c.enabled = false;
    UnsolvedMotionPrior off(c);
    Eigen::Matrix3d along_x = Eigen::Matrix3d::Zero();
    along_x(0, 0) = 1.0;
    EXPECT_DOUBLE_EQ(off.apply(fromSeconds(1.0), Eigen::Vector3d(3.0, 0.0, 0.0), along_x).x(), 3.0);
}

// A corridor seen along its axis after every direction was solved for 40 s (20 s to climb the
// ramp from the start's "prior alone", 20 s of grace): the IMU (its biases learnt meanwhile) is
// trusted for imu_trusted_s, then the prior ramps in.
TEST(UnsolvedMotionPrior, AfterASolvedStretchTheImuIsTrustedForAWhile) {
    PriorLoop loop(0.05);
    while (loop.t < 41.5) loop.step(0.0, true);  // all solved for 40 s
    const double v0 = loop.v.x();
    const double t0 = loop.t;
    while (loop.t < t0 + 19.5) loop.step(0.0);
    // 19.5 s of IMU alone: its tilt error integrated, nothing learnt, nothing decayed.
    EXPECT_NEAR(loop.v.x(), v0 + 0.05 * 19.5, 1e-9);
    EXPECT_EQ(loop.prior.accelError().x(), 0.0);
    EXPECT_EQ(loop.prior.strength(), 0.0);
    while (loop.t < t0 + 30.0) loop.step(0.0);
    EXPECT_NEAR(loop.prior.strength(), 0.5, 1e-9);  // half way up the 20 s ramp
    while (loop.t < t0 + 80.0) loop.step(0.0);
    EXPECT_NEAR(loop.prior.accelError().x(), 0.05, 0.015);  // then the prior took over
}

// A tunnel where one sweep solved the axis (a weak direction confirmed once): that sweep taught
// the IMU nothing about its biases along the axis, so it buys no more trust than its own 0.5 s.
// (Before, any solved sweep bought imu_trusted_s = 20 s of IMU alone, and one such sweep in the
// simulated 90 s tunnel, seed 3, took the ATE from 13 to 107 m.)
TEST(UnsolvedMotionPrior, AnOddSolvedSweepBuysOnlyItsOwnPeriod) {
    PriorLoop loop(0.05);
    while (loop.t < 40.0) loop.step(0.0);
    EXPECT_EQ(loop.prior.strength(), 1.0);
    loop.step(0.0, true);
    loop.step(0.0);
    EXPECT_NEAR(loop.prior.strength(), 1.0, 1e-9);  // -20 s + 0.5 s - 0.5 s: the prior acts fully
    // Ten solved seconds earn back half of the 20 s ramp.
    for (int k = 0; k < 20; ++k) loop.step(0.0, true);
    loop.step(0.0);
    EXPECT_NEAR(loop.prior.strength(), 0.525, 1e-9);  // -20 + 10 - 0.5 s of a 20 s ramp
}

// After a gap the held attitude misses the turn made in it (integrateOrHold): gravity's share
// along the missed tilt leaks into the acceleration until relevel() takes the tilt out.
TEST(ImuPredictor, AfterAGapTheHeldAttitudesTiltIsLevelledFromTheAccelerometer) {
    // Walking steadily at 1 m/s along x, level; in a 2 s gap the body rolled 7 deg and turned
    // 40 deg, and walks on as steadily.
    ImuPredictor p({}, Eigen::Isometry3d::Identity());
    NavState x0;
    x0.v_world_imu = Eigen::Vector3d(1.0, 0.0, 0.0);
    p.initialize(x0, {});
    const Eigen::Matrix3d R1 = (Eigen::AngleAxisd(40.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(7.0 * M_PI / 180.0, Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
    auto add = [&](int from, int to, const Eigen::Matrix3d& R) {
        for (int k = from; k < to; ++k) {
            ImuSample s;
            s.t_host = k * 5 * kNsPerMs;
            s.accel_mps2_imu = R.transpose() * Eigen::Vector3d(0, 0, 9.81);
            ASSERT_TRUE(p.addImu(s).isOk());
        }
    };
    add(0, 201, Eigen::Matrix3d::Identity());  // 0 .. 1 s
    add(600, 1001, R1);                        // the gap 1 .. 3 s, then 3 .. 5 s
    const TimeNs back = 3 * kNsPerSec, end = 5 * kNsPerSec;
    const Eigen::Vector3d v_back = p.stateAt(back)->v_world_imu;
    EXPECT_LT((v_back - x0.v_world_imu).norm(), 1e-9);  // held across the gap
    // 7 deg of gravity: 1.2 m/s^2 for 2 s.
    EXPECT_NEAR((p.stateAt(end)->v_world_imu - v_back).norm(),
                9.81 * std::sin(7.0 * M_PI / 180.0) * 2.0, 0.05);

    EXPECT_FALSE(p.relevel(end, end).isOk());  // one sample: not enough
    const auto tilt = p.relevel(back, back + kNsPerSec);
    ASSERT_TRUE(tilt.isOk()) << tilt.status().message();
    EXPECT_NEAR(*tilt * 180.0 / M_PI, 7.0, 1e-6);
    const auto x = p.stateAt(end);
    ASSERT_TRUE(x.isOk());
    const Eigen::Vector3d up_est = x->R_world_imu.transpose() * Eigen::Vector3d::UnitZ();
    const Eigen::Vector3d up_true = R1.transpose() * Eigen::Vector3d::UnitZ();
    EXPECT_LT((up_est - up_true).norm(), 1e-6);
    EXPECT_LT((x->v_world_imu - v_back).norm(), 1e-6);  // no gravity in the acceleration
    EXPECT_LT((x->p_world_imu - p.stateAt(back)->p_world_imu - 2.0 * v_back).norm(), 1e-6);
}

TEST(ImuPredictor, StaticStartTakesTheAccelBiasAlongGravity) {
    const Eigen::Matrix3d R0 = expSO3(Eigen::Vector3d(0.1, -0.2, 0.3));
    const Eigen::Vector3d up_imu = R0.transpose() * Eigen::Vector3d::UnitZ();
    ImuPredictor predictor({}, Eigen::Isometry3d::Identity());
    // 0.05 m/s^2 of bias along the vertical: unnoticed, the still IMU would sink 2.5 cm in 1 s.
    for (int k = 0; k < 500; ++k) {
        ImuSample s;
        s.t_host = k * 5 * kNsPerMs;
        s.accel_mps2_imu = up_imu * (9.81 + 0.05);
        ASSERT_TRUE(predictor.addImu(s).isOk());
    }
    ASSERT_TRUE(predictor.alignment().has_value());
    EXPECT_NEAR(predictor.alignment()->accel_norm_error_mps2, 0.05, 1e-9);
    EXPECT_LT((predictor.biases().accel_mps2 - 0.05 * up_imu).norm(), 1e-9);
    EXPECT_LT(predictor.stateAt(predictor.newestTime())->p_world_imu.norm(), 1e-9);
}

TEST(DofProjector, MaskAndEigenvectorForms) {
    const Matrix6d P = projectorFromMask(0x2D);  // rx, rz, tx, tz
    EXPECT_EQ(maskFromProjector(P), 0x2D);
    EXPECT_EQ(P.trace(), 4.0);
    // Eq. (21) with an eigenbasis aligned to the axes but permuted gives the same projector.
    Matrix6d V = Matrix6d::Zero();
    const int order[6] = {5, 0, 3, 2, 1, 4};  // rows = eigenvectors sorted by eigenvalue
    for (int i = 0; i < 6; ++i) V(i, order[i]) = 1.0;
    EXPECT_EQ(maskFromProjector(projectorFromEigenvectors(V, 4)), 0x2D);
    // A rotated basis: the projector is idempotent of rank h and leaves its span unchanged.
    const Eigen::Matrix<double, 6, 6> Q =
        Eigen::HouseholderQR<Matrix6d>(Matrix6d::Random()).householderQ();
    const Matrix6d Pq = projectorFromEigenvectors(Q.transpose(), 3);
    EXPECT_LT((Pq * Pq - Pq).norm(), 1e-9);
    EXPECT_NEAR(Pq.trace(), 3.0, 1e-9);
    EXPECT_LT((Pq * Q.col(0) - Q.col(0)).norm(), 1e-9);
    EXPECT_LT((Pq * Q.col(4)).norm(), 1e-9);
}

}  // namespace
}  // namespace handscan::imu
