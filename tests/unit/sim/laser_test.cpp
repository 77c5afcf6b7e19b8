// The simulated UTM-30LX-EW: per-step geometry and time, range noise growing with distance,
// dropouts on black and glancing surfaces, intensity from reflectivity.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "handscan/sim/laser_model.hpp"
#include "handscan/sim/mesh_builder.hpp"

namespace handscan::sim {
namespace {

// A square room [-h, h]^2 with walls of the given reflectivity; the laser at the centre.
World room(double h, float reflectivity) {
    World w;
    MeshBuilder b(w);
    const auto m =
        b.addMaterial(Material{"wall", reflectivity, {0.5f, 0.5f, 0.5f}, TextureId::kPlain, 1.0f});
    b.addWall({-h, -h}, {h, -h}, 0.1, -2, 4, {}, m);
    b.addWall({h, -h}, {h, h}, 0.1, -2, 4, {}, m);
    b.addWall({h, h}, {-h, h}, 0.1, -2, 4, {}, m);
    b.addWall({-h, h}, {-h, -h}, 0.1, -2, 4, {}, m);
    return w;
}

const auto kStill = [](double) { return Eigen::Isometry3d::Identity(); };

TEST(LaserModelTest, RangesFollowGeometryAndNoiseGrowsWithDistance) {
    for (double h : {2.05, 10.05}) {
        const World w = room(h, 0.8f);
        Raycaster rc(w);
        LaserConfig cfg;
        LaserModel laser(cfg, rc, Rng(3, "laser"));
        const double inner = h - 0.05;
        double sum = 0, sum2 = 0;
        int n = 0;
        for (int s = 0; s < 100; ++s) {
            const LaserScanTruth scan = laser.scan(0.025 * s, kStill);
            ASSERT_EQ(scan.ranges_mm.size(), 1081u);
            // Front step 540 looks along +x at the wall.
            EXPECT_NEAR(scan.true_range_m[540], inner, 1e-4);
            // Step 540 + 180 is +45 deg: the corner direction within the square.
            EXPECT_NEAR(scan.true_range_m[720], inner * std::sqrt(2.0), 1e-3);
            for (int k = 500; k < 580; ++k) {
                const double err = scan.ranges_mm[k] * 1e-3 - scan.true_range_m[k];
                sum += err;
                sum2 += err * err;
                ++n;
            }
        }
        const double sigma = std::sqrt(sum2 / n - (sum / n) * (sum / n));
        const double expect = cfg.noise_base_m + cfg.noise_per_m * inner;
        EXPECT_NEAR(sigma / expect, 1.0, 0.1) << "at " << inner << " m";
        EXPECT_NEAR(sum / n, 0.0, 0.003);
    }
}

TEST(LaserModelTest, BlackWallsDropOutAndBrightWallsReturnStrongly) {
    LaserConfig cfg;
    const World white = room(8.05, 0.9f), black = room(8.05, 0.03f);
    Raycaster rw(white), rb(black);
    LaserModel lw(cfg, rw, Rng(1, "l")), lb(cfg, rb, Rng(1, "l"));
    const LaserScanTruth sw = lw.scan(0, kStill), sb = lb.scan(0, kStill);
    int white_errors = 0, black_errors = 0;
    for (int k = 400; k <= 680; ++k) {
        white_errors += sw.ranges_mm[k] < cfg.dmin_mm;
        black_errors += sb.ranges_mm[k] < cfg.dmin_mm;
        if (sb.ranges_mm[k] < cfg.dmin_mm) {
            EXPECT_EQ(sb.ranges_mm[k], cfg.code_weak);
        }
    }
    EXPECT_EQ(white_errors, 0);
    EXPECT_GT(black_errors, 270);  // black plastic is not seen at 8 m
    EXPECT_GT(sw.intensities[540], 1000u);
}

TEST(LaserModelTest, GlancingIncidenceDropsOutAndNothingInRangeIsNoEcho) {
    // One long wall along x at y = 1: beams near +-90 deg hit it head on, beams towards +x graze
    // it.
    World w;
    MeshBuilder b(w);
    const auto m =
        b.addMaterial(Material{"wall", 0.8f, {0.5f, 0.5f, 0.5f}, TextureId::kPlain, 1.0f});
    b.addQuad({-100, 1, -2}, {100, 1, -2}, {100, 1, 2}, {-100, 1, 2}, m);
    Raycaster rc(w);
    LaserConfig cfg;
    LaserModel laser(cfg, rc, Rng(5, "l"));
    const LaserScanTruth s = laser.scan(0, kStill);
    // Step 900 = +90 deg: straight at the wall, 1 m.
    EXPECT_NEAR(s.ranges_mm[900] * 1e-3, 1.0, 0.05);
    // Steps 1.25..3.75 deg left of the front (+x) hit the wall within 60 m, at 86-89 deg
    // incidence: too glancing for an echo.
    for (int k = 545; k <= 555; ++k) {
        EXPECT_TRUE(std::isfinite(s.true_range_m[k])) << k;
        EXPECT_EQ(s.ranges_mm[k], cfg.code_weak) << k;
    }
    // Steps to the right (-y side) see nothing at all: no echo.
    EXPECT_EQ(s.ranges_mm[180], cfg.code_no_echo);
}

TEST(LaserModelTest, StepsAreTimedAndPlacedIndividually) {
    const World w = room(3.05, 0.8f);
    Raycaster rc(w);
    LaserConfig cfg;
    LaserModel laser(cfg, rc, Rng(5, "l"));
    EXPECT_NEAR(laser.stepPeriod(), 0.025 / 1440, 1e-12);
    std::vector<double> times;
    // The rig spins about z during the scan: the range of each step depends on its own time.
    const double spin = 10.0;  // rad/s
    const auto pose = [&](double t) {
        times.push_back(t);
        return Eigen::Isometry3d(Eigen::AngleAxisd(spin * t, Eigen::Vector3d::UnitZ()));
    };
    const LaserScanTruth s = laser.scan(1.0, pose);
    ASSERT_EQ(times.size(), 1081u);
    EXPECT_DOUBLE_EQ(times.front(), 1.0);
    EXPECT_NEAR(times.back() - times.front(), 1080 * 0.025 / 1440, 1e-12);
    const double a =
        (540 - 540) * 2 * std::numbers::pi / 1440 + spin * (1.0 + 540 * laser.stepPeriod());
    EXPECT_NEAR(s.true_range_m[540], 3.0 / std::max(std::abs(std::cos(a)), std::abs(std::sin(a))),
                2e-3);
}

}  // namespace
}  // namespace handscan::sim
