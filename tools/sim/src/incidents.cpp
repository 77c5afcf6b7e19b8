#include "handscan/sim/incidents.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace handscan::sim {

Trajectory withDrop(const Trajectory& walk, double t_drop, double floor_z, double lie_s,
                    double pickup_s) {
    const double dt = walk.knotSpacing();
    const std::vector<Vector6d>& c = walk.controlPoints();
    if (c.size() < 3) return walk;
    const auto i0 = std::clamp<std::size_t>(static_cast<std::size_t>(std::lround(t_drop / dt)), 1,
                                            c.size() - 2);
    const Vector6d hand = c[i0];
    std::vector<Vector6d> out(c.begin(), c.begin() + static_cast<long>(i0) + 1);
    // Falling: z under gravity, x/y carried on at the walk's speed, rolling onto the side.
    constexpr double g = 9.81;
    const double rest_z = floor_z + 0.1;
    const double height = std::max(0.05, hand[2] - rest_z);
    const double t_fall = std::sqrt(2.0 * height / g);
    const Eigen::Vector2d v = (c[i0].head<2>() - c[i0 - 1].head<2>()) / dt;
    Vector6d rest = hand;
    for (int k = 1;; ++k) {
        const double t = std::min(k * dt, t_fall);
        Vector6d p = hand;
        p.head<2>() += v * t;
        p[2] = hand[2] - 0.5 * g * t * t;
        p[5] = hand[5] + 0.5 * std::numbers::pi * (t / t_fall);
        out.push_back(p);
        rest = p;
        if (t >= t_fall) break;
    }
    // Lying on the floor, then picked up: a smooth step back to the pose it fell from.
    const int lie = std::max(1, static_cast<int>(std::lround(lie_s / dt)));
    for (int k = 0; k < lie; ++k) out.push_back(rest);
    const int pick = std::max(2, static_cast<int>(std::lround(pickup_s / dt)));
    for (int k = 1; k <= pick; ++k) {
        const double s = static_cast<double>(k) / pick;
        const double w = s * s * (3.0 - 2.0 * s);
        out.push_back(rest + w * (hand - rest));
    }
    out.insert(out.end(), c.begin() + static_cast<long>(i0) + 1, c.end());
    return Trajectory(dt, std::move(out), walk.duration());
}

}  // namespace handscan::sim
