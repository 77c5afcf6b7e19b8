// VisualInertialOdometry end to end on rendered frames of a textured room (the config's
// 640x512 equidistant tracking camera) along a known hand-held-like motion at 50 Hz. The IMU
// increments it is given drift (a bias of 1 deg/s and 0.2 m/s of velocity error): the camera
// must correct them. With laser points the features get laser depth; without them some are
// triangulated; in the dark nothing is solved and the IMU prediction passes through (section 8).
#include "handscan/vio/visual_odometry.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "synthetic_camera.hpp"

namespace handscan::vio {
namespace {

constexpr double kRate = 50.0;
// A brisk hand-held sway: +-0.3 m and +-11 deg of yaw over 2 s (up to 0.9 m/s and 36 deg/s).
constexpr double kPeriod = 2.0;

struct RunSummary {
    double final_trans_err_m = 0.0;
    double final_rot_err_rad = 0.0;
    double imu_only_trans_err_m = 0.0;
    int keyframes = 0;
    int max_laser_depth = 0;
    int max_triangulated = 0;
    int frames_all_solved = 0;
    int frames_none_solved = 0;
    int frames = 0;
};

// `chain_from_world`: where the VIO's chain starts relative to the laser points' frame {W} (a
// chain that has drifted from the map); with `laser_frame_pose` each frame's true pose in {W}
// is given for the depth map.
RunSummary run(int frames, bool laser, double brightness,
               const Eigen::Isometry3d& chain_from_world = Eigen::Isometry3d::Identity(),
               bool laser_frame_pose = false) {
    Calibration cal;
    loadCamchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml", cal);
    const test::SyntheticRoom room(7);
    const auto rays = test::pixelRays(cal.tracking);
    std::mt19937 rng(3);
    VisualInertialOdometry vio(cal.tracking);
    // A drifting IMU: each increment's error grows the motion by a rotation of 1 deg/s and a
    // velocity error of 0.2 m/s.
    const Eigen::Vector3d gyro_bias(0.0, 0.0175, 0.0);
    const Eigen::Vector3d vel_err(0.2, 0.0, -0.1);
    const double dt = 1.0 / kRate;
    Eigen::Isometry3d T_imu_only = chain_from_world * test::trajectory(0.0, kPeriod);
    vio.setWorldPose(T_imu_only);
    // The laser has already swept the room once before the first frame.
    if (laser) vio.addLaserPoints(0, test::laserPoints(room, T_imu_only, 60000, 0.01, rng));
    RunSummary s;
    for (int i = 0; i < frames; ++i) {
        const double t = i * dt;
        const Eigen::Isometry3d truth = test::trajectory(t, kPeriod);
        std::optional<Eigen::Isometry3d> imu;
        if (i > 0) {
            const Eigen::Isometry3d prev = test::trajectory(t - dt, kPeriod);
            Eigen::Isometry3d drift = Eigen::Isometry3d::Identity();
            drift.linear() = expSO3(gyro_bias * dt);
            drift.translation() = -vel_err * dt;
            // T_{c-1}^c maps points of frame c-1 into frame c: (T_wc^-1 T_w,c-1).
            imu = drift * truth.inverse() * prev;
            T_imu_only = T_imu_only * imu->inverse();
        }
        if (laser)
            vio.addLaserPoints(static_cast<TimeNs>(t * 1e9),
                               test::laserPoints(room, truth, 3000, 0.01, rng));
        const cv::Mat img = test::render(room, rays, 640, 512, truth, 1.0, rng, brightness);
        if (laser_frame_pose) vio.setLaserFramePose(truth);
        const auto res = vio.processFrame(static_cast<TimeNs>(t * 1e9), img, imu);
        EXPECT_TRUE(res.isOk()) << res.status().message();
        if (!res) continue;
        ++s.frames;
        s.keyframes += res->keyframe;
        s.max_laser_depth = std::max(s.max_laser_depth, res->with_laser_depth);
        s.max_triangulated = std::max(s.max_triangulated, res->triangulated);
        s.frames_all_solved += res->solved_dof_mask == scan::kAllDof;
        s.frames_none_solved += res->solved_dof_mask == 0;
        const Eigen::Isometry3d chain_truth = chain_from_world * truth;
        s.final_trans_err_m = (res->T_world_cam.translation() - chain_truth.translation()).norm();
        s.final_rot_err_rad = rotationAngle(res->T_world_cam.linear(), chain_truth.linear());
        s.imu_only_trans_err_m = (T_imu_only.translation() - chain_truth.translation()).norm();
    }
    std::printf(
        "%d frames: VIO %.1f mm / %.2f deg from the truth, IMU alone %.1f mm; %d key-frames, "
        "up to %d features with laser depth and %d triangulated in a frame\n",
        s.frames, s.final_trans_err_m * 1e3, s.final_rot_err_rad * 57.2958,
        s.imu_only_trans_err_m * 1e3, s.keyframes, s.max_laser_depth, s.max_triangulated);
    return s;
}

TEST(VisualInertialOdometry, LaserDepthCorrectsADriftingImu) {
    const RunSummary s = run(75, true, 1.0);  // 1.5 s
    EXPECT_GT(s.imu_only_trans_err_m, 0.2) << "the IMU alone drifts";
    EXPECT_LT(s.final_trans_err_m, 0.01) << "m after 1.5 s";
    EXPECT_LT(s.final_rot_err_rad, 0.005);
    EXPECT_GT(s.max_laser_depth, 200) << "features with laser depth in a frame";
    EXPECT_LE(s.max_laser_depth, 300);
    EXPECT_GE(s.keyframes, 2);
    EXPECT_GE(s.frames_all_solved, s.frames - 1) << "all but the first frame";
}

TEST(VisualInertialOdometry, DepthMapIsSeenFromThePoseInTheLasersFrame) {
    // The chain 0.4 m and 8 deg away from the map the laser points are in (the worker's VIO
    // chain drifts from the laser-inertial odometry's map between matches): with the frames'
    // poses in the map, the features get the same laser depth as without the offset ...
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
    offset.linear() = expSO3(Eigen::Vector3d(0.05, 0.12, -0.06));
    offset.translation() = Eigen::Vector3d(0.3, -0.2, 0.2);
    const RunSummary s = run(75, true, 1.0, offset, true);
    EXPECT_GT(s.max_laser_depth, 200) << "features with laser depth in a frame";
    EXPECT_LT(s.final_trans_err_m, 0.01) << "m after 1.5 s";
    EXPECT_LT(s.final_rot_err_rad, 0.005);
    // ... seen from the chain's pose the depth map is another place's: depth is wrong or none.
    const RunSummary wrong = run(75, true, 1.0, offset, false);
    EXPECT_GT(wrong.final_trans_err_m, 2.0 * s.final_trans_err_m);
}

TEST(VisualInertialOdometry, WithoutLaserFeaturesAreTriangulated) {
    const RunSummary s = run(75, false, 1.0);
    EXPECT_GT(s.max_triangulated, 100) << "features triangulated in a frame";
    EXPECT_EQ(s.max_laser_depth, 0);
    EXPECT_LT(s.final_trans_err_m, 0.05) << "m after 1.5 s";
    EXPECT_LT(s.final_rot_err_rad, 0.01);
}

TEST(VisualInertialOdometry, DarkCameraSolvesNothingAndPassesTheImuThrough) {
    const RunSummary s = run(20, true, 0.01);
    EXPECT_EQ(s.frames_none_solved, s.frames);
    EXPECT_NEAR(s.final_trans_err_m, s.imu_only_trans_err_m, 1e-9);
}

TEST(VisualInertialOdometry, RejectsFramesOfTheWrongSizeOrFormat) {
    Calibration cal;
    loadCamchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml", cal);
    VisualInertialOdometry vio(cal.tracking);
    EXPECT_FALSE(vio.processFrame(0, cv::Mat(100, 100, CV_8UC1, cv::Scalar(0)), std::nullopt));
    Image yuyv;
    yuyv.format = PixelFormat::kYuyv;
    yuyv.width = 640;
    yuyv.height = 512;
    yuyv.stride_bytes = 1280;
    yuyv.data.resize(1280 * 512);
    EXPECT_FALSE(vio.processFrame(yuyv, std::nullopt));
    Image short_frame;
    short_frame.width = 640;
    short_frame.height = 512;
    short_frame.stride_bytes = 640;
    short_frame.data.resize(1000);
    const auto r = vio.processFrame(short_frame, std::nullopt);
    ASSERT_FALSE(r);
    EXPECT_NE(r.status().message().find("shorter"), std::string::npos);
}

}  // namespace
}  // namespace handscan::vio
