// DepthMap (section 5.3) on synthetic laser points: depth on a tilted plane is interpolated to
// the plane's true depth, features outside the laser's coverage get none, a box in front of a
// wall gives neither surface's depth across its silhouette (the spread check), nearer points hide
// farther ones in the same direction, and old points leave the map.
#include "handscan/vio/depth_map.hpp"

#include <gtest/gtest.h>

#include <random>

#include "handscan/core/se3.hpp"

namespace handscan::vio {
namespace {

constexpr TimeNs kSec = 1'000'000'000;

// Points on the plane n.X = d (camera at the origin looking along +z), on random rays within
// `half_tan` of the axis.
std::vector<Eigen::Vector3d> planePoints(const Eigen::Vector3d& n, double d, int count,
                                         double half_tan, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-half_tan, half_tan);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < count; ++i) {
        const Eigen::Vector3d ray(u(rng), u(rng), 1.0);
        pts.push_back(ray * (d / n.dot(ray)));
    }
    return pts;
}

// Depths of 300 random features within `half_tan` of the axis against the plane n.X = d seen
// from T_world_cam: how many got one, and the worst error.
struct DepthCheck {
    int found = 0;
    double worst = 0.0;
};
DepthCheck checkDepths(const DepthMap& map, const Eigen::Isometry3d& T_world_cam,
                       const Eigen::Vector3d& n, double d, double half_tan, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-half_tan, half_tan);
    DepthCheck c;
    for (int i = 0; i < 300; ++i) {
        const Eigen::Vector2d xbar(u(rng), u(rng));
        const auto z = map.depthOf(xbar);
        if (!z) continue;
        ++c.found;
        // True depth: the ray from the camera meets the plane.
        const Eigen::Vector3d o = T_world_cam.translation();
        const Eigen::Vector3d r = T_world_cam.linear() * Eigen::Vector3d(xbar.x(), xbar.y(), 1);
        c.worst = std::max(c.worst, std::abs(*z - (d - n.dot(o)) / n.dot(r)));
    }
    return c;
}

TEST(DepthMap, InterpolatesDepthOnATiltedPlane) {
    const Eigen::Vector3d n = Eigen::Vector3d(0.3, -0.2, 1.0).normalized();
    const double d = 3.0;
    DepthMap map;
    map.addPoints(0, planePoints(n, d, 20000, 0.6, 1));
    // Seen from a camera 0.5 m to the side and turned 10 degrees: the map is built in its frame.
    Eigen::Isometry3d T_world_cam = Eigen::Isometry3d::Identity();
    T_world_cam.translation() = Eigen::Vector3d(0.5, 0.0, 0.0);
    T_world_cam.linear() = expSO3(Eigen::Vector3d(0.0, -0.17, 0.0));
    ASSERT_GT(map.build(0, T_world_cam), 5000u);
    const DepthCheck c = checkDepths(map, T_world_cam, n, d, 0.3, 2);
    EXPECT_GT(c.found, 290);
    EXPECT_LT(c.worst, 1e-4) << "m (points on the plane, kept in float)";
}

// What a spinning 2D laser leaves in the camera's view: scan lines (here of constant azimuth)
// 0.03 rad apart, a point every 0.004 rad along each, on the tilted plane n.X = d. The nearest
// three points to a feature are mostly on one line and span no plane.
std::vector<Eigen::Vector3d> scanLinePoints(const Eigen::Vector3d& n, double d) {
    std::vector<Eigen::Vector3d> pts;
    for (double az = -0.5; az <= 0.5; az += 0.03) {
        for (double el = -0.5; el <= 0.5; el += 0.004) {
            const Eigen::Vector3d ray(std::sin(az) * std::cos(el), std::sin(el),
                                      std::cos(az) * std::cos(el));
            pts.push_back(ray * (d / n.dot(ray)));
        }
    }
    return pts;
}

