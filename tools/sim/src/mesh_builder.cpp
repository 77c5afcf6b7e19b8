#include "handscan/sim/mesh_builder.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

namespace handscan::sim {

std::uint16_t MeshBuilder::addMaterial(const Material& m) {
    if (w_.materials.size() >= 0xFFFF)
        throw std::length_error("MeshBuilder: more than 65535 materials");
    w_.materials.push_back(m);
    return static_cast<std::uint16_t>(w_.materials.size() - 1);
}

void MeshBuilder::beginObject(std::string name) {
    object_name_ = std::move(name);
    object_first_ = static_cast<std::uint32_t>(w_.vertices.size());
}

void MeshBuilder::endObject() {
    const auto end = static_cast<std::uint32_t>(w_.vertices.size());
    if (end > object_first_) w_.objects.push_back({object_name_, object_first_, end});
    object_name_.clear();
}

std::uint32_t MeshBuilder::vertex(const Eigen::Vector3d& p) {
    w_.vertices.push_back(p.cast<float>());
    return static_cast<std::uint32_t>(w_.vertices.size() - 1);
}

void MeshBuilder::addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                              const Eigen::Vector3d& c, std::uint16_t mat) {
    const std::uint32_t ia = vertex(a), ib = vertex(b), ic = vertex(c);
    w_.triangles.push_back({ia, ib, ic});
    w_.triangle_material.push_back(mat);
}

void MeshBuilder::addQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                          const Eigen::Vector3d& c, const Eigen::Vector3d& d, std::uint16_t mat) {
    const std::uint32_t ia = vertex(a), ib = vertex(b), ic = vertex(c), id = vertex(d);
    w_.triangles.push_back({ia, ib, ic});
    w_.triangles.push_back({ia, ic, id});
    w_.triangle_material.push_back(mat);
    w_.triangle_material.push_back(mat);
}

void MeshBuilder::addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::uint16_t mat) {
    auto p = [&](int x, int y, int z) {
        return Eigen::Vector3d(x ? hi.x() : lo.x(), y ? hi.y() : lo.y(), z ? hi.z() : lo.z());
    };
    addQuad(p(0, 0, 0), p(0, 1, 0), p(1, 1, 0), p(1, 0, 0), mat);  // bottom (-z)
    addQuad(p(0, 0, 1), p(1, 0, 1), p(1, 1, 1), p(0, 1, 1), mat);  // top (+z)
    addQuad(p(0, 0, 0), p(1, 0, 0), p(1, 0, 1), p(0, 0, 1), mat);  // -y
    addQuad(p(0, 1, 0), p(0, 1, 1), p(1, 1, 1), p(1, 1, 0), mat);  // +y
    addQuad(p(0, 0, 0), p(0, 0, 1), p(0, 1, 1), p(0, 1, 0), mat);  // -x
    addQuad(p(1, 0, 0), p(1, 1, 0), p(1, 1, 1), p(1, 0, 1), mat);  // +x
}

