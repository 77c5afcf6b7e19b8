// Point-to-triangle distance, the BVH-accelerated mesh distance, PLY reading and the map error.
#include "handscan/eval/mesh_distance.hpp"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "handscan/eval/ply_reader.hpp"

namespace handscan::eval {
namespace {

const Eigen::Vector3d A(0, 0, 0), B(1, 0, 0), C(0, 1, 0);

TEST(PointTriangle, Regions) {
    EXPECT_NEAR(pointTriangleDistance({0.2, 0.2, 0.7}, A, B, C), 0.7, 1e-12);         // face
    EXPECT_NEAR(pointTriangleDistance({0.2, 0.2, -0.3}, A, B, C), 0.3, 1e-12);        // face, below
    EXPECT_NEAR(pointTriangleDistance({0.5, -0.4, 0.3}, A, B, C), 0.5, 1e-12);        // edge AB
    EXPECT_NEAR(pointTriangleDistance({-0.3, 0.5, 0.4}, A, B, C), 0.5, 1e-12);        // edge AC
    EXPECT_NEAR(pointTriangleDistance({1, 1, 0}, A, B, C), std::sqrt(0.5), 1e-12);    // edge BC
    EXPECT_NEAR(pointTriangleDistance({-1, -1, 0}, A, B, C), std::sqrt(2.0), 1e-12);  // vertex A
    EXPECT_NEAR(pointTriangleDistance({2, -1, 0}, A, B, C), std::sqrt(2.0), 1e-12);   // vertex B
    EXPECT_NEAR(pointTriangleDistance({-0.5, 2, 1}, A, B, C), 1.5, 1e-12);            // vertex C
    EXPECT_NEAR(pointTriangleDistance({0.25, 0.25, 0}, A, B, C), 0.0, 1e-15);         // on it
    // Degenerate (collinear) triangle: distance to the segment.
    EXPECT_NEAR(pointTriangleDistance({0.5, 1, 0}, A, B, Eigen::Vector3d(2, 0, 0)), 1.0, 1e-12);
}

// Brute-force minimum over all triangles.
double bruteForce(const PlyGeometry& m, const Eigen::Vector3d& p) {
    double best = 1e300;
    for (const auto& t : m.triangles) {
        best = std::min(
            best, pointTriangleDistance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
    }
    return best;
}

TEST(MeshDistance, MatchesBruteForceOnARandomMesh) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-5.0, 5.0);
    PlyGeometry m;
    for (int i = 0; i < 300; ++i) {
        const Eigen::Vector3d c(u(rng), u(rng), u(rng));
        for (int k = 0; k < 3; ++k)
            m.vertices.push_back(c + 0.3 * Eigen::Vector3d(u(rng), u(rng), u(rng)) / 5.0);
        m.triangles.push_back({static_cast<std::uint32_t>(3 * i),
                               static_cast<std::uint32_t>(3 * i + 1),
                               static_cast<std::uint32_t>(3 * i + 2)});
    }
    // Plus a huge floor triangle (bounds of centroid-based indexes break on these).
    m.vertices.push_back({-100, -100, -6});
    m.vertices.push_back({100, -100, -6});
    m.vertices.push_back({0, 100, -6});
    m.triangles.push_back({900, 901, 902});
    auto mesh = MeshDistance::build(m);
    ASSERT_TRUE(mesh) << mesh.status().message();
    for (int i = 0; i < 500; ++i) {
        const Eigen::Vector3d p(u(rng) * 1.5, u(rng) * 1.5, u(rng) * 1.5);
        EXPECT_NEAR((*mesh)->distance(p), bruteForce(m, p), 1e-9) << i;
    }
    EXPECT_FALSE(MeshDistance::build(PlyGeometry{}).isOk());
}

// Unit cube as 12 triangles.
PlyGeometry cube() {
    PlyGeometry m;
    for (int i = 0; i < 8; ++i) m.vertices.emplace_back(i & 1, (i >> 1) & 1, (i >> 2) & 1);
    const std::uint32_t f[6][4] = {{0, 1, 3, 2}, {4, 6, 7, 5}, {0, 4, 5, 1},
                                   {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 5, 7, 3}};
    for (const auto& q : f) {
        m.triangles.push_back({q[0], q[1], q[2]});
        m.triangles.push_back({q[0], q[2], q[3]});
    }
    return m;
}

TEST(MapError, PercentilesOfKnownOffsets) {
    auto mesh = MeshDistance::build(cube());
    ASSERT_TRUE(mesh);
    std::vector<Eigen::Vector3d> pts;
    for (int i = 0; i < 100; ++i) {
        // 100 points 1 cm above the top face... the last ten 10 cm above.
        const double off = i < 90 ? 0.01 : 0.10;
        pts.emplace_back(0.1 + 0.008 * i, 0.5, 1.0 + off);
    }
    const MapErrorResult r = computeMapError(pts, **mesh);
    EXPECT_EQ(r.points, 100u);
    EXPECT_NEAR(r.median_m, 0.01, 1e-9);
    EXPECT_NEAR(r.p90_m, 0.10, 1e-9);
    EXPECT_NEAR(r.p99_m, 0.10, 1e-9);
    EXPECT_NEAR(r.max_m, 0.10, 1e-9);
}

TEST(Ply, AsciiWithQuadsAndExtraProperties) {
    const std::string ply =
        "ply\nformat ascii 1.0\ncomment test\nelement vertex 4\nproperty float x\nproperty float "
        "y\n"
        "property float z\nproperty uchar red\nelement face 1\nproperty list uchar int "
        "vertex_indices\n"
        "end_header\n0 0 0 255\n1 0 0 0\n1 1 0 0\n0 1 0 0\n4 0 1 2 3\n";
    auto g = parsePly(ply);
    ASSERT_TRUE(g) << g.status().message();
    EXPECT_EQ(g->vertices.size(), 4u);
    ASSERT_EQ(g->triangles.size(), 2u);  // quad fan-triangulated
    EXPECT_EQ(g->triangles[1][2], 3u);
    EXPECT_EQ(g->vertices[2], Eigen::Vector3d(1, 1, 0));
}

TEST(Ply, BinaryLittleEndianAndTruncation) {
    std::string ply =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty double x\nproperty "
        "double y\n"
        "property double z\nproperty float intensity\nelement face 1\nproperty list uchar uint "
        "vertex_indices\n"
        "end_header\n";
    for (int i = 0; i < 3; ++i) {
        const double xyz[3] = {1.0 * i, 2.0 * i, -0.5 * i};
        const float intensity = 7.0f;
        ply.append(reinterpret_cast<const char*>(xyz), sizeof xyz);
        ply.append(reinterpret_cast<const char*>(&intensity), sizeof intensity);
    }
    const std::uint8_t n = 3;
    const std::uint32_t idx[3] = {0, 1, 2};
    ply.append(reinterpret_cast<const char*>(&n), 1);
    ply.append(reinterpret_cast<const char*>(idx), sizeof idx);
    auto g = parsePly(ply, "scene.ply");
    ASSERT_TRUE(g) << g.status().message();
    ASSERT_EQ(g->vertices.size(), 3u);
    EXPECT_EQ(g->vertices[2], Eigen::Vector3d(2.0, 4.0, -1.0));
    ASSERT_EQ(g->triangles.size(), 1u);

    auto cut = parsePly(ply.substr(0, ply.size() - 5), "scene.ply");
    ASSERT_FALSE(cut.isOk());
    EXPECT_NE(cut.status().message().find("scene.ply: truncated"), std::string::npos);
    EXPECT_FALSE(parsePly("ply\nformat binary_big_endian 1.0\nend_header\n").isOk());
    EXPECT_FALSE(parsePly("not a ply").isOk());
    auto bad_index = parsePly(
        "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
        "end_header\n0 0 0\n3 0 1 2\n");
    EXPECT_FALSE(bad_index.isOk());
}

}  // namespace
}  // namespace handscan::eval
