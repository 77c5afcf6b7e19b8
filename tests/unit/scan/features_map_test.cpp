#include <gtest/gtest.h>

#include <cmath>

#include "handscan/scan/feature_extractor.hpp"
#include "handscan/scan/voxel_map.hpp"
#include "spin_sim.hpp"

namespace handscan::scan {
namespace {

using testing::deviceGeometry;

Sweep roomSweep(const testing::Scene& scene, const Eigen::Isometry3d& T, double noise = 0.005) {
    return testing::staticSweep(scene, T, 7, noise, SweepBoundary::kHalfRevolution);
}

// Distance to the nearest vertical (y-parallel) or other box edge of the scene's boxes.
double distanceToBoxEdge(const testing::Scene& scene, const Eigen::Vector3d& p) {
    double best = 1e9;
    for (const auto& b : scene.boxes) {
        for (int axis = 0; axis < 3; ++axis) {
            const int u = (axis + 1) % 3;
            const int v = (axis + 2) % 3;
            for (double cu : {b.lo[u], b.hi[u]}) {
                for (double cv : {b.lo[v], b.hi[v]}) {
                    const double du = p[u] - cu;
                    const double dv = p[v] - cv;
                    const double along =
                        std::max({b.lo[axis] - p[axis], 0.0, p[axis] - b.hi[axis]});
                    best = std::min(best, std::sqrt(du * du + dv * dv + along * along));
                }
            }
        }
    }
    return best;
}

TEST(Features, SmoothnessIsZeroOnAPlaneAndLargeAtACorner) {
    // One synthetic line: 21 steps on a wall, then 20 on a perpendicular wall (a 90 deg corner).
    Sweep s;
    const double inc = 0.25 * M_PI / 180.0;
    for (int i = 0; i < 41; ++i) {
        // The wall x = 2 up to the corner (2, 2), then the wall y = 2, 5 cm between points.
        SweepPoint p;
        p.p_start = i <= 20 ? Eigen::Vector3d(2.0, 2.0 - 0.05 * (20 - i), 0.0)
                            : Eigen::Vector3d(2.0 - 0.05 * (i - 20), 2.0, 0.0);
        p.range_m = static_cast<float>(p.p_start.norm());
        p.step = static_cast<std::uint16_t>(i);
        s.points.push_back(p);
    }
    s.lines.push_back({0, s.points.size(), inc});
    const auto c = lineSmoothness(s, s.lines[0], 5);
    EXPECT_TRUE(std::isnan(c[0]));
    EXPECT_TRUE(std::isnan(c[40]));
    EXPECT_LT(c[10], 1e-9);       // on the first wall
    EXPECT_LT(c[30], 1e-9);       // on the second
    EXPECT_GT(c[20], 1.5 * inc);  // at the corner
    EXPECT_GT(c[20], 100 * c[10] + 1e-6);
}

TEST(Features, EdgesOnBoxEdgesPlanarsOnSurfaces) {
    const auto scene = testing::officeRoom();
    const auto T = testing::pose(0.0, 0.3, 0.0, 0.3, 0.0, 0.5);
    const Sweep s = roomSweep(scene, T);
    const FeatureCloud f = extractFeatures(s, FeatureConfig{});
    ASSERT_GT(f.edges.size(), 40U);
    ASSERT_GT(f.planars.size(), 1000U);
    int on_edges = 0;
    for (const auto& p : f.edges) on_edges += distanceToBoxEdge(scene, T * p) < 0.1 ? 1 : 0;
    EXPECT_GT(on_edges, static_cast<int>(0.8 * f.edges.size()))
        << on_edges << " of " << f.edges.size();
    int off_edges = 0;
    for (const auto& p : f.planars) off_edges += distanceToBoxEdge(scene, T * p) > 0.05 ? 1 : 0;
    EXPECT_GT(off_edges, static_cast<int>(0.97 * f.planars.size()));
    // Balanced across sub-regions: no region gives more than its quota per line.
    FeatureConfig one;
    one.regions_per_line = 1;
    one.max_edges_per_region = 1;
    EXPECT_LE(extractFeatures(s, one).edges.size(), s.lines.size());
}

TEST(Features, OccludedBoundaryAndGrazingPointsAreRejected) {
    // A thin post 1 m in front of a wall 4 m away: the wall points right next to the post's
    // shadow look like edges (Figure 8, B) but must not be picked.
    testing::Scene scene;
    scene.boxes.push_back({{-6, -3, -6}, {6, 3, 4}, true});
    scene.boxes.push_back({{-0.05, -3, 0.95}, {0.05, 3, 1.05}, false});
    const Sweep s = roomSweep(scene, Eigen::Isometry3d::Identity(), 0.0);
    FeatureConfig cfg;
    const FeatureCloud f = extractFeatures(s, cfg);
    int near_shadow = 0;
    for (const auto& p : f.edges) {
        // Wall points (z ~ 4) in the post's shadow boundary band (|x| < 0.6).
        if (p.z() > 3.5 && std::abs(p.x()) < 0.6 && std::abs(p.y()) < 2.0) ++near_shadow;
    }
    EXPECT_EQ(near_shadow, 0);
    // The post's own edges (Figure 8, point A) are found.
    int post_edges = 0;
    for (const auto& p : f.edges) {
        if (std::abs(p.z() - 0.95) < 0.1 && std::abs(std::abs(p.x()) - 0.05) < 0.05) ++post_edges;
    }
    EXPECT_GT(post_edges, 4);
}

TEST(VoxelMap, ConstantDensityAndExtractionNearFeatures) {
    VoxelMapConfig cfg;
    VoxelMap map(cfg);
    map.recenter(Eigen::Vector3d::Zero());
    std::vector<Eigen::Vector3d> wall;
    for (double x = -5; x < 5; x += 0.02) {
        for (double y = -1.5; y < 1.5; y += 0.02) wall.emplace_back(x, y, 3.0);
    }
    const std::size_t kept = map.insert(FeatureKind::kPlanar, wall);
    // 10 m x 3 m at one point per 0.2 m leaf: 50 x 16 leaves (y from -1.5 spans 16 leaf rows).
    EXPECT_EQ(kept, 50U * 16U);
    EXPECT_EQ(map.insert(FeatureKind::kPlanar, wall), 0U);  // already dense: nothing added
    EXPECT_EQ(map.stats().points[1], kept);

    // Features near one corner of the wall select only the fine voxels there.
    const LocalMap local = map.extract({}, {Eigen::Vector3d(-4.5, -1.0, 3.0)});
    EXPECT_GT(local.size(FeatureKind::kPlanar), 0U);
    EXPECT_LT(local.size(FeatureKind::kPlanar), kept / 5);
    Eigen::Vector3d nb[5];
    double d2[5];
    EXPECT_EQ(local.nearest(FeatureKind::kPlanar, Eigen::Vector3d(-4.5, -1.0, 3.1), 5, nb, d2), 5);
    EXPECT_LT(d2[4], 0.2 * 0.2 * 2);
    EXPECT_EQ(local.nearest(FeatureKind::kPlanar, Eigen::Vector3d(3.0, 0.0, 3.0), 5, nb, d2), 0);
}

TEST(VoxelMap, FeaturesAcrossACoarseBoundaryFindTheirNeighbours) {
    VoxelMap map;
    map.recenter(Eigen::Vector3d::Zero());
    std::vector<Eigen::Vector3d> pts;
    for (double x = 9.0; x < 11.0; x += 0.05) pts.emplace_back(x, 0.5, 0.5);
    map.insert(FeatureKind::kEdge, pts);
    const LocalMap local = map.extract({Eigen::Vector3d(9.98, 0.5, 0.5)}, {});
    Eigen::Vector3d nb[5];
    double d2[5];
    ASSERT_EQ(local.nearest(FeatureKind::kEdge, Eigen::Vector3d(9.98, 0.5, 0.5), 5, nb, d2), 5);
    int beyond = 0;
    for (const auto& p : nb) beyond += p.x() >= 10.0 ? 1 : 0;
    EXPECT_GE(beyond, 2);  // the neighbours over the coarse boundary are in this voxel's tree
}

TEST(VoxelMap, RollsWithTheSensorAndStaysBounded) {
    VoxelMapConfig cfg;
    cfg.window_voxels = {5, 5, 3};
    cfg.roll_margin_voxels = 1;
    VoxelMap map(cfg);
    std::size_t peak = 0;
    // Drive 500 m along x, dropping a wall of points every metre.
    for (int i = 0; i < 500; ++i) {
        const Eigen::Vector3d sensor(i, 0.0, 0.0);
        map.recenter(sensor);
        std::vector<Eigen::Vector3d> wall;
        for (double y = -2; y < 2; y += 0.1) wall.emplace_back(i + 0.5, y, 2.0);
        map.insert(FeatureKind::kPlanar, wall);
        peak = std::max(peak, map.stats().points[1]);
    }
    const VoxelMapStats st = map.stats();
    EXPECT_GT(st.truncated_points, 0U);
    // The window spans 50 m along x: at most ~50 walls of 20 leaves remain.
    EXPECT_LE(peak, 50U * 20U);
    EXPECT_LE(st.points[1], map.capacityBound());
    const auto pts = map.points(FeatureKind::kPlanar);
    for (const auto& p : pts) EXPECT_GT(p.x(), 499 - 50);
    // Far behind the sensor nothing can be inserted.
    EXPECT_EQ(map.insert(FeatureKind::kPlanar, {Eigen::Vector3d(0, 0, 0)}), 0U);
    EXPECT_EQ(map.stats().rejected_outside, 1U);
}

}  // namespace
}  // namespace handscan::scan
