// Ray casting against a box room returns the analytic distances.
#include <gtest/gtest.h>

#include <cmath>

#include "handscan/sim/mesh_builder.hpp"
#include "handscan/sim/raycaster.hpp"

namespace handscan::sim {
namespace {

World boxRoom() {
    World w;
    MeshBuilder b(w);
    const auto m =
        b.addMaterial(Material{"wall", 0.8f, {0.8f, 0.8f, 0.8f}, TextureId::kPlaster, 1.0f});
    // Inside faces of the room [0,4] x [0,3] x [0,2.5].
    using V = Eigen::Vector3d;
    b.addQuad(V(0, 0, 0), V(4, 0, 0), V(4, 3, 0), V(0, 3, 0), m);          // floor
    b.addQuad(V(0, 0, 2.5), V(0, 3, 2.5), V(4, 3, 2.5), V(4, 0, 2.5), m);  // ceiling
    b.addQuad(V(0, 0, 0), V(0, 0, 2.5), V(4, 0, 2.5), V(4, 0, 0), m);      // y = 0
    b.addQuad(V(0, 3, 0), V(4, 3, 0), V(4, 3, 2.5), V(0, 3, 2.5), m);      // y = 3
    b.addQuad(V(0, 0, 0), V(0, 3, 0), V(0, 3, 2.5), V(0, 0, 2.5), m);      // x = 0
    b.addQuad(V(4, 0, 0), V(4, 0, 2.5), V(4, 3, 2.5), V(4, 3, 0), m);      // x = 4
    return w;
}

TEST(RaycastTest, BoxRoomAxisDistances) {
    const World w = boxRoom();
    Raycaster rc(w);
    const Eigen::Vector3f o(1.0f, 1.0f, 1.2f);
    struct Case {
        Eigen::Vector3f d;
        float expect;
    } cases[] = {{{1, 0, 0}, 3.0f},  {{-1, 0, 0}, 1.0f}, {{0, 1, 0}, 2.0f},
                 {{0, -1, 0}, 1.0f}, {{0, 0, 1}, 1.3f},  {{0, 0, -1}, 1.2f}};
    for (const auto& c : cases) {
        const RayHit h = rc.cast(Ray{o, c.d});
        ASSERT_TRUE(h.hit());
        EXPECT_NEAR(h.t, c.expect, 1e-5f) << c.d.transpose();
        EXPECT_NEAR(std::abs(w.triangleNormal(h.triangle).dot(c.d)), 1.0f, 1e-6f);
    }
}

TEST(RaycastTest, BoxRoomObliqueRaysMatchPlaneIntersection) {
    const World w = boxRoom();
    Raycaster rc(w);
    const Eigen::Vector3f o(2.5f, 1.7f, 0.9f);
    std::vector<Ray> rays;
    std::vector<float> expect;
    for (int i = 0; i < 500; ++i) {
        const float az = 0.0125f * static_cast<float>(i) * 6.283f / 6.25f,
                    el = std::sin(0.37f * i) * 1.2f;
        const Eigen::Vector3f d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az),
                                std::sin(el));
        // Analytic: the nearest of the six planes along d.
        float best = INFINITY;
        const float lo[3] = {0, 0, 0}, hi[3] = {4, 3, 2.5f};
        for (int a = 0; a < 3; ++a) {
            if (std::abs(d[a]) < 1e-9f) continue;
            for (float plane : {lo[a], hi[a]}) {
                const float t = (plane - o[a]) / d[a];
                if (t > 0) best = std::min(best, t);
            }
        }
        rays.push_back(Ray{o, d});
        expect.push_back(best);
    }
    std::vector<RayHit> hits(rays.size());
    rc.castBatch(rays, hits, false);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(hits[i].hit()) << i;
        EXPECT_NEAR(hits[i].t, expect[i], 2e-4f) << i;
        EXPECT_EQ(hits[i].triangle, rc.cast(rays[i]).triangle);  // stream == single rays
    }
}

TEST(RaycastTest, MissesOutsideAndRespectsTmax) {
    const World w = boxRoom();
    Raycaster rc(w);
    EXPECT_FALSE(rc.cast(Ray{{10, 10, 10}, {1, 0, 0}}).hit());
    EXPECT_FALSE(rc.cast(Ray{{1, 1, 1}, {1, 0, 0}, 2.5f}).hit());  // wall at 3 m
    EXPECT_TRUE(rc.cast(Ray{{1, 1, 1}, {1, 0, 0}, 3.5f}).hit());
}

}  // namespace
}  // namespace handscan::sim
