// Cost of one 640x512 tracking-camera frame (issue 12's budget: 5 ms on one core): the tracker
// alone (pyramid, KLT of up to 300 features, Harris top-up of the grid) and the whole VIO frame
// (+ undistortion, motion estimation of eqs. 6-11, key-frames with depth association). Frames are
// rendered once from the synthetic room along a closed 2 s hand-held sway at 50 Hz (100 frames,
// looped, so the tracker never jumps), with laser points for the depth map. The depth map's
// build at a key-frame (3 s of laser points) and one motion estimation are timed on their own.
#include <benchmark/benchmark.h>

#include <random>

#include "handscan/vio/visual_odometry.hpp"
#include "synthetic_camera.hpp"

namespace handscan::vio {
namespace {

constexpr int kFrames = 100;
constexpr double kPeriod = 2.0;

struct Sequence {
    CameraIntrinsics camera;
    std::vector<cv::Mat> images;
    std::vector<Eigen::Isometry3d> poses;
    std::vector<std::vector<Eigen::Vector3d>> laser;

    Sequence() {
        Calibration cal;
        loadCamchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml", cal);
        camera = cal.tracking;
        const test::SyntheticRoom room(11);
        const auto rays = test::pixelRays(camera);
        std::mt19937 rng(5);
        for (int i = 0; i < kFrames; ++i) {
            const Eigen::Isometry3d T = test::trajectory(i * kPeriod / kFrames, kPeriod);
            poses.push_back(T);
            images.push_back(test::render(room, rays, 640, 512, T, 1.0, rng));
            // A spinning laser's ~40k points per second: 800 per camera frame.
            laser.push_back(test::laserPoints(room, T, 800, 0.01, rng));
        }
    }
};

const Sequence& sequence() {
    static const Sequence s;
    return s;
}

// Arg 0: the tracker's settings before the gyro's prediction (21 x 21 windows, 4 pyramid
// levels), for comparison in the same run; 1: the current ones. Both without a prediction.
void BM_TrackerFrame(benchmark::State& state) {
    const Sequence& s = sequence();
    FeatureTrackerConfig config;
    if (state.range(0) == 0) {
        config.klt_window_px = 21;
        config.klt_pyramid_levels = 3;
    }
    FeatureTracker tracker(config);
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(tracker.track(s.images[i % kFrames]));
        ++i;
    }
    state.counters["features"] = static_cast<double>(tracker.features().size());
}
BENCHMARK(BM_TrackerFrame)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->MinTime(3.0);

void BM_VioFrame(benchmark::State& state) {
    const Sequence& s = sequence();
    VisualInertialOdometry vio(s.camera);
    vio.setWorldPose(s.poses[0]);
    for (const auto& pts : s.laser) vio.addLaserPoints(0, pts);
    std::size_t i = 0;
    int keyframes = 0;
    double laser_depth = 0;
    TimeNs t = 0;
    for (auto _ : state) {
        const std::size_t k = i % kFrames;
        const std::size_t prev = (i + kFrames - 1) % kFrames;
        const Eigen::Isometry3d imu = s.poses[k].inverse() * s.poses[prev];
        t += 20'000'000;
        vio.addLaserPoints(t, s.laser[k]);
        auto r = vio.processFrame(t, s.images[k], i == 0 ? std::nullopt : std::optional(imu));
        if (r) {
            keyframes += r->keyframe;
            laser_depth += r->with_laser_depth;
        }
        ++i;
    }
    state.counters["keyframes_per_frame"] = static_cast<double>(keyframes) / static_cast<double>(i);
    state.counters["laser_depth_features"] = laser_depth / static_cast<double>(i);
}
BENCHMARK(BM_VioFrame)->Unit(benchmark::kMillisecond)->MinTime(3.0);

// A key-frame's depth map: the 100 frames' laser points (80k, about the 3 s the map keeps of a
// spinning laser's sweeps) seen from each pose in turn.
void BM_DepthMapBuild(benchmark::State& state) {
    const Sequence& s = sequence();
    DepthMap map;
    for (const auto& pts : s.laser) map.addPoints(0, pts);
    std::size_t i = 0;
    for (auto _ : state) {
        benchmark::DoNotOptimize(map.build(0, s.poses[i % kFrames]));
        ++i;
    }
    state.counters["points"] = static_cast<double>(map.storedPoints());
    state.counters["on_sphere_first_pose"] = static_cast<double>(map.build(0, s.poses[0]));
}
BENCHMARK(BM_DepthMapBuild)->Unit(benchmark::kMillisecond);

// One frame's motion estimation (eqs. 6-11): 250 features, 100 with depth, 5 % outliers, the
// IMU prior a little off the truth.
void BM_MotionEstimate(benchmark::State& state) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> xy(-0.9, 0.9), z(1.5, 8.0), bad(-0.2, 0.2);
    std::normal_distribution<double> noise(0.0, 0.7 / 290.0);
    Vector6d xi;
    xi << 0.01, -0.02, 0.005, 0.02, -0.01, 0.03;
    const Eigen::Isometry3d truth = expSE3(xi);
    std::vector<FeatureConstraint> fs;
    while (fs.size() < 250) {
        const double d = z(rng);
        const Eigen::Vector3d X_l(xy(rng) * d, xy(rng) * d, d);
        const Eigen::Vector3d X_c = truth * X_l;
        FeatureConstraint f;
        f.has_depth = fs.size() < 100;
        f.X_l = f.has_depth ? X_l : Eigen::Vector3d(X_l / X_l.z());
        f.xbar_c = X_c.head<2>() / X_c.z() + Eigen::Vector2d(noise(rng), noise(rng));
        if (fs.size() % 20 == 0) f.xbar_c += Eigen::Vector2d(bad(rng), bad(rng));
        fs.push_back(f);
    }
    ImuMotionPrior prior;
    prior.T_l_c = expSE3(xi + Vector6d::Constant(0.002));
    prior.information.diagonal() << Eigen::Vector3d::Constant(1e4), Eigen::Vector3d::Constant(1e3);
    const MotionEstimator estimator;
    int iterations = 0;
    for (auto _ : state) {
        const MotionResult m = estimator.estimate(fs, prior.T_l_c, prior, 290.0);
        iterations = m.iterations;
        benchmark::DoNotOptimize(m.T_l_c);
    }
    state.counters["iterations"] = iterations;
}
BENCHMARK(BM_MotionEstimate)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace handscan::vio
