// Tap-to-place: window pixels through the view camera onto the map (top-down and perspective,
// checked by projecting the result back as the GPU does), the height from the earlier path, and
// a tap + drag as the continue command's start pose.
#include "handscan/ui/start_placement.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "handscan/ui/view_camera.hpp"

namespace handscan::ui {
namespace {

// The window pixel where map point p is drawn in view (vx, vy, vw, vh).
Eigen::Vector2f pixelOf(const Eigen::Matrix4f& vp, float vx, float vy, float vw, float vh,
                        const Eigen::Vector3f& p) {
    const Eigen::Vector4f c = vp * p.homogeneous();
    const Eigen::Vector3f n = c.head<3>() / c.w();
    return {vx + (n.x() + 1.0f) / 2.0f * vw, vy + (1.0f - n.y()) / 2.0f * vh};
}

TEST(StartPlacement, TopDownTapLandsWhereTheMapPointIsDrawn) {
    ViewCamera cam;
    cam.mode = CameraMode::kTopDown;
    cam.target = {12.0f, -3.0f, 1.2f};
    cam.top_down_half_height_m = 6.0f;
    const float vx = 0, vy = 110, vw = 1020, vh = 690;
    const Eigen::Matrix4f vp = cam.projection(vw / vh) * cam.view();
    // The view's centre is the camera target; north (+y) is up on the screen, east right.
    auto centre = screenToMap(vp, vx, vy, vw, vh, vx + vw / 2, vy + vh / 2, 1.2f);
    ASSERT_TRUE(centre);
    EXPECT_NEAR(centre->x(), 12.0f, 1e-3);
    EXPECT_NEAR(centre->y(), -3.0f, 1e-3);
    EXPECT_NEAR(centre->z(), 1.2f, 1e-4);
    // Half a view height up the screen is 6 m north; the right edge is 6 * aspect m east.
    auto up = screenToMap(vp, vx, vy, vw, vh, vx + vw / 2, vy, 0.0f);
    ASSERT_TRUE(up);
    EXPECT_NEAR(up->y(), 3.0f, 1e-3);
    auto right = screenToMap(vp, vx, vy, vw, vh, vx + vw, vy + vh / 2, 0.0f);
    ASSERT_TRUE(right);
    EXPECT_NEAR(right->x(), 12.0f + 6.0f * vw / vh, 2e-3);
    // Any pixel: the map point found is drawn at that pixel.
    const Eigen::Vector2f px(333.0f, 512.0f);
    auto p = screenToMap(vp, vx, vy, vw, vh, px.x(), px.y(), 0.5f);
    ASSERT_TRUE(p);
    EXPECT_LT((pixelOf(vp, vx, vy, vw, vh, *p) - px).norm(), 0.05f);
}

TEST(StartPlacement, PerspectiveTapMeetsTheFloorPlaneBelowTheEye) {
    ViewCamera cam;
    cam.mode = CameraMode::kFree;
    cam.target = {2.0f, 1.0f, 0.0f};
    cam.distance_m = 10.0f;
    cam.pitch_rad = 0.3f;  // 17 deg down, the top of the 60 deg view above the horizon
    cam.yaw_rad = 0.4f;
    const float vx = 0, vy = 0, vw = 800, vh = 600;
    const Eigen::Matrix4f vp = cam.projection(vw / vh) * cam.view();
    auto p = screenToMap(vp, vx, vy, vw, vh, 250.0f, 420.0f, 0.0f);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->z(), 0.0f, 1e-4);
    EXPECT_LT((pixelOf(vp, vx, vy, vw, vh, *p) - Eigen::Vector2f(250.0f, 420.0f)).norm(), 0.05f);
    // Above the horizon the ray never meets the floor.
    EXPECT_FALSE(screenToMap(vp, vx, vy, vw, vh, 400.0f, 0.0f, 0.0f));
}

TEST(StartPlacement, TapAndDragGiveTheStartPose) {
    const std::vector<shm::TrackPoint> path = {
        {0, 0.0f, 0.0f, 1.3f, 0}, {0, 5.0f, 0.0f, 1.35f, 0}, {0, 5.0f, 4.0f, 4.2f, 0}};
    EXPECT_FALSE(pathHeightNear({}, 0, 0));
    EXPECT_FLOAT_EQ(*pathHeightNear(path, 4.2f, 0.5f), 1.35f);  // the ground floor's path
    EXPECT_FLOAT_EQ(*pathHeightNear(path, 4.6f, 3.1f), 4.2f);   // upstairs

    StartPlacement s;
    EXPECT_FALSE(s.placed());
    s.press({4.0f, 1.0f, *pathHeightNear(path, 4.0f, 1.0f)});
    s.drag({4.05f, 1.1f, 0.0f});  // a wobble: no heading yet
    EXPECT_FLOAT_EQ(s.headingRad(), 0.0f);
    s.drag({3.0f, 2.0f, 0.0f});  // north-west
    ASSERT_TRUE(s.placed());
    EXPECT_NEAR(s.headingRad(), 3.0f * M_PI / 4.0f, 1e-6);
    const Eigen::Isometry3d T = s.pose();
    EXPECT_TRUE(T.translation().isApprox(Eigen::Vector3d(4.0, 1.0, 1.35), 1e-6));
    const Eigen::Vector3d x = T.linear().col(0);
    EXPECT_NEAR(std::atan2(x.y(), x.x()), 3.0 * M_PI / 4.0, 1e-6);
    EXPECT_NEAR(T.linear()(2, 2), 1.0, 1e-12);  // level
    const double h = 3.0 * M_PI / 8.0;          // half the heading
    char want[160];
    std::snprintf(want, sizeof(want), "4.000,1.000,1.350,0.000000,0.000000,%.6f,%.6f", std::sin(h),
                  std::cos(h));
    EXPECT_EQ(s.poseText(), want);
}

}  // namespace
}  // namespace handscan::ui
