// The 200 Hz output carries the directions the camera solved (section 8) while VIO frames keep
// coming, and none once they stop (a bypassed camera): the live map's VIO column.
#include <gtest/gtest.h>

#include "handscan/lio/laser_inertial_odometry.hpp"

namespace handscan::lio {
namespace {

ImuSample still(TimeNs t) {
    ImuSample s;
    s.t_host = t;
    s.accel_mps2_imu = Eigen::Vector3d(0.0, 0.0, 9.81);
    return s;
}

TEST(LioVisualMask, OutputPosesCarryTheCamerasDirectionsWhileFramesCome) {
    LioConfig config;
    config.laser_enabled = false;  // camera and IMU only: no sweeps needed
    LaserInertialOdometry lio(config, Calibration{});
    constexpr TimeNs kStep = 5 * kNsPerMs;
    TimeNs t = 0;
    for (; !lio.aligned() && t < 20 * kNsPerSec; t += kStep) lio.addImu(still(t));
    ASSERT_TRUE(lio.aligned()) << "no gravity alignment after 20 s still";
    (void)lio.takePoses();
    // Frames at 50 Hz solving everything but the yaw (bit 2) for one second.
    const std::uint8_t mask = 0x3F & ~0x04;
    const TimeNs t_frames_end = t + kNsPerSec;
    for (; t < t_frames_end; t += kStep) {
        if ((t / kStep) % 4 == 0) {
            PoseEstimate vio;
            vio.t_host = t;
            vio.solved_dof_mask = mask;
            vio.source = PoseSource::kVisualOdometry;
            lio.addVisualPose(vio, Matrix6d::Identity());
        }
        lio.addImu(still(t));
    }
    std::vector<PoseEstimate> with_frames = lio.takePoses();
    ASSERT_GT(with_frames.size(), 150u);
    for (std::size_t i = 4; i < with_frames.size(); ++i)
        EXPECT_EQ(with_frames[i].visual_solved_dof_mask, mask) << "pose " << i;
    // The camera goes dark: within visual_max_gap_s the column empties.
    for (const TimeNs end = t + kNsPerSec; t < end; t += kStep) lio.addImu(still(t));
    std::vector<PoseEstimate> after = lio.takePoses();
    ASSERT_GT(after.size(), 150u);
    const auto gap = static_cast<TimeNs>(config.visual_max_gap_s * 1e9);
    for (const PoseEstimate& p : after) {
        if (p.t_host > t_frames_end + gap) {
            EXPECT_EQ(p.visual_solved_dof_mask, 0);
        }
    }
}

}  // namespace
}  // namespace handscan::lio
