// Built-in scenes: geometry exists, the walking loops are closed, collision-free, at walking
// speed; PLY export and OBJ import.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "handscan/core/se3.hpp"
#include "handscan/sim/ply_export.hpp"
#include "handscan/sim/raycaster.hpp"
#include "handscan/sim/scenes.hpp"
#include "handscan/sim/trajectory.hpp"

namespace handscan::sim {
namespace {

TEST(SceneTest, CatalogueListsSixScenesWithDescriptions) {
    const auto& cat = sceneCatalogue();
    ASSERT_EQ(cat.size(), 6u);
    for (const auto& s : cat) {
        EXPECT_FALSE(s.description.empty()) << s.name;
        EXPECT_EQ(s.description.find('\n'), std::string::npos);
    }
    EXPECT_THROW(buildScene("moon"), std::invalid_argument);
}

// Smallest distance from p to any surface, probed with rays in 26 directions.
float clearance(const Raycaster& rc, const Eigen::Vector3d& p) {
    float best = 1e9f;
    for (int x = -1; x <= 1; ++x)
        for (int y = -1; y <= 1; ++y)
            for (int z = -1; z <= 1; ++z) {
                if (!x && !y && !z) continue;
                const RayHit h =
                    rc.cast(Ray{p.cast<float>(), Eigen::Vector3f(x, y, z).normalized(), 5.0f});
                if (h.hit()) best = std::min(best, h.t);
            }
    return best;
}

class WalkTest : public ::testing::TestWithParam<const char*> {};

TEST_P(WalkTest, TwoMinuteWalkIsAClosedCollisionFreeLoopAtWalkingSpeed) {
    const Scene scene = buildScene(GetParam());
    ASSERT_GT(scene.world.triangleCount(), 10u);
    ASSERT_GE(scene.walk_loop.size(), 3u);
    Raycaster rc(scene.world);
    WalkOptions o;
    o.duration_s = 130.0;
    const WalkPlan plan = makeWalk(scene.walk_loop, o);
    ASSERT_TRUE(plan.closed);
    const Trajectory& tr = plan.trajectory;
    EXPECT_NEAR(tr.duration(), o.duration_s, 0.05);
    const BodyState a = tr.at(0.0), b = tr.at(tr.duration());
    EXPECT_LT((a.T_world_body.translation() - b.T_world_body.translation()).norm(), 0.01);
    EXPECT_LT(
        rotationAngle(a.T_world_body.linear(), b.T_world_body.linear()) * 180.0 / std::numbers::pi,
        1.0);
    // Still at the start (IMU initialisation), moving later.
    EXPECT_LT(tr.at(1.0).v_world.norm(), 1e-9);
    EXPECT_LT(tr.at(2.5).omega_body.norm(), 1e-9);
    double max_speed = 0.0, walked_time = 0.0;
    float min_clear = 1e9f;
    for (double t = 0.0; t <= tr.duration(); t += 0.05) {
        const BodyState s = tr.at(t);
        const double v = s.v_world.head<2>().norm();
        max_speed = std::max(max_speed, v);
        if (v > 0.3) walked_time += 0.05;
        const float c = clearance(rc, s.T_world_body.translation());
        if (c < 0.25f)
            ADD_FAILURE() << GetParam() << " t=" << t << " at "
                          << s.T_world_body.translation().transpose() << " clearance " << c;
        min_clear = std::min(min_clear, c);
    }
    const double mean_speed = tr.pathLength() / (o.duration_s - o.still_start_s - o.still_end_s);
    EXPECT_LE(max_speed, 1.6) << GetParam();
    EXPECT_GE(mean_speed, 0.5) << GetParam();
    EXPECT_LE(mean_speed, 1.5) << GetParam();
    EXPECT_GT(walked_time, 60.0);
    EXPECT_GT(min_clear, 0.25f) << GetParam() << ": the device comes within " << min_clear
                                << " m of a surface";
}

INSTANTIATE_TEST_SUITE_P(Scenes, WalkTest,
                         ::testing::Values("office", "house", "corridor", "courtyard", "tunnel",
                                           "field"));

TEST(SceneTest, HouseLoopClimbsAStorey) {
    const Scene scene = buildScene("house");
    WalkOptions o;
    o.duration_s = 120.0;
    const Trajectory tr = makeWalk(scene.walk_loop, o).trajectory;
    double zmax = -1e9, zmin = 1e9;
    for (double t = 0; t < tr.duration(); t += 0.1) {
        zmax = std::max(zmax, tr.at(t).T_world_body.translation().z());
        zmin = std::min(zmin, tr.at(t).T_world_body.translation().z());
    }
    EXPECT_GT(zmax - zmin, 2.8);
}

TEST(SceneTest, PlyExportWritesEveryTriangle) {
    const Scene scene = buildScene("office");
    const auto dir = std::filesystem::temp_directory_path();
    const std::string bin = (dir / "handscan_sim_office.ply").string();
    const std::string txt = (dir / "handscan_sim_office_ascii.ply").string();
    ASSERT_TRUE(writePly(scene.world, bin, true).isOk());
    ASSERT_TRUE(writePly(scene.world, txt, false).isOk());
    const std::size_t nv = scene.world.vertices.size(), nf = scene.world.triangleCount();
    std::ifstream in(bin, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line) && line != "end_header") header += line + "\n";
    EXPECT_NE(header.find("element vertex " + std::to_string(nv)), std::string::npos);
    EXPECT_NE(header.find("element face " + std::to_string(nf)), std::string::npos);
    const auto body = std::filesystem::file_size(bin) - static_cast<std::uintmax_t>(in.tellg());
    EXPECT_EQ(body, nv * 12 + nf * (1 + 12 + 2 + 3));
    std::ifstream a(txt);
    std::size_t lines = 0;
    while (std::getline(a, line)) ++lines;
    EXPECT_GT(lines, nv + nf);
    std::filesystem::remove(bin);
    std::filesystem::remove(txt);
}

TEST(SceneTest, ObjImportKeepsTrianglesAndMaterials) {
    const auto dir = std::filesystem::temp_directory_path() / "handscan_sim_obj";
    std::filesystem::create_directories(dir);
    {
        std::ofstream mtl(dir / "room.mtl");
        mtl << "newmtl brickwall\nKd 0.6 0.3 0.2\nmap_Kd brick.png\nnewmtl floor\nKd 0.2 0.2 0.2\n";
        std::ofstream obj(dir / "room.obj");
        obj << "mtllib room.mtl\nv 0 0 0\nv 4 0 0\nv 4 3 0\nv 0 3 0\nv 0 0 2\nv 4 0 2\n"
               "usemtl floor\nf 1 2 3 4\nusemtl brickwall\nf 1 2 6 5\n";
    }
    const Scene s = importObj((dir / "room.obj").string());
    ASSERT_EQ(s.world.triangleCount(), 4u);  // two quads, triangulated
    const Material& m = s.world.materials[s.world.triangle_material[2]];
    EXPECT_EQ(m.name, "brickwall");
    EXPECT_EQ(m.texture, TextureId::kBrick);
    EXPECT_NEAR(m.colour[0], 0.6f, 1e-6f);
    Raycaster rc(s.world);
    EXPECT_NEAR(rc.cast(Ray{{1, 1, 1}, {0, 0, -1}}).t, 1.0f, 1e-5f);
    EXPECT_THROW(importObj((dir / "missing.obj").string()), std::runtime_error);
    std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace handscan::sim