void MeshBuilder::addWall(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, double thickness,
                          double z0, double height, const std::vector<WallOpening>& openings,
                          std::uint16_t mat) {
    const Eigen::Vector2d along2 = p1 - p0;
    const double length = along2.norm();
    if (length <= 0.0) return;
    const Eigen::Vector2d u2 = along2 / length;
    const Eigen::Vector3d u(u2.x(), u2.y(), 0.0);
    const Eigen::Vector3d n(-u2.y(), u2.x(), 0.0);  // wall normal (left of p0 -> p1)
    const Eigen::Vector3d o(p0.x(), p0.y(), z0);
    const double h = thickness / 2.0;
    // A solid slab between along-wall coordinates [s0, s1] and heights [zb, zt], as an oriented
    // box.
    auto slab = [&](double s0, double s1, double zb, double zt) {
        if (s1 - s0 <= 1e-6 || zt - zb <= 1e-6) return;
        auto p = [&](double s, double t, double z) {
            return Eigen::Vector3d(o + s * u + t * n + Eigen::Vector3d(0, 0, z));
        };
        addQuad(p(s0, -h, zb), p(s1, -h, zb), p(s1, -h, zt), p(s0, -h, zt), mat);
        addQuad(p(s1, h, zb), p(s0, h, zb), p(s0, h, zt), p(s1, h, zt), mat);
        addQuad(p(s0, h, zb), p(s0, -h, zb), p(s0, -h, zt), p(s0, h, zt), mat);
        addQuad(p(s1, -h, zb), p(s1, h, zb), p(s1, h, zt), p(s1, -h, zt), mat);
        addQuad(p(s0, -h, zt), p(s1, -h, zt), p(s1, h, zt), p(s0, h, zt), mat);
        addQuad(p(s0, h, zb), p(s1, h, zb), p(s1, -h, zb), p(s0, -h, zb), mat);
    };
    std::vector<WallOpening> ops = openings;
    std::sort(ops.begin(), ops.end(),
              [](const WallOpening& a, const WallOpening& b) { return a.from_m < b.from_m; });
    double s = 0.0;
    for (const WallOpening& op : ops) {
        const double a = std::clamp(op.from_m, 0.0, length), b = std::clamp(op.to_m, 0.0, length);
        slab(s, a, 0.0, height);  // full-height part before the opening
        slab(a, b, 0.0, std::clamp(op.bottom_m, 0.0, height));  // below a window
        slab(a, b, std::clamp(op.top_m, 0.0, height), height);  // lintel above
        s = std::max(s, b);
    }
    slab(s, length, 0.0, height);
}

void MeshBuilder::addCylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                              int segments, std::uint16_t mat) {
    const Eigen::Vector3d axis = b - a;
    if (axis.norm() <= 0.0 || segments < 3) return;
    const Eigen::Vector3d d = axis.normalized();
    const Eigen::Vector3d e1 = d.unitOrthogonal();
    const Eigen::Vector3d e2 = d.cross(e1);
    for (int i = 0; i < segments; ++i) {
        const double a0 = 2.0 * std::numbers::pi * i / segments,
                     a1 = 2.0 * std::numbers::pi * (i + 1) / segments;
        const Eigen::Vector3d r0 = radius * (std::cos(a0) * e1 + std::sin(a0) * e2);
        const Eigen::Vector3d r1 = radius * (std::cos(a1) * e1 + std::sin(a1) * e2);
        addQuad(a + r0, a + r1, b + r1, b + r0, mat);
        addTriangle(a, a + r1, a + r0, mat);
        addTriangle(b, b + r0, b + r1, mat);
    }
}

void MeshBuilder::addStairs(const Eigen::Vector3d& start, const Eigen::Vector2d& dir, double width,
                            int steps, double rise_m, double run_m, std::uint16_t mat) {
    const Eigen::Vector3d f(dir.x(), dir.y(), 0.0);
    const Eigen::Vector3d s(-dir.y(), dir.x(), 0.0);
    for (int i = 0; i < steps; ++i) {
        // Step i: a block from the floor to its tread, so the flight is solid underneath.
        const Eigen::Vector3d base = start + f * (run_m * i);
        const double top = rise_m * (i + 1);
        auto p = [&](double along, double side, double z) {
            return Eigen::Vector3d(base + along * f + side * s + Eigen::Vector3d(0, 0, z));
        };
        const double hw = width / 2.0;
        addQuad(p(0, -hw, top), p(run_m, -hw, top), p(run_m, hw, top), p(0, hw, top),
                mat);  // tread
        addQuad(p(0, hw, top - rise_m), p(0, -hw, top - rise_m), p(0, -hw, top), p(0, hw, top),
                mat);                                                                      // riser
        addQuad(p(0, -hw, 0), p(run_m, -hw, 0), p(run_m, -hw, top), p(0, -hw, top), mat);  // side
        addQuad(p(run_m, hw, 0), p(0, hw, 0), p(0, hw, top), p(run_m, hw, top), mat);      // side
    }
}

void MeshBuilder::addLeaf(const Eigen::Vector3d& centre, const Eigen::Vector3d& n,
                          const Eigen::Vector3d& along, double length, double width,
                          std::uint16_t mat) {
    const Eigen::Vector3d a = along.normalized();
    const Eigen::Vector3d side = n.cross(a).normalized();
    addQuad(centre - 0.5 * length * a, centre - 0.5 * width * side, centre + 0.5 * length * a,
            centre + 0.5 * width * side, mat);
}

}  // namespace handscan::sim
