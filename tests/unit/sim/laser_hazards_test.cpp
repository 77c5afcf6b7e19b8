// The harder world for the laser (LaserHazards): people in the beam, glass panes that answer,
// mirror or pass the beam, mixed pixels at depth edges, black surfaces.
#include "handscan/sim/laser_hazards.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "handscan/sim/laser_model.hpp"
#include "handscan/sim/mesh_builder.hpp"

namespace handscan::sim {
namespace {

// A square room [-5, 5]^2 (walls 0.1 thick: inner faces at +-4.95), optionally a panel
// standing in front of the +x wall from y = 0 to y = 3 (its near face at x = 4.25).
World room(bool panel) {
    World w;
    MeshBuilder b(w);
    const auto m =
        b.addMaterial(Material{"wall", 0.8f, {0.5f, 0.5f, 0.5f}, TextureId::kPlain, 1.0f});
    const double h = 5.0;
    b.addWall({-h, -h}, {h, -h}, 0.1, -2, 4, {}, m);
    b.addWall({h, -h}, {h, h}, 0.1, -2, 4, {}, m);
    b.addWall({h, h}, {-h, h}, 0.1, -2, 4, {}, m);
    b.addWall({-h, h}, {-h, -h}, 0.1, -2, 4, {}, m);
    if (panel) b.addWall({4.3, 0.0}, {4.3, 3.0}, 0.1, -2, 4, {}, m);
    return w;
}

// The operator walks along +x at 0.6 m/s, x = -3 + 0.6 t, holding the device 1.3 m up.
Trajectory straightWalk() {
    std::vector<Vector6d> c;
    for (int i = 0; i <= 12; ++i) {
        Vector6d k;
        k << -3.0 + 0.6 * (i - 1), 0.0, 1.3, 0.0, 0.0, 0.0;  // knot i at t = i - 1
        c.push_back(k);
    }
    return Trajectory(1.0, c, 10.0);
}

LaserEcho wallEcho(double range) { return LaserEcho{range, 0.8, 1.0}; }

TEST(LaserHazards, APersonAheadOnThePathBlocksTheBeam) {
    const World w = room(false);
    Raycaster rc(w);
    const Trajectory path = straightWalk();
    HazardOptions o;
    o.people = 1;  // person 0 walks 3 s ahead of the operator
    LaserHazards hazards(o, path, w, Rng(1, "hazards"));
    const double t = 4.0;
    const Eigen::Vector3d me = path.at(t).T_world_body.translation();
    const Eigen::Vector3d feet = hazards.personAt(0, t);
    EXPECT_NEAR(feet.x() - me.x(), 1.8, 0.05);  // 3 s at 0.6 m/s
    EXPECT_NEAR(feet.z(), 0.0, 1e-6);           // on the floor below the hand
    const Eigen::Vector3f o_f = me.cast<float>();
    auto ahead = hazards.echo(o_f, Eigen::Vector3f::UnitX(), t, wallEcho(4.95 - me.x()), 60.f, rc);
    ASSERT_TRUE(ahead);
    EXPECT_NEAR(ahead->range_m, feet.x() - me.x() - 0.22, 0.01);
    EXPECT_NEAR(ahead->reflectivity, 0.35, 1e-9);
    // Behind the operator, and above the person's head: the wall.
    auto behind =
        hazards.echo(o_f, -Eigen::Vector3f::UnitX(), t, wallEcho(4.95 + me.x()), 60.f, rc);
    ASSERT_TRUE(behind);
    EXPECT_NEAR(behind->range_m, 4.95 + me.x(), 1e-9);
    const Eigen::Vector3f up_ahead = Eigen::Vector3f(1.0f, 0.0f, 0.6f).normalized();
    auto over = hazards.echo(o_f, up_ahead, t, wallEcho(9.0), 60.f, rc);
    ASSERT_TRUE(over);
    EXPECT_NEAR(over->range_m, 9.0, 1e-9);
}

TEST(LaserHazards, GlassAnswersAtNormalIncidenceElseMirrorsOrPasses) {
    const World w = room(false);
    Raycaster rc(w);
    const Trajectory path = straightWalk();
    HazardOptions o;
    o.glass_panes = 1;  // at t = 5 s (x = 0): 1 m to the left (+y), facing the path
    LaserHazards hazards(o, path, w, Rng(2, "hazards"));
    const Eigen::Vector3d at_pane = path.at(5.0).T_world_body.translation();
    const double x5 = at_pane.x(), y5 = at_pane.y();
    // Straight at the pane: the pane answers.
    auto normal = hazards.echo(Eigen::Vector3d(x5, y5, 1.3).cast<float>(), Eigen::Vector3f::UnitY(),
                               0.0, wallEcho(4.95 - y5), 60.f, rc);
    ASSERT_TRUE(normal);
    EXPECT_NEAR(normal->range_m, 1.0, 1e-6);
    // At 45 deg from half a metre back: through the pane to the +y wall, or mirrored by it
    // towards the +x wall, about a quarter of the time.
    const Eigen::Vector3f from = Eigen::Vector3d(x5 - 0.5, y5, 1.3).cast<float>();
    const Eigen::Vector3f dir = Eigen::Vector3f(1.f, 1.f, 0.f).normalized();
    const double r_through = (4.95 - y5) * std::sqrt(2.0);
    const double r_mirrored = std::sqrt(2.0) * (1.0 + std::min(4.95 - (x5 + 0.5), y5 + 1.0 + 4.95));
    int through = 0, mirrored = 0;
    for (int i = 0; i < 2000; ++i) {
        auto e = hazards.echo(from, dir, 0.0, wallEcho(r_through), 60.f, rc);
        ASSERT_TRUE(e);
        if (std::abs(e->range_m - r_through) < 1e-3) {
            ++through;
            EXPECT_LT(e->reflectivity, 0.8);  // weakened by the glass
        } else {
            EXPECT_NEAR(e->range_m, r_mirrored, 0.01);
            ++mirrored;
        }
    }
    EXPECT_EQ(through + mirrored, 2000);
    EXPECT_NEAR(mirrored / 2000.0, 0.25, 0.05);
}

TEST(LaserHazards, MixedPixelsFloatBetweenTheSurfacesOfADepthEdge) {
    // The panel's edge (y = 0, 0.7 m in front of the wall) seen from the origin: with mixed
    // pixels some beams report a range between the panel and the wall, never without.
    const World w = room(true);
    Raycaster rc(w);
    const Trajectory path = straightWalk();
    LaserConfig cfg;
    auto between = [&](LaserHazards* hazards) {
        LaserModel laser(cfg, rc, Rng(3, "laser"), hazards);
        int n = 0;
        for (int s = 0; s < 200; ++s) {
            // The shaft turned a little each scan so the edge falls at every place in the step.
            const double yaw = 0.25 * std::numbers::pi / 180.0 * s / 200.0;
            Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
            T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
            const LaserScanTruth scan = laser.scan(0.025 * s, [&](double) { return T; });
            for (int k = 530; k < 550; ++k) {
                const double r = scan.ranges_mm[k] * 1e-3;
                if (r > 4.35 && r < 4.85) ++n;
            }
        }
        return n;
    };
    EXPECT_EQ(between(nullptr), 0);
    HazardOptions o;
    o.mixed_pixels = true;
    LaserHazards hazards(o, path, w, Rng(3, "hazards"));
    EXPECT_GT(between(&hazards), 40);  // about one beam in two scans straddles the edge
}

TEST(LaserHazards, DarkSurfacesAreBlackAtTheLasersWavelength) {
    const World w = room(false);
    const Trajectory path = straightWalk();
    HazardOptions o;
    o.dark_surfaces = 1.0;
    LaserHazards all_dark(o, path, w, Rng(4, "hazards"));
    EXPECT_NEAR(all_dark.reflectivity(w, 0), 0.03, 1e-9);
    o.dark_surfaces = 0.0;
    LaserHazards none(o, path, w, Rng(4, "hazards"));
    EXPECT_NEAR(none.reflectivity(w, 0), 0.8, 1e-6);
}

}  // namespace
}  // namespace handscan::sim
