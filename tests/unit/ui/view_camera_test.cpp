// The camera's matrices against hand-computed projections, and the coverage grid's gaps.
#include "handscan/ui/view_camera.hpp"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "handscan/ui/coverage_grid.hpp"

namespace handscan::ui {
namespace {

Eigen::Vector3f ndc(const Eigen::Matrix4f& m, const Eigen::Vector3f& p) {
    const Eigen::Vector4f c = m * p.homogeneous();
    return c.head<3>() / c.w();
}

TEST(ViewCamera, LookAtPutsTargetOnTheAxis) {
    const Eigen::Matrix4f v = lookAt({0, -10, 0}, {0, 0, 0}, {0, 0, 1});
    const Eigen::Vector4f t = v * Eigen::Vector4f(0, 0, 0, 1);
    EXPECT_NEAR(t.x(), 0, 1e-6);
    EXPECT_NEAR(t.y(), 0, 1e-6);
    EXPECT_NEAR(t.z(), -10, 1e-6);                              // in front of the eye: -z
    const Eigen::Vector4f r = v * Eigen::Vector4f(1, 0, 2, 1);  // world +x is screen right, +z up
    EXPECT_NEAR(r.x(), 1, 1e-6);
    EXPECT_NEAR(r.y(), 2, 1e-6);
}

TEST(ViewCamera, PerspectiveMapsTheFrustumEdges) {
    const float fov = 90.0f * 3.14159265f / 180.0f;
    const Eigen::Matrix4f p = perspective(fov, 2.0f, 0.1f, 100.0f);
    // At depth 5 with a 90 deg vertical fov the top edge is at y = 5, the right edge at x = 10.
    EXPECT_NEAR(ndc(p, {0, 5, -5}).y(), 1.0f, 1e-5);
    EXPECT_NEAR(ndc(p, {10, 0, -5}).x(), 1.0f, 1e-5);
    EXPECT_NEAR(ndc(p, {0, 0, -0.1f}).z(), -1.0f, 1e-4);
    EXPECT_NEAR(ndc(p, {0, 0, -100}).z(), 1.0f, 1e-4);
}

TEST(ViewCamera, TopDownIsNorthUpOrthographic) {
    ViewCamera cam;
    cam.mode = CameraMode::kTopDown;
    cam.target = {2, 3, 1};
    cam.top_down_half_height_m = 5;
    const Eigen::Matrix4f m = cam.projection(1.0f) * cam.view();
    const Eigen::Vector3f north = ndc(m, {2, 8, 0});
    EXPECT_NEAR(north.x(), 0, 1e-5);
    EXPECT_NEAR(north.y(), 1, 1e-5);
    const Eigen::Vector3f east = ndc(m, {7, 3, 1.5f});
    EXPECT_NEAR(east.x(), 1, 1e-5);
    EXPECT_NEAR(east.y(), 0, 1e-5);
}

TEST(ViewCamera, FollowSitsBehindTheDevice) {
    ViewCamera cam;
    cam.mode = CameraMode::kFollow;
    cam.pitch_rad = 0.0f;
    cam.distance_m = 4.0f;
    cam.setDevice({1, 1, 1}, 3.14159265f / 2);  // walking north
    const Eigen::Vector3f e = cam.eye();
    EXPECT_NEAR(e.x(), 1, 1e-5);
    EXPECT_NEAR(e.y(), -3, 1e-5);  // 4 m south of the device
    cam.zoom(0.5f);
    EXPECT_NEAR(cam.eye().y(), -1, 1e-5);
}

TEST(CoverageGrid, GapsStayEmpty) {
    CoverageGrid g(1.0f);
    std::vector<shm::DisplayPoint> pts;
    for (int x = 0; x < 10; ++x) {
        for (int y = 0; y < 4; ++y) {
            if (x == 5) continue;  // an unscanned strip
            for (int k = 0; k < (x < 5 ? 1 : 9); ++k)
                pts.push_back({x + 0.5f, y + 0.5f, 0.0f, 0, 0, 0, 0});
        }
    }
    g.add(pts);
    EXPECT_EQ(g.occupiedCells(), 36u);
    EXPECT_EQ(g.countAt(5.5f, 1.5f), 0u);
    EXPECT_EQ(g.countAt(7.5f, 1.5f), 9u);
    const CoverageImage img = g.render();
    ASSERT_EQ(img.width, 10);
    ASSERT_EQ(img.height, 4);
    EXPECT_FLOAT_EQ(img.min_x_m, 0.0f);
    EXPECT_FLOAT_EQ(img.max_y_m, 4.0f);
    const auto px = [&](int col, int row) {
        return &img.rgba[(static_cast<std::size_t>(row) * img.width + col) * 4];
    };
    EXPECT_LT(px(5, 0)[1], 10);           // gap: dark
    EXPECT_GT(px(7, 0)[1], px(2, 0)[1]);  // denser is brighter
    EXPECT_EQ(img.counts[static_cast<std::size_t>(3) * 10 + 7],
              9u);  // row 3 = southmost (y in [0,1))
}

TEST(CoverageGrid, CeilingDoesNotHideFloorGaps) {
    CoverageGrid g(1.0f);
    const std::vector<shm::DisplayPoint> pts = {{0.5f, 0.5f, 0.0f, 0, 0, 0, 0},
                                                {1.5f, 0.5f, 3.0f, 0, 0, 0, 0}};
    g.add(pts, 0.9f);
    EXPECT_EQ(g.countAt(0.5f, 0.5f), 1u);
    EXPECT_EQ(g.countAt(1.5f, 0.5f), 0u);  // only the ceiling was seen there: still a gap
}

}  // namespace
}  // namespace handscan::ui
