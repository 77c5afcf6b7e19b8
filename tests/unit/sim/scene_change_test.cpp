// A second session through the same scene (issue 14): the walk started elsewhere on the loop,
// and objects moved between the sessions, deterministically per seed.
#include "handscan/sim/scene_change.hpp"

#include <gtest/gtest.h>

#include "handscan/sim/scenes.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {
namespace {

TEST(SceneChangeTest, FurnitureScenesHaveMovableObjects) {
    // Desks, chairs, shelves, cabinets; sofa, tables, bed, shelves; benches and bushes.
    for (const auto& [name, count] :
         {std::pair{"office", 20u}, std::pair{"house", 8u}, std::pair{"courtyard", 12u}}) {
        const Scene s = buildScene(name);
        EXPECT_EQ(s.world.objects.size(), count) << name;
        for (const SceneObject& o : s.world.objects) {
            EXPECT_LT(o.first_vertex, o.end_vertex) << name << " " << o.name;
            EXPECT_LE(o.end_vertex, s.world.vertices.size());
        }
    }
}

TEST(SceneChangeTest, MovesTheAskedNumberOfObjectsTheSameWayPerSeed) {
    const Scene original = buildScene("house");
    Scene a = buildScene("house"), b = buildScene("house"), c = buildScene("house");
    const auto ma = moveObjects(a, 2, 7);
    const auto mb = moveObjects(b, 2, 7);
    const auto mc = moveObjects(c, 2, 8);
    ASSERT_EQ(ma.size(), 2u);
    ASSERT_EQ(mb.size(), 2u);
    EXPECT_EQ(a.world.vertices, b.world.vertices);  // same seed, same change
    EXPECT_NE(a.world.vertices, c.world.vertices);  // another seed, another change
    std::size_t changed = 0;
    for (std::size_t i = 0; i < a.world.vertices.size(); ++i)
        changed += (a.world.vertices[i] - original.world.vertices[i]).norm() > 1e-4f;
    EXPECT_GT(changed, 0u);
    for (const MovedObject& m : ma) {
        const double shift = (m.centre_after - m.centre_before).head<2>().norm();
        EXPECT_GE(shift, 0.4 - 1e-9) << m.name;
        EXPECT_LE(shift, 0.7 + 1e-9) << m.name;
        EXPECT_NEAR(m.centre_after.z(), m.centre_before.z(), 1e-12);
        EXPECT_GE(std::abs(m.turn_deg), 15.0);
        EXPECT_LE(std::abs(m.turn_deg), 35.0);
    }
    // Walls and floors stay: the first vertex (the floor slab) is where it was.
    EXPECT_EQ(a.world.vertices.front(), original.world.vertices.front());
    EXPECT_TRUE(moveObjects(a, 0, 7).empty());
}

TEST(SceneChangeTest, StartAtBeginsTheWalkElsewhereOnTheSameLoop) {
    const Scene scene = buildScene("house");
    WalkOptions o;
    o.duration_s = 20.0;
    const Trajectory first = makeWalk(scene.walk_loop, o).trajectory;
    o.start_fraction = 0.5;
    const Trajectory second = makeWalk(scene.walk_loop, o).trajectory;
    const Eigen::Vector3d p0 = first.at(0.0).T_world_body.translation();
    const Eigen::Vector3d p1 = second.at(0.0).T_world_body.translation();
    EXPECT_GT((p0 - p1).norm(), 3.0);  // half way round the house loop: upstairs
    // Still on the loop: the second start lies on the first session's path of a full lap.
    WalkOptions lap;
    lap.duration_s = 120.0;
    const Trajectory full = makeWalk(scene.walk_loop, lap).trajectory;
    double nearest = 1e9;
    for (double t = 0; t < full.duration(); t += 0.05)
        nearest = std::min(nearest, (full.at(t).T_world_body.translation() - p1).norm());
    EXPECT_LT(nearest, 0.15);
}

}  // namespace
}  // namespace handscan::sim
