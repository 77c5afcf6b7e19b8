// FeatureTracker and PixelUndistorter: corners tracked across a known sub-pixel shift, spread
// over the 5 x 6 grid, and across a jump beyond the pyramid's reach from a prediction; none on a
// texture-less frame; on real EuRoC frames (a nearly still camera)
// the tracks survive and move together, and cam0 -> cam1 tracks of a stereo pair, undistorted with
// the camchain, satisfy the epipolar constraint of its extrinsics. The undistortion inverts
// colour::CameraProjection (independent code) for both camchain models, and its project() agrees
// with it.
#include "handscan/vio/feature_tracker.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <set>

#include "handscan/colour/camera_projection.hpp"
#include "handscan/vio/pixel_undistorter.hpp"
#include "synthetic_camera.hpp"

namespace handscan::vio {
namespace {

Calibration camchain(const std::string& path) {
    Calibration c;
    loadCamchain(path, c);
    return c;
}

cv::Mat roomImage() {
    const Calibration cal = camchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml");
    const test::SyntheticRoom room(3);
    std::mt19937 rng(1);
    return test::render(room, test::pixelRays(cal.tracking), 640, 512,
                        Eigen::Isometry3d::Identity(), 1.0, rng);
}

// Our tracking camera (equidistant) and EuRoC's (radtan): both camchain models.
std::vector<CameraIntrinsics> bothCamchainModels() {
    return {camchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml").tracking,
            camchain(std::string(HANDSCAN_TEST_DATA_DIR) + "/vio/euroc/camchain.yaml").tracking};
}

int occupiedCells(const FeatureTracker& tracker) {
    std::set<int> cells;
    for (const TrackedFeature& f : tracker.features()) cells.insert(tracker.cellOf(f.px));
    return static_cast<int>(cells.size());
}

TEST(PixelUndistorter, InvertsTheCamchainProjectionForBothModels) {
    for (const CameraIntrinsics& cam : bothCamchainModels()) {
        const PixelUndistorter undistorter(cam);
        const colour::CameraProjection projection(cam);
        double worst = 0.0;
        for (int v = 0; v < cam.resolution[1]; v += 23) {
            for (int u = 0; u < cam.resolution[0]; u += 29) {
                const Eigen::Vector2d m = undistorter.undistort(cv::Point2f(u, v));
                const auto px = projection.project(Eigen::Vector3d(m.x(), m.y(), 1.0) * 3.0);
                ASSERT_TRUE(px.has_value());
                worst = std::max(worst, (*px - Eigen::Vector2d(u, v)).norm());
            }
        }
        EXPECT_LT(worst, 0.01) << cam.distortion_model << ": pixels";
    }
}

TEST(PixelUndistorter, ProjectsAsTheCamchainProjectionForBothModels) {
    for (const CameraIntrinsics& cam : bothCamchainModels()) {
        const PixelUndistorter undistorter(cam);
        const colour::CameraProjection projection(cam);
        std::vector<Eigen::Vector3d> points;
        for (double y = -0.6; y <= 0.6; y += 0.1)
            for (double x = -0.7; x <= 0.7; x += 0.1) points.emplace_back(2.0 * x, 2.0 * y, 2.0);
        points.emplace_back(0.1, 0.2, -1.0);  // behind the camera
        std::vector<cv::Point2f> px;
        undistorter.project(points, px);
        ASSERT_EQ(px.size(), points.size());
        double worst = 0.0;
        for (std::size_t i = 0; i + 1 < points.size(); ++i) {
            const auto expected = projection.project(points[i]);
            ASSERT_TRUE(expected.has_value());
            worst = std::max(worst, (*expected - Eigen::Vector2d(px[i].x, px[i].y)).norm());
        }
        EXPECT_LT(worst, 0.01) << cam.distortion_model << ": pixels";
        EXPECT_EQ(px.back(), cv::Point2f(-1.0f, -1.0f));
    }
}

TEST(PixelUndistorter, RejectsModelsItCannotInvert) {
    CameraIntrinsics cam;
    cam.intrinsics = {300, 300, 320, 256};
    cam.resolution = {640, 512};
    cam.camera_model = "omni";
    EXPECT_THROW(PixelUndistorter{cam}, std::invalid_argument);
    cam.camera_model = "pinhole";
    cam.distortion_model = "fov";
    cam.distortion_coeffs = {0.1};
    EXPECT_THROW(PixelUndistorter{cam}, std::invalid_argument);
}

TEST(FeatureTracker, FollowsAKnownSubpixelShiftWithFeaturesOverTheWholeGrid) {
    const cv::Mat a = roomImage();
    cv::Mat b;
    const cv::Matx23d shift(1, 0, 2.3, 0, 1, -1.6);
    cv::warpAffine(a, b, shift, a.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
    FeatureTracker tracker;
    tracker.track(a);
    const std::vector<TrackedFeature> before = tracker.features();
    EXPECT_GE(before.size(), 270u);
    EXPECT_LE(before.size(), 300u);
    EXPECT_EQ(occupiedCells(tracker), 30);
    const TrackerFrameStats stats = tracker.track(b);
    EXPECT_GE(stats.tracked, 0.95 * before.size());
    std::vector<double> err;
    for (const TrackedFeature& f : tracker.features()) {
        if (f.age == 0) continue;
        for (const TrackedFeature& g : before) {
            if (g.id != f.id) continue;
            err.push_back(std::hypot(f.px.x - g.px.x - 2.3, f.px.y - g.px.y + 1.6));
        }
    }
    ASSERT_FALSE(err.empty());
    std::sort(err.begin(), err.end());
    EXPECT_LT(err[err.size() / 2], 0.1) << "median pixels";
    EXPECT_LT(err[err.size() * 9 / 10], 0.25) << "90th percentile pixels";
    EXPECT_LE(tracker.features().size(), 300u);
}

// A jump beyond the pyramid's reach (a fast turn between two frames) is found from the gyro's
// prediction, which is off by a pixel or two; without it most tracks are lost.
TEST(FeatureTracker, FollowsAJumpBeyondItsReachFromThePrediction) {
    const cv::Mat a = roomImage();
    cv::Mat b;
    const double dx = 85.0, dy = -40.0;
    const cv::Matx23d shift(1, 0, dx, 0, 1, dy);
    cv::warpAffine(a, b, shift, a.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
    FeatureTracker guided;
    guided.track(a);
    const std::vector<TrackedFeature> before = guided.features();
    std::vector<cv::Point2f> predicted;
    for (const TrackedFeature& f : before)
        predicted.emplace_back(f.px.x + static_cast<float>(dx) + 1.5f,
                               f.px.y + static_cast<float>(dy) - 1.0f);
    guided.track(b, &predicted);
    int visible = 0;  // still inside b, away from the border
    for (const TrackedFeature& f : before) {
        const double x = f.px.x + dx, y = f.px.y + dy;
        visible += x > 10 && y > 10 && x < 629 && y < 501;
    }
    std::vector<double> err;
    for (const TrackedFeature& f : guided.features()) {
        if (f.age == 0) continue;
        for (const TrackedFeature& g : before)
            if (g.id == f.id) err.push_back(std::hypot(f.px.x - g.px.x - dx, f.px.y - g.px.y - dy));
    }
    ASSERT_GT(visible, 150);
    EXPECT_GE(static_cast<double>(err.size()), 0.9 * visible);
    std::sort(err.begin(), err.end());
    ASSERT_FALSE(err.empty());
    EXPECT_LT(err[err.size() / 2], 0.1) << "median pixels";
    EXPECT_LT(err[err.size() * 9 / 10], 0.25) << "90th percentile pixels";

    FeatureTracker blind;  // the same jump searched from the last position
    blind.track(a);
    const TrackerFrameStats stats = blind.track(b);
    int right = 0;
    for (const TrackedFeature& f : blind.features()) {
        if (f.age == 0) continue;
        for (const TrackedFeature& g : before)
            right += g.id == f.id && std::hypot(f.px.x - g.px.x - dx, f.px.y - g.px.y - dy) < 0.5;
    }
    EXPECT_LT(right, visible / 2) << stats.tracked << " tracked";
}

TEST(FeatureTracker, TexturelessFrameGivesNoFeatures) {
    cv::Mat flat(512, 640, CV_8UC1);
    cv::randn(flat, 128, 2.0);  // sensor noise on a blank wall
    FeatureTracker tracker;
    tracker.track(flat);
    EXPECT_EQ(tracker.features().size(), 0u);
    cv::Mat dark(512, 640, CV_8UC1);
    cv::randn(dark, 3, 1.0);
    tracker.track(dark);
    EXPECT_EQ(tracker.features().size(), 0u);
}

TEST(FeatureTracker, RefillsCellsWhoseFeaturesWereDropped) {
    const cv::Mat a = roomImage();
    FeatureTracker tracker;
    tracker.track(a);
    std::vector<std::uint64_t> cell0;
    for (const TrackedFeature& f : tracker.features())
        if (tracker.cellOf(f.px) == 0) cell0.push_back(f.id);
    ASSERT_FALSE(cell0.empty());
    tracker.drop(cell0);
    const TrackerFrameStats stats = tracker.track(a);
    EXPECT_GE(stats.detected, static_cast<int>(cell0.size()) - 2);
    int in_cell0 = 0;
    for (const TrackedFeature& f : tracker.features()) in_cell0 += tracker.cellOf(f.px) == 0;
    EXPECT_GE(in_cell0, static_cast<int>(cell0.size()) - 2);
}

// Real frames: EuRoC V1_01 cam0/cam1 (see ../shared/data/camera/euroc-v101-still/SOURCE.txt).
std::vector<std::filesystem::path> eurocFrames(const std::string& cam) {
    const std::filesystem::path dir =
        std::filesystem::path(HANDSCAN_SHARED_DATA_DIR) / "camera/euroc-v101-still" / cam;
    std::vector<std::filesystem::path> files;
    if (!std::filesystem::exists(dir)) return files;
    for (const auto& e : std::filesystem::directory_iterator(dir))
        if (e.path().extension() == ".png") files.push_back(e.path());
    std::sort(files.begin(), files.end());
    return files;
}

TEST(FeatureTrackerReal, EurocTracksSurviveAndMoveTogetherOnANearlyStillCamera) {
    const auto files = eurocFrames("cam0");
    if (files.size() < 10) GTEST_SKIP() << "EuRoC frames not found under " HANDSCAN_SHARED_DATA_DIR;
    FeatureTracker tracker;
    tracker.track(cv::imread(files.front().string(), cv::IMREAD_GRAYSCALE));
    const std::vector<TrackedFeature> first = tracker.features();
    EXPECT_GE(first.size(), 220u);
    EXPECT_GE(occupiedCells(tracker), 27) << "of 30 cells";
    // Displacement of every surviving first-frame feature after frame i.
    auto displacements = [&](std::vector<cv::Point2f>& d) {
        d.clear();
        for (const TrackedFeature& f : tracker.features())
            for (const TrackedFeature& g : first)
                if (g.id == f.id) d.push_back(f.px - g.px);
    };
    auto median = [](std::vector<double> v) {
        std::sort(v.begin(), v.end());
        return v[v.size() / 2];
    };
    std::vector<cv::Point2f> d;
    for (std::size_t i = 1; i < files.size(); ++i) {
        tracker.track(cv::imread(files[i].string(), cv::IMREAD_GRAYSCALE));
        displacements(d);
        ASSERT_GE(d.size(), 0.9 * first.size()) << "survivors after frame " << i;
        // The MAV stands on the ground but its camera shifts by up to 0.4 px (x) from frame 6
        // on: every track must follow the common shift, none wander on its own.
        std::vector<double> dx, dy;
        for (const cv::Point2f& p : d) {
            dx.push_back(p.x);
            dy.push_back(p.y);
        }
        const cv::Point2f common(static_cast<float>(median(dx)), static_cast<float>(median(dy)));
        EXPECT_LT(std::hypot(common.x, common.y), 0.6) << "pixels after frame " << i;
        std::vector<double> own;
        for (const cv::Point2f& p : d) own.push_back(cv::norm(p - common));
        std::sort(own.begin(), own.end());
        EXPECT_LT(own[own.size() / 2], 0.1) << "median pixels after frame " << i;
        EXPECT_LT(own[own.size() * 9 / 10], 0.25) << "90th percentile pixels after frame " << i;
    }
}

TEST(FeatureTrackerReal, EurocStereoTracksSatisfyTheCamchainEpipolarGeometry) {
    const auto left = eurocFrames("cam0");
    const auto right = eurocFrames("cam1");
    if (left.empty() || right.empty()) GTEST_SKIP() << "EuRoC frames not found";
    const Calibration cal =
        camchain(std::string(HANDSCAN_TEST_DATA_DIR) + "/vio/euroc/camchain.yaml");
    // 11 cm of baseline: up to 50 px of disparity, a real motion for KLT.
    FeatureTrackerConfig config;
    config.klt_pyramid_levels = 4;
    FeatureTracker tracker(config);
    tracker.track(cv::imread(left.front().string(), cv::IMREAD_GRAYSCALE));
    const std::vector<TrackedFeature> first = tracker.features();
    // cam1 is exposed differently (mean grey 130 vs 145) and KLT assumes constant brightness:
    // match its mean and contrast to cam0 first.
    const cv::Mat l0 = cv::imread(left.front().string(), cv::IMREAD_GRAYSCALE);
    cv::Mat r0 = cv::imread(right.front().string(), cv::IMREAD_GRAYSCALE);
    cv::Scalar ml, sl, mr, sr;
    cv::meanStdDev(l0, ml, sl);
    cv::meanStdDev(r0, mr, sr);
    r0.convertTo(r0, CV_8U, sl[0] / sr[0], ml[0] - mr[0] * sl[0] / sr[0]);
    tracker.track(r0);
    const PixelUndistorter u0(cal.tracking), u1(cal.colour);  // cam1 of the camchain
    const Eigen::Matrix3d R = cal.T_colour_tracking.linear();
    const Eigen::Vector3d t = cal.T_colour_tracking.translation();
    const Eigen::Matrix3d E = skew(t) * R;  // x1^T E x0 = 0
    std::vector<double> err;
    for (const TrackedFeature& f : tracker.features()) {
        for (const TrackedFeature& g : first) {
            if (g.id != f.id) continue;
            const Eigen::Vector2d m0 = u0.undistort(g.px), m1 = u1.undistort(f.px);
            const Eigen::Vector3d x0(m0.x(), m0.y(), 1), x1(m1.x(), m1.y(), 1);
            const Eigen::Vector3d line = E * x0;
            err.push_back(std::abs(x1.dot(line)) / line.head<2>().norm() * u1.focalLength());
        }
    }
    ASSERT_GE(err.size(), 150u);
    std::sort(err.begin(), err.end());
    EXPECT_LT(err[err.size() / 2], 0.5) << "median pixels from the epipolar line";
    EXPECT_LT(err[err.size() * 8 / 10], 1.5) << "80th percentile pixels";
}

}  // namespace
}  // namespace handscan::vio
