#include "handscan/sim/world.hpp"

#include <Eigen/Geometry>
#include <limits>

namespace handscan::sim {

Eigen::Vector3f World::triangleNormal(std::size_t i) const {
    const auto& t = triangles[i];
    const Eigen::Vector3f n =
        (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]);
    const float len = n.norm();
    return len > 0.0f ? Eigen::Vector3f(n / len) : Eigen::Vector3f::UnitZ();
}

void World::bounds(Eigen::Vector3f& lo, Eigen::Vector3f& hi) const {
    lo.setConstant(std::numeric_limits<float>::max());
    hi.setConstant(std::numeric_limits<float>::lowest());
    for (const auto& v : vertices) {
        lo = lo.cwiseMin(v);
        hi = hi.cwiseMax(v);
    }
}

}  // namespace handscan::sim
