// Transform integration (section 7): scan pose + VIO increment + IMU increment.
#include "handscan/fusion/transform_integrator.hpp"

#include <gtest/gtest.h>

#include "handscan/core/se3.hpp"

namespace handscan::fusion {
namespace {

// A predictor moving at constant velocity along x (world), level, so its motion is known exactly.
class Integration : public ::testing::Test {
protected:
    void SetUp() override {
        imu::NavState x;
        x.v_world_imu = Eigen::Vector3d(1.0, 0.0, 0.0);
        predictor_.initialize(x, {});
        for (int k = 0; k <= 400; ++k) {  // 2 s at 200 Hz
            ImuSample s;
            s.t_host = k * 5 * kNsPerMs;
            s.accel_mps2_imu = Eigen::Vector3d(0, 0, 9.81);
            ASSERT_TRUE(predictor_.addImu(s).isOk());
        }
    }
    imu::ImuPredictor predictor_{imu::ImuPredictorConfig{}, Eigen::Isometry3d::Identity()};
};

TEST_F(Integration, PredictionOnlyBeforeTheFirstScanMatch) {
    TransformIntegrator integrator(predictor_);
    auto p = integrator.poseAt(kNsPerSec);
    ASSERT_TRUE(p);
    EXPECT_EQ(p->source, PoseSource::kImuPrediction);
    EXPECT_NEAR(p->T_world_body.translation().x(), 1.0, 1e-9);
}

TEST_F(Integration, ScanPoseComposedWithTheImuIncrement) {
    TransformIntegrator integrator(predictor_);
    PoseEstimate scan;
    scan.t_host = kNsPerSec;  // the matcher says: at 1 s the body was elsewhere and turned
    scan.T_world_body.translation() = Eigen::Vector3d(5.0, 2.0, 0.5);
    scan.T_world_body.linear() = expSO3(Eigen::Vector3d(0, 0, M_PI / 2));
    scan.solved_dof_mask = 0x1F;  // tz degenerate
    scan.source = PoseSource::kScanMatching;
    integrator.setScanPose(scan);

    auto at_scan = integrator.poseAt(kNsPerSec);
    ASSERT_TRUE(at_scan);
    EXPECT_LT((at_scan->T_world_body.matrix() - scan.T_world_body.matrix()).norm(), 1e-9);
    // 0.5 s later the IMU moved 0.5 m along its x, which the scan pose turned to world +y.
    auto later = integrator.poseAt(1500 * kNsPerMs);
    ASSERT_TRUE(later);
    EXPECT_LT((later->T_world_body.translation() - Eigen::Vector3d(5.0, 2.5, 0.5)).norm(), 1e-9);
    EXPECT_EQ(later->source, PoseSource::kIntegrated);
    EXPECT_EQ(later->solved_dof_mask, 0x1F);
}

TEST_F(Integration, VisualIncrementBetweenScanAndImu) {
    TransformIntegrator integrator(predictor_);
    // VIO (its own drifting frame) says the body moved 0.3 m along y between 1.0 s and 1.2 s.
    Eigen::Isometry3d vio_frame = Eigen::Isometry3d::Identity();
    vio_frame.translation() = Eigen::Vector3d(100, 0, 0);
    for (int k = 0; k <= 4; ++k) {
        PoseEstimate v;
        v.t_host = (900 + 50 * k) * kNsPerMs;
        v.T_world_body = vio_frame;
        v.T_world_body.translation().y() += k >= 2 ? 0.15 * (k - 2) : 0.0;
        integrator.setVisualPose(v);
    }
    PoseEstimate scan;
    scan.t_host = kNsPerSec;
    integrator.setScanPose(scan);
    // VIO covers 1.0 s -> 1.1 s (y: 0 -> 0.3), then the IMU from 1.1 s.
    auto p = integrator.poseAt(1200 * kNsPerMs);
    ASSERT_TRUE(p);
    const double vio_dy = 0.3;  // k = 2 at 1.0 s (0), k = 4 at 1.1 s (0.3)
    EXPECT_NEAR(p->T_world_body.translation().y(), vio_dy, 1e-9);
    EXPECT_NEAR(p->T_world_body.translation().x(), 0.1, 1e-9);  // IMU 1.1 s -> 1.2 s at 1 m/s
}

}  // namespace
}  // namespace handscan::fusion