TEST(DepthMap, InterpolatesBetweenScanLines) {
    const Eigen::Vector3d n = Eigen::Vector3d(0.2, 0.3, 1.0).normalized();
    const double d = 3.0;
    DepthMap map;
    map.addPoints(0, scanLinePoints(n, d));
    ASSERT_GT(map.build(0, Eigen::Isometry3d::Identity()), 4000u);
    const DepthCheck c = checkDepths(map, Eigen::Isometry3d::Identity(), n, d, 0.4, 8);
    // Every feature is within max_neighbour_angle_rad of a line: all get depth (the three
    // nearest points alone gave 210 of 300, up to 0.28 m off).
    EXPECT_GT(c.found, 290);
    EXPECT_LT(c.worst, 1e-3) << "m";
}

TEST(DepthMap, NoDepthWithoutLaserCoverage) {
    DepthMap map;
    map.addPoints(0, planePoints(Eigen::Vector3d::UnitZ(), 4.0, 5000, 0.2, 3));
    map.build(0, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(map.depthOf({0.05, -0.1}).has_value());
    EXPECT_FALSE(map.depthOf({0.5, 0.0}).has_value()) << "beyond the scanned patch";
    DepthMap empty;
    empty.build(0, Eigen::Isometry3d::Identity());
    EXPECT_FALSE(empty.depthOf({0.0, 0.0}).has_value());
}

TEST(DepthMap, SpreadCheckRejectsPatchesAcrossTwoObjects) {
    // A wall at 5 m and a box face at 2 m covering x/z in [-0.1, 0.1].
    std::vector<Eigen::Vector3d> pts;
    for (const Eigen::Vector3d& p : planePoints(Eigen::Vector3d::UnitZ(), 5.0, 30000, 0.3, 4)) {
        if (std::abs(p.x() / p.z()) > 0.1) pts.push_back(p);
    }
    for (const Eigen::Vector3d& p : planePoints(Eigen::Vector3d::UnitZ(), 2.0, 30000, 0.3, 5)) {
        if (std::abs(p.x() / p.z()) <= 0.1) pts.push_back(p);
    }
    DepthMap map;
    map.addPoints(0, pts);
    map.build(0, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(map.depthOf({0.0, 0.0}).has_value());
    EXPECT_NEAR(*map.depthOf({0.0, 0.0}), 2.0, 1e-4);
    EXPECT_NEAR(*map.depthOf({0.2, 0.0}), 5.0, 1e-4);
    // On the silhouette the three nearest points mix box and wall: no depth rather than a
    // depth in between.
    int mixed = 0, accepted = 0;
    for (double y = -0.2; y <= 0.2; y += 0.01) {
        const auto z = map.depthOf({0.1, y});
        if (!z) continue;
        ++accepted;
        if (std::abs(*z - 2.0) > 0.01 && std::abs(*z - 5.0) > 0.01) ++mixed;
    }
    EXPECT_EQ(mixed, 0);
    EXPECT_LT(accepted, 41);
}

TEST(DepthMap, NearerPointsHideFartherOnesAndOldPointsLeave) {
    DepthMap map;
    map.addPoints(0, planePoints(Eigen::Vector3d::UnitZ(), 6.0, 20000, 0.3, 6));
    map.addPoints(2 * kSec, planePoints(Eigen::Vector3d::UnitZ(), 3.0, 20000, 0.3, 7));
    map.build(2 * kSec, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(map.depthOf({0.0, 0.0}).has_value());
    EXPECT_NEAR(*map.depthOf({0.0, 0.0}), 3.0, 1e-6) << "the nearer surface in every cell";
    EXPECT_EQ(map.storedPoints(), 40000u);
    map.build(4 * kSec, Eigen::Isometry3d::Identity());  // keep_s = 3: the first batch leaves
    EXPECT_EQ(map.storedPoints(), 20000u);
    map.build(6 * kSec, Eigen::Isometry3d::Identity());
    EXPECT_EQ(map.storedPoints(), 0u);
    EXPECT_FALSE(map.depthOf({0.0, 0.0}).has_value());
}

}  // namespace
}  // namespace handscan::vio
