#include "handscan/sim/scene_change.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "handscan/sim/random.hpp"

namespace handscan::sim {
namespace {

// The horizontal direction from the walking loop's nearest point to `c` (any, without a loop).
Eigen::Vector2d awayFromLoop(const std::vector<Eigen::Vector3d>& loop, const Eigen::Vector3d& c,
                             Rng& rng) {
    double best = std::numeric_limits<double>::infinity();
    Eigen::Vector2d dir = Eigen::Vector2d::Zero();
    for (std::size_t i = 0; i < loop.size(); ++i) {
        const Eigen::Vector3d& a = loop[i];
        const Eigen::Vector3d& b = loop[(i + 1) % loop.size()];
        const Eigen::Vector3d ab = b - a;
        const double f =
            ab.squaredNorm() > 0 ? std::clamp((c - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
        const Eigen::Vector3d q = a + f * ab;
        // Objects of another storey are not near this part of the loop.
        const double d = (c - q).head<2>().norm() + 3.0 * std::abs(c.z() - (q.z() - 1.3));
        if (d < best) {
            best = d;
            dir = (c - q).head<2>();
        }
    }
    if (dir.norm() < 1e-6) {
        const double a = rng.uniform(0.0, 2 * std::numbers::pi);
        return {std::cos(a), std::sin(a)};
    }
    return dir.normalized();
}

}  // namespace

std::vector<MovedObject> moveObjects(Scene& scene, int count, std::uint64_t seed) {
    World& w = scene.world;
    std::vector<MovedObject> moved;
    if (count <= 0 || w.objects.empty()) return moved;
    Rng rng(seed, "scene-change");
    // A seeded shuffle picks which objects move.
    std::vector<std::size_t> order(w.objects.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    for (std::size_t i = order.size(); i > 1; --i) std::swap(order[i - 1], order[rng.below(i)]);
    order.resize(std::min(order.size(), static_cast<std::size_t>(count)));
    std::sort(order.begin(), order.end());
    for (const std::size_t k : order) {
        const SceneObject& o = w.objects[k];
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (std::uint32_t v = o.first_vertex; v < o.end_vertex; ++v)
            c += w.vertices[v].cast<double>();
        c /= static_cast<double>(o.end_vertex - o.first_vertex);
        const double turn = (rng.chance(0.5) ? 1.0 : -1.0) * rng.uniform(15.0, 35.0);
        const double shift = rng.uniform(0.4, 0.7);
        const Eigen::Vector2d away = awayFromLoop(scene.walk_loop, c, rng);
        const Eigen::Vector3d t(shift * away.x(), shift * away.y(), 0.0);
        const Eigen::Matrix3d R =
            Eigen::AngleAxisd(turn * std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ())
                .toRotationMatrix();
        for (std::uint32_t v = o.first_vertex; v < o.end_vertex; ++v) {
            const Eigen::Vector3d p = w.vertices[v].cast<double>();
            w.vertices[v] = (c + t + R * (p - c)).cast<float>();
        }
        moved.push_back({o.name, c, c + t, turn});
    }
    return moved;
}

}  // namespace handscan::sim
