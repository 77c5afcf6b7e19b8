// CameraProjection against OpenCV: radtan must equal cv::projectPoints with (k1 k2 p1 p2), the
// equidistant model cv::fisheye::projectPoints, and projection must invert OpenCV's undistortion.
#include "handscan/colour/camera_projection.hpp"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>

#include "synthetic_scene.hpp"

namespace handscan::colour {
namespace {

Calibration camchain() {
    Calibration c;
    loadCamchain(std::string(HANDSCAN_SOURCE_DIR) + "/config/camchain.yaml", c);
    return c;
}

std::vector<cv::Point3d> randomPointsInView(int count, double half_angle_tan, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> xy(-half_angle_tan, half_angle_tan), z(0.3, 15.0);
    std::vector<cv::Point3d> pts;
    for (int i = 0; i < count; ++i) {
        const double d = z(rng);
        pts.emplace_back(xy(rng) * d, xy(rng) * d, d);
    }
    return pts;
}

TEST(CameraProjection, RadtanMatchesOpenCvProjectPoints) {
    const Calibration cal = camchain();
    ASSERT_EQ(cal.colour.distortion_model, "radtan");
    const CameraProjection proj(cal.colour);
    const auto pts = randomPointsInView(5000, 0.8, 1);
    std::vector<cv::Point2d> ref;
    cv::projectPoints(pts, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), test::cameraMatrix(cal.colour),
                      test::distCoeffs(cal.colour), ref);
    double worst = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto px = proj.project({pts[i].x, pts[i].y, pts[i].z});
        ASSERT_TRUE(px.has_value());
        worst = std::max(worst, (*px - Eigen::Vector2d(ref[i].x, ref[i].y)).norm());
    }
    EXPECT_LT(worst, 1e-8) << "pixels";
}

TEST(CameraProjection, RadtanInvertsOpenCvUndistortion) {
    const Calibration cal = camchain();
    const CameraProjection proj(cal.colour);
    std::vector<cv::Point2d> px;
    for (int v = 0; v < 1200; v += 37)
        for (int u = 0; u < 1600; u += 41) px.emplace_back(u + 0.25, v + 0.75);
    std::vector<cv::Point2d> norm;
    cv::undistortPoints(
        px, norm, test::cameraMatrix(cal.colour), test::distCoeffs(cal.colour), cv::noArray(),
        cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 60, 1e-14));
    double worst = 0;
    for (std::size_t i = 0; i < px.size(); ++i) {
        const auto back = proj.project(Eigen::Vector3d(norm[i].x, norm[i].y, 1.0) * 2.5);
        ASSERT_TRUE(back.has_value());
        worst = std::max(worst, (*back - Eigen::Vector2d(px[i].x, px[i].y)).norm());
    }
    EXPECT_LT(worst, 1e-6) << "pixels";
}

TEST(CameraProjection, EquidistantMatchesOpenCvFisheye) {
    const Calibration cal = camchain();
    ASSERT_EQ(cal.tracking.distortion_model, "equidistant");
    const CameraProjection proj(cal.tracking);
    const auto pts = randomPointsInView(5000, 1.5, 2);
    std::vector<cv::Point2d> ref;
    cv::fisheye::projectPoints(pts, ref, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0),
                               test::cameraMatrix(cal.tracking), test::distCoeffs(cal.tracking));
    double worst = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto px = proj.project({pts[i].x, pts[i].y, pts[i].z});
        ASSERT_TRUE(px.has_value());
        worst = std::max(worst, (*px - Eigen::Vector2d(ref[i].x, ref[i].y)).norm());
    }
    EXPECT_LT(worst, 1e-7) << "pixels";
}

TEST(CameraProjection, RejectsBehindAndFoldedPoints) {
    CameraIntrinsics cam;
    cam.intrinsics = {1000, 1000, 800, 600};
    cam.resolution = {1600, 1200};
    cam.distortion_model = "radtan";
    cam.distortion_coeffs = {-0.3, 0.0, 0.0, 0.0};  // 1 - 0.9 r^2 turns at r = 1.054
    const CameraProjection proj(cam);
    EXPECT_FALSE(proj.project({0, 0, -1}).has_value());
    EXPECT_FALSE(proj.project({0, 0, 0}).has_value());
    EXPECT_TRUE(proj.project({1.0, 0, 1}).has_value());
    // Far off-axis the polynomial folds back towards the centre: such points must not project.
    EXPECT_FALSE(proj.project({1.5, 0, 1}).has_value());
}

TEST(CameraProjection, RejectsUnsupportedModelsAtStartUp) {
    CameraIntrinsics cam;
    cam.intrinsics = {1000, 1000, 800, 600};
    cam.resolution = {1600, 1200};
    cam.distortion_model = "fov";
    cam.distortion_coeffs = {0.1};
    EXPECT_THROW(CameraProjection{cam}, std::invalid_argument);
    cam.distortion_model = "radtan";
    cam.distortion_coeffs = {0.1, 0.0};
    EXPECT_THROW(CameraProjection{cam}, std::invalid_argument);
    cam.distortion_coeffs = {0.1, 0.0, 0, 0};
    cam.camera_model = "omni";
    EXPECT_THROW(CameraProjection{cam}, std::invalid_argument);
}

}  // namespace
}  // namespace handscan::colour
