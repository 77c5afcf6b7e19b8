// Builds a World from primitives: quads, boxes, walls with door openings, cylinders (table legs,
// tree trunks and branches), stairs, leaves. Used by the procedural scenes.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "handscan/sim/world.hpp"

namespace handscan::sim {

// An opening in a wall, measured along the wall from its start point.
struct WallOpening {
    double from_m = 0.0;
    double to_m = 0.0;
    double bottom_m = 0.0;  // 0 for a door, > 0 for a window sill
    double top_m = 2.05;
};

class MeshBuilder {
public:
    explicit MeshBuilder(World& world) : w_(world) {}

    std::uint16_t addMaterial(const Material& m);
    // Everything added between these two is one movable object (World::objects).
    void beginObject(std::string name);
    void endObject();

    void addTriangle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                     std::uint16_t mat);
    // Planar quad a-b-c-d (in order around its edge).
    void addQuad(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                 const Eigen::Vector3d& d, std::uint16_t mat);
    // Axis-aligned solid box.
    void addBox(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, std::uint16_t mat);
    // A vertical wall of `thickness` centred on the segment p0-p1 (xy), from z0 to z0 + height,
    // with rectangular openings (doors, windows) cut through it.
    void addWall(const Eigen::Vector2d& p0, const Eigen::Vector2d& p1, double thickness, double z0,
                 double height, const std::vector<WallOpening>& openings, std::uint16_t mat);
    // A closed cylinder from a to b.
    void addCylinder(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double radius,
                     int segments, std::uint16_t mat);
    // A straight flight of stairs starting at `start` (bottom of the first riser, centre of its
    // width) climbing along the unit xy direction `dir`.
    void addStairs(const Eigen::Vector3d& start, const Eigen::Vector2d& dir, double width,
                   int steps, double rise_m, double run_m, std::uint16_t mat);
    // A leaf: a small double-sided diamond with normal n.
    void addLeaf(const Eigen::Vector3d& centre, const Eigen::Vector3d& n,
                 const Eigen::Vector3d& along, double length, double width, std::uint16_t mat);

private:
    std::uint32_t vertex(const Eigen::Vector3d& p);
    World& w_;
    std::string object_name_;
    std::uint32_t object_first_ = 0;
};

}  // namespace handscan::sim
