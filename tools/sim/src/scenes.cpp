// Procedural scenes. Dimensions in metres; {W} has z up and the floor of the ground storey at
// z = 0. Walking loops hold the device 1.3 m above the floor.
#include "handscan/sim/scenes.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "handscan/sim/mesh_builder.hpp"
#include "handscan/sim/random.hpp"

namespace handscan::sim {
namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kHand = 1.3;  // device height above the floor while walking

Material mat(const char* name, float refl, float r, float g, float b, TextureId tex, float scale) {
    return Material{name, refl, {r, g, b}, tex, scale};
}

// Common palette of indoor materials.
struct Palette {
    std::uint16_t wall, wall_alt, floor, ceiling, wood, metal, black, poster, checker, shelf;
    explicit Palette(MeshBuilder& b)
        : wall(
              b.addMaterial(mat("plaster", 0.80f, 0.85f, 0.82f, 0.74f, TextureId::kPlaster, 2.0f))),
          wall_alt(
              b.addMaterial(mat("brick", 0.45f, 0.62f, 0.34f, 0.26f, TextureId::kBrick, 1.2f))),
          floor(b.addMaterial(mat("carpet", 0.25f, 0.35f, 0.38f, 0.45f, TextureId::kCarpet, 1.0f))),
          ceiling(
              b.addMaterial(mat("ceiling", 0.85f, 0.92f, 0.92f, 0.90f, TextureId::kChecker, 1.2f))),
          wood(b.addMaterial(mat("wood", 0.55f, 0.62f, 0.45f, 0.30f, TextureId::kWood, 0.8f))),
          metal(
              b.addMaterial(mat("metal", 0.60f, 0.55f, 0.57f, 0.60f, TextureId::kConcrete, 0.5f))),
          black(b.addMaterial(
              mat("black plastic", 0.03f, 0.05f, 0.05f, 0.06f, TextureId::kPlain, 1.0f))),
          poster(b.addMaterial(mat("poster", 0.70f, 1.0f, 1.0f, 1.0f, TextureId::kPosters, 0.9f))),
          checker(b.addMaterial(
              mat("checkerboard", 0.65f, 1.0f, 1.0f, 1.0f, TextureId::kChecker, 0.5f))),
          shelf(b.addMaterial(mat("books", 0.50f, 0.9f, 0.85f, 0.8f, TextureId::kPosters, 0.35f))) {
    }
};

// A poster 1 cm in front of a wall face: centre c, outward normal n (horizontal), size w x h.
void poster(MeshBuilder& b, const Vector3d& c, const Vector3d& n, double w, double h,
            std::uint16_t m) {
    const Vector3d side = Vector3d::UnitZ().cross(n).normalized();
    const Vector3d p = c + 0.01 * n;
    const Vector3d up = Vector3d::UnitZ();
    b.addQuad(p - side * w / 2 - up * h / 2, p + side * w / 2 - up * h / 2,
              p + side * w / 2 + up * h / 2, p - side * w / 2 + up * h / 2, m);
}

// Whatever `build` adds is one movable object of the scene (scene_change.hpp).
template <typename Build>
void object(MeshBuilder& b, const char* name, Build&& build) {
    b.beginObject(name);
    build();
    b.endObject();
}

// A table: top plus four legs.
void table(MeshBuilder& b, const Vector2d& lo, const Vector2d& hi, double z0, double height,
           std::uint16_t top, std::uint16_t legs) {
    b.addBox(Vector3d(lo.x(), lo.y(), z0 + height - 0.04), Vector3d(hi.x(), hi.y(), z0 + height),
             top);
    const double r = 0.025, in = 0.06;
    for (const Vector2d& p :
         {Vector2d(lo.x() + in, lo.y() + in), Vector2d(hi.x() - in, lo.y() + in),
          Vector2d(lo.x() + in, hi.y() - in), Vector2d(hi.x() - in, hi.y() - in)}) {
        b.addCylinder(Vector3d(p.x(), p.y(), z0), Vector3d(p.x(), p.y(), z0 + height - 0.04), r, 8,
                      legs);
    }
}

// A chair: seat, back and legs.
void chair(MeshBuilder& b, const Vector2d& c, double yaw, double z0, std::uint16_t seat,
           std::uint16_t legs) {
    const Eigen::Rotation2Dd R(yaw);
    auto P = [&](double x, double y, double z) {
        const Vector2d q = c + R * Vector2d(x, y);
        return Vector3d(q.x(), q.y(), z0 + z);
    };
    b.addQuad(P(-0.22, -0.22, 0.45), P(0.22, -0.22, 0.45), P(0.22, 0.22, 0.45),
              P(-0.22, 0.22, 0.45), seat);
    b.addQuad(P(-0.22, 0.22, 0.45), P(0.22, 0.22, 0.45), P(0.22, 0.24, 0.9), P(-0.22, 0.24, 0.9),
              seat);
    for (const auto& xy :
         {Vector2d(-0.2, -0.2), Vector2d(0.2, -0.2), Vector2d(-0.2, 0.2), Vector2d(0.2, 0.2)}) {
        b.addCylinder(P(xy.x(), xy.y(), 0.0), P(xy.x(), xy.y(), 0.45), 0.015, 6, legs);
    }
}

// Floor slab with rectangular holes (stairwells), built as strips between the holes.
void slabWithHoles(MeshBuilder& b, const Vector2d& lo, const Vector2d& hi, double z0, double z1,
                   const std::vector<std::pair<Vector2d, Vector2d>>& holes, std::uint16_t m) {
    // Split along x at hole edges; inside each x-strip, split along y.
    std::vector<double> xs{lo.x(), hi.x()};
    for (const auto& h : holes) {
        xs.push_back(h.first.x());
        xs.push_back(h.second.x());
    }
    std::sort(xs.begin(), xs.end());
    for (std::size_t i = 0; i + 1 < xs.size(); ++i) {
        const double x0 = xs[i], x1 = xs[i + 1];
        if (x1 - x0 < 1e-6) continue;
        const double xm = 0.5 * (x0 + x1);
        std::vector<std::pair<double, double>> cuts;
        for (const auto& h : holes)
            if (xm > h.first.x() && xm < h.second.x()) cuts.emplace_back(h.first.y(), h.second.y());
        std::sort(cuts.begin(), cuts.end());
        double y = lo.y();
        for (const auto& c : cuts) {
            if (c.first > y) b.addBox(Vector3d(x0, y, z0), Vector3d(x1, c.first, z1), m);
            y = std::max(y, c.second);
        }
        if (hi.y() > y) b.addBox(Vector3d(x0, y, z0), Vector3d(x1, hi.y(), z1), m);
    }
}

// Points of a racetrack loop (two straights joined by semicircles), counter-clockwise.
std::vector<Vector3d> racetrack(const Vector2d& c0, const Vector2d& c1, double radius, double z,
                                int arc_points) {
    std::vector<Vector3d> pts;
    const Vector2d d = (c1 - c0).normalized();
    const double a0 = std::atan2(d.y(), d.x());
    for (int k = 0; k <= arc_points; ++k) {  // around c1, from the right side to the left side
        const double a = a0 - std::numbers::pi / 2 + std::numbers::pi * k / arc_points;
        pts.emplace_back(c1.x() + radius * std::cos(a), c1.y() + radius * std::sin(a), z);
    }
    for (int k = 0; k <= arc_points; ++k) {
        const double a = a0 + std::numbers::pi / 2 + std::numbers::pi * k / arc_points;
        pts.emplace_back(c0.x() + radius * std::cos(a), c0.y() + radius * std::sin(a), z);
    }
    return pts;
}

Scene office() {
    Scene s;
    s.world.name = "office";
    MeshBuilder b(s.world);
    Palette p(b);
    const double H = 3.0, T = 0.15;
    b.addBox(Vector3d(-0.5, -0.5, -0.1), Vector3d(20.5, 12.5, 0.0), p.floor);
    b.addBox(Vector3d(-0.5, -0.5, H), Vector3d(20.5, 12.5, H + 0.1), p.ceiling);
    // Outer walls (windows in the south and north facades look out into nothing: no returns).
    b.addWall({0, 0}, {20, 0}, T, 0, H, {{2, 3.5, 0.9, 2.2}, {12, 14, 0.9, 2.2}}, p.wall);
    b.addWall({20, 0}, {20, 12}, T, 0, H, {}, p.wall_alt);
    b.addWall({20, 12}, {0, 12}, T, 0, H, {{4, 6, 0.9, 2.2}}, p.wall);
    b.addWall({0, 12}, {0, 0}, T, 0, H, {}, p.wall_alt);
    // Corridor (y 5..7) walls with doors; room dividers.
    b.addWall({0, 5}, {20, 5}, T, 0, H, {{3.0, 4.0}, {16.0, 17.0}}, p.wall);
    b.addWall({0, 7}, {20, 7}, T, 0, H, {{3.0, 4.0}, {10.0, 11.0}, {16.0, 17.0}}, p.wall);
    b.addWall({10, 0}, {10, 5}, T, 0, H, {{2.0, 3.0}}, p.wall);
    b.addWall({7, 7}, {7, 12}, T, 0, H, {}, p.wall);
    b.addWall({14, 7}, {14, 12}, T, 0, H, {}, p.wall);
    // Posters and a calibration board along the corridor and in the rooms.
    // (Posters only where the wall is solid: none across a door.)
    for (double x : {1.5, 6.0, 8.5, 12.5, 14.6, 18.7})
        poster(b, {x, 5.0 + T / 2, 1.6}, {0, 1, 0}, 0.7, 1.0, p.poster);
    for (double x : {2.0, 5.5, 8.2, 12.8, 14.9, 18.5})
        poster(b, {x, 7.0 - T / 2, 1.5}, {0, -1, 0}, 0.6, 0.85, p.poster);
    poster(b, {19.9 - T / 2, 6.0, 1.5}, {-1, 0, 0}, 0.9, 0.9, p.checker);
    poster(b, {5.0, 0.0 + T / 2, 1.7}, {0, 1, 0}, 1.2, 0.8, p.poster);
    poster(b, {15.0, 12.0 - T / 2, 1.6}, {0, -1, 0}, 1.0, 0.7, p.poster);
    poster(b, {7.0 + T / 2, 9.5, 1.5}, {1, 0, 0}, 1.4, 0.9, p.poster);
    // South-west room (0..10 x 0..5): desks with monitors, chairs, a cabinet, a bookshelf.
    for (double x : {1.0, 6.5}) {
        object(b, "desk", [&] {
            table(b, {x, 0.2}, {x + 1.6, 1.0}, 0, 0.75, p.wood, p.metal);
            b.addBox(Vector3d(x + 0.5, 0.35, 0.75), Vector3d(x + 1.1, 0.4, 1.15),
                     p.black);  // monitor
        });
        object(b, "chair", [&] { chair(b, {x + 0.8, 1.4}, 0.1, 0, p.black, p.metal); });
    }
    object(b, "bookshelf",
           [&] { b.addBox(Vector3d(0.2, 3.3, 0), Vector3d(0.65, 4.8, 1.9), p.shelf); });
    object(b, "cabinet",
           [&] { b.addBox(Vector3d(8.5, 4.2, 0), Vector3d(9.8, 4.8, 1.1), p.metal); });
    // South-east room (10..20 x 0..5): meeting table and chairs south of the walking line.
    object(b, "meeting table", [&] {
        table(b, {12.5, 0.4}, {17.0, 1.5}, 0, 0.74, p.wood, p.metal);
    });
    for (double x = 13.0; x < 17.0; x += 0.9)
        object(b, "chair", [&] { chair(b, {x, 1.75}, std::numbers::pi, 0, p.black, p.metal); });
    object(b, "bookshelf",
           [&] { b.addBox(Vector3d(19.3, 3.4, 0), Vector3d(19.8, 4.8, 2.0), p.shelf); });
    object(b, "sideboard",
           [&] { b.addBox(Vector3d(10.2, 3.8, 0), Vector3d(11.5, 4.8, 0.9), p.wood); });
    // North rooms: a central table in the middle one (walked around), desks in the others.
    object(b, "table", [&] { table(b, {9.9, 9.25}, {11.1, 9.95}, 0, 0.75, p.wood, p.metal); });
    object(b, "chair", [&] { chair(b, {10.5, 9.0}, 0.0, 0, p.black, p.metal); });
    object(b, "desk", [&] { table(b, {0.3, 10.8}, {2.3, 11.7}, 0, 0.75, p.wood, p.metal); });
    object(b, "bookshelf",
           [&] { b.addBox(Vector3d(4.0, 11.3, 0), Vector3d(6.5, 11.8, 2.1), p.shelf); });
    object(b, "desk", [&] {
        table(b, {15.5, 10.9}, {18.5, 11.7}, 0, 0.75, p.wood, p.metal);
        b.addBox(Vector3d(16.5, 11.35, 0.75), Vector3d(17.2, 11.4, 1.15), p.black);
    });
    object(b, "cabinet",
           [&] { b.addBox(Vector3d(19.2, 7.3, 0), Vector3d(19.8, 8.8, 1.2), p.metal); });
    // Walking loop: corridor west, room SW through door A, door C into SE, door B back into the
    // corridor, north into the middle room around its table, back out and west to the start.
    for (const Vector2d& q :
         {Vector2d(6.0, 6.0), Vector2d(3.5, 6.0), Vector2d(3.5, 4.2), Vector2d(4.5, 2.6),
          Vector2d(8.8, 2.5), Vector2d(11.2, 2.5), Vector2d(15.5, 2.6), Vector2d(16.5, 3.8),
          Vector2d(16.5, 6.0), Vector2d(13.0, 6.0), Vector2d(10.5, 6.0), Vector2d(10.5, 8.3),
          Vector2d(12.3, 9.6), Vector2d(10.5, 11.0), Vector2d(8.7, 9.6), Vector2d(10.5, 8.3),
          Vector2d(10.5, 6.0)}) {
        s.walk_loop.emplace_back(q.x(), q.y(), kHand);
    }
    s.world.description =
        "office floor: corridor, five rooms, doors, desks, chairs, shelves, posters";
    return s;
}

Scene house() {
    Scene s;
    s.world.name = "house";
    MeshBuilder b(s.world);
    Palette p(b);
    const double T = 0.15, storey = 3.0, slab = 0.2;
    const double W = 12.0, D = 9.0;
    const std::pair<Vector2d, Vector2d> holeA{{0.3, 1.6}, {1.7, 6.4}},
        holeB{{10.3, 2.6}, {11.7, 7.2}}, holeC{{3.8, 7.95}, {8.4, 8.95}};
    b.addBox(Vector3d(-0.3, -0.3, -0.1), Vector3d(W + 0.3, D + 0.3, 0.0), p.floor);
    slabWithHoles(b, {-0.3, -0.3}, {W + 0.3, D + 0.3}, storey - slab, storey, {holeA, holeB},
                  p.floor);
    slabWithHoles(b, {-0.3, -0.3}, {W + 0.3, D + 0.3}, 2 * storey - slab, 2 * storey, {holeC},
                  p.floor);
    slabWithHoles(b, {-0.3, -0.3}, {W + 0.3, D + 0.3}, 3 * storey - slab, 3 * storey, {},
                  p.ceiling);
    for (int level = 0; level < 3; ++level) {
        const double z0 = level * storey, h = storey - (level == 0 ? slab : slab);
        b.addWall({0, 0}, {W, 0}, T, z0, h, {{4, 5.5, 0.9, 2.1}, {8, 9.5, 0.9, 2.1}}, p.wall);
        b.addWall({W, 0}, {W, D}, T, z0, h, {}, level == 0 ? p.wall_alt : p.wall);
        b.addWall({W, D}, {0, D}, T, z0, h, {{5, 6.5, 0.9, 2.1}}, p.wall);
        b.addWall({0, D}, {0, 0}, T, z0, h, {}, level == 0 ? p.wall_alt : p.wall);
    }
    // Ground floor: a partition with a door, sofa, table, shelf.
    b.addWall({2.0, 4.5}, {9.8, 4.5}, T, 0, storey - slab, {{3.0, 4.0}}, p.wall);
    object(b, "sofa", [&] { b.addBox(Vector3d(7.0, 0.3, 0), Vector3d(9.0, 1.1, 0.8), p.black); });
    object(b, "table", [&] { table(b, {2.5, 6.0}, {3.7, 7.0}, 0, 0.75, p.wood, p.metal); });
    object(b, "chair", [&] { chair(b, {3.1, 7.35}, 0, 0, p.wood, p.metal); });
    object(b, "bookshelf",
           [&] { b.addBox(Vector3d(0.2, 7.3, 0), Vector3d(0.6, 8.8, 2.0), p.shelf); });
    poster(b, {7.5, 4.5 - T / 2, 1.5}, {0, -1, 0}, 0.8, 0.6, p.poster);
    poster(b, {8.5, 4.5 + T / 2, 1.5}, {0, 1, 0}, 0.8, 0.6, p.poster);
    poster(b, {W - T / 2, 2.5, 1.5}, {-1, 0, 0}, 1.0, 0.7, p.checker);
    // Stairs: A along the west wall climbing +y, B along the east wall climbing -y.
    b.addStairs({1.0, 2.0, 0.0}, {0, 1}, 1.0, 15, 0.2, 0.28, p.wood);
    b.addStairs({11.0, 7.0, 0.0}, {0, -1}, 1.0, 15, 0.2, 0.28, p.wood);
    // First floor: partition, bed, desk, posters.
    b.addWall({6.0, 0}, {6.0, 5.5}, T, storey, storey - slab, {}, p.wall);
    object(b, "bed", [&] {
        b.addBox(Vector3d(2.5, 0.4, storey), Vector3d(4.5, 2.4, storey + 0.5), p.poster);
    });
    object(b, "desk", [&] {
        table(b, {7.0, 0.3}, {8.4, 1.0}, storey, 0.75, p.wood, p.metal);
        b.addBox(Vector3d(7.4, 0.45, storey + 0.75), Vector3d(8.0, 0.5, storey + 1.15), p.black);
    });
    poster(b, {3.0, D - T / 2, storey + 1.5}, {0, -1, 0}, 1.2, 0.8, p.poster);
    poster(b, {6.0 + T / 2, 3.0, storey + 1.5}, {1, 0, 0}, 0.9, 0.7, p.poster);
    // Stairs C from the first to the second floor along the north wall, climbing -x.
    b.addStairs({8.2, 8.45, storey}, {-1, 0}, 0.9, 15, 0.2, 0.28, p.wood);
    // Second floor (under the roof): a partition, a table, a shelf, posters.
    b.addWall({0, 4.0}, {7.0, 4.0}, T, 2 * storey, storey - slab, {{2.0, 3.0}}, p.wall);
    object(b, "table", [&] {
        table(b, {8.5, 2.0}, {10.0, 3.0}, 2 * storey, 0.75, p.wood, p.metal);
    });
    object(b, "bookshelf", [&] {
        b.addBox(Vector3d(11.4, 4.0, 2 * storey), Vector3d(11.8, 6.0, 2 * storey + 1.9), p.shelf);
    });
    poster(b, {W - T / 2, 7.0, 2 * storey + 1.5}, {-1, 0, 0}, 1.0, 0.8, p.poster);
    poster(b, {3.5, 4.0 + T / 2, 2 * storey + 1.5}, {0, 1, 0}, 0.8, 0.8, p.poster);
    // Loop: up stairs A, across the first floor, down stairs B, back through the partition door.
    const double up = storey + kHand;
    for (const Vector3d& q :
         {Vector3d(3.0, 1.15, kHand), Vector3d(1.0, 1.1, kHand), Vector3d(1.0, 2.0, kHand),
          Vector3d(1.0, 6.2, up), Vector3d(1.0, 7.2, up), Vector3d(3.0, 7.0, up),
          Vector3d(7.0, 6.9, up), Vector3d(8.8, 5.0, up), Vector3d(9.6, 1.6, up),
          Vector3d(11.0, 1.4, up), Vector3d(11.0, 2.8, up), Vector3d(11.0, 7.0, kHand),
          Vector3d(11.0, 7.9, kHand), Vector3d(8.5, 8.0, kHand), Vector3d(5.5, 6.5, kHand),
          Vector3d(5.5, 3.2, kHand), Vector3d(4.5, 1.6, kHand)}) {
        s.walk_loop.push_back(q);
    }
    s.world.description =
        "three-storey house: rooms, three staircases, furniture (the loop climbs one stair, "
        "descends another)";
    return s;
}

Scene corridor() {
    Scene s;
    s.world.name = "corridor";
    MeshBuilder b(s.world);
    Palette p(b);
    const double L = 50.0, hw = 1.1, H = 2.7, T = 0.15;
    b.addBox(Vector3d(-4.5, -3, -0.1), Vector3d(L + 4.5, 3, 0), p.floor);
    b.addBox(Vector3d(-4.5, -3, H), Vector3d(L + 4.5, 3, H + 0.1), p.ceiling);
    // Corridor walls with a door recess every 8 m, alternating sides; lobbies at both ends.
    std::vector<WallOpening> south, north;
    for (double x = 4.0; x < L - 2; x += 8.0) south.push_back({x, x + 0.9, 0, 2.05});
    for (double x = 8.0; x < L - 2; x += 8.0) north.push_back({x, x + 0.9, 0, 2.05});
    b.addWall({0, -hw}, {L, -hw}, T, 0, H, south, p.wall);
    b.addWall({L, hw}, {0, hw}, T, 0, H, {}, p.wall);
    for (const auto& o : south)
        b.addBox(Vector3d(o.from_m, -hw - 0.25, 0), Vector3d(o.to_m, -hw - 0.2, 2.05), p.wood);
    for (const auto& o : north)
        b.addBox(Vector3d(L - o.to_m, hw - 0.07, 0), Vector3d(L - o.from_m, hw - 0.02, 2.05),
                 p.wood);
    for (double sx : {-1.0, 1.0}) {
        const double x0 = sx < 0 ? -4.0 : L, x1 = sx < 0 ? 0.0 : L + 4.0;
        b.addWall({x0, -2.5}, {x1, -2.5}, T, 0, H, {}, p.wall);
        b.addWall({x1, 2.5}, {x0, 2.5}, T, 0, H, {}, p.wall);
        const double xe = sx < 0 ? x0 : x1;
        b.addWall({xe, -2.5}, {xe, 2.5}, T, 0, H, {}, p.wall_alt);
        b.addWall({sx < 0 ? 0.0 : L, -2.5}, {sx < 0 ? 0.0 : L, -hw}, T, 0, H, {}, p.wall);
        b.addWall({sx < 0 ? 0.0 : L, hw}, {sx < 0 ? 0.0 : L, 2.5}, T, 0, H, {}, p.wall);
    }
    poster(b, {-4.0 + T / 2, 0.0, 1.5}, {1, 0, 0}, 1.0, 0.8, p.poster);
    poster(b, {L + 4.0 - T / 2, 0.0, 1.5}, {-1, 0, 0}, 1.0, 0.8, p.poster);
    poster(b, {L / 2, -hw + T / 2, 1.5}, {0, 1, 0}, 0.6, 0.8, p.poster);
    // Lanes at y = -+0.45 along the corridor, U-turns inside the lobbies.
    for (const Vector2d& q :
         {Vector2d(25.0, -0.45), Vector2d(50.8, -0.45), Vector2d(52.2, -1.2), Vector2d(53.2, 0.0),
          Vector2d(52.2, 1.2), Vector2d(50.8, 0.45), Vector2d(-0.8, 0.45), Vector2d(-2.2, 1.2),
          Vector2d(-3.2, 0.0), Vector2d(-2.2, -1.2), Vector2d(-0.8, -0.45)}) {
        s.walk_loop.emplace_back(q.x(), q.y(), kHand);
    }
    s.world.description =
        "50 m corridor, 2.2 m wide, plain walls, a few door recesses, lobbies at the ends";
    return s;
}

// A tree: trunk, recursively forking thin branches above 1.9 m, leaves at the tips.
void tree(MeshBuilder& b, Rng& rng, const Vector3d& base, std::uint16_t bark, std::uint16_t leaf) {
    const double trunk_h = rng.uniform(1.9, 2.6);
    const double r0 = rng.uniform(0.12, 0.2);
    const Vector3d top = base + Vector3d(0, 0, trunk_h);
    b.addCylinder(base, top, r0, 10, bark);
    struct Branch {
        Vector3d from, dir;
        double length, radius;
        int depth;
    };
    std::vector<Branch> stack;
    const int main_branches = 4 + static_cast<int>(rng.below(3));
    for (int i = 0; i < main_branches; ++i) {
        const double az = 2 * std::numbers::pi * (i + rng.uniform(0, 0.6)) / main_branches;
        const double el = rng.uniform(0.5, 1.1);
        stack.push_back(
            {top, Vector3d(std::cos(az) * std::cos(el), std::sin(az) * std::cos(el), std::sin(el)),
             rng.uniform(1.0, 1.6), r0 * 0.5, 0});
    }
    while (!stack.empty()) {
        const Branch br = stack.back();
        stack.pop_back();
        const Vector3d end = br.from + br.dir * br.length;
        b.addCylinder(br.from, end, br.radius, br.depth < 1 ? 6 : 4, bark);
        if (br.depth < 3) {
            const int forks = 2 + static_cast<int>(rng.below(2));
            for (int k = 0; k < forks; ++k) {
                Vector3d d =
                    br.dir + Vector3d(rng.gauss(0.5), rng.gauss(0.5), rng.gauss(0.3) + 0.15);
                d.normalize();
                stack.push_back(
                    {end, d, br.length * rng.uniform(0.55, 0.75), br.radius * 0.6, br.depth + 1});
            }
        } else {
            for (int k = 0; k < 36; ++k) {
                const Vector3d c = end + Vector3d(rng.gauss(0.3), rng.gauss(0.3), rng.gauss(0.2));
                const Vector3d n =
                    Vector3d(rng.gauss(), rng.gauss(), rng.gauss() + 1.0).normalized();
                b.addLeaf(c, n, n.unitOrthogonal(), rng.uniform(0.07, 0.14),
                          rng.uniform(0.04, 0.07), leaf);
            }
        }
    }
}

// A bush: a cluster of leaves and twigs below 1 m.
void bush(MeshBuilder& b, Rng& rng, const Vector3d& c, std::uint16_t twig, std::uint16_t leaf) {
    for (int k = 0; k < 6; ++k) {
        const Vector3d d = Vector3d(rng.gauss(0.4), rng.gauss(0.4), 1.0).normalized();
        b.addCylinder(c - Vector3d(0, 0, c.z()), c + d * 0.4, 0.01, 4, twig);
    }
    for (int k = 0; k < 150; ++k) {
        const Vector3d q = c + Vector3d(rng.gauss(0.3), rng.gauss(0.3), rng.gauss(0.2));
        if (q.z() < 0.05) continue;
        const Vector3d n = Vector3d(rng.gauss(), rng.gauss(), rng.gauss() + 0.5).normalized();
        b.addLeaf(q, n, n.unitOrthogonal(), rng.uniform(0.05, 0.1), rng.uniform(0.03, 0.05), leaf);
    }
}

Scene courtyard() {
    Scene s;
    s.world.name = "courtyard";
    MeshBuilder b(s.world);
    Palette p(b);
    Rng rng(20260401, "courtyard");
    const std::uint16_t paving =
        b.addMaterial(mat("paving", 0.35f, 0.55f, 0.52f, 0.48f, TextureId::kConcrete, 1.5f));
    const std::uint16_t lawn =
        b.addMaterial(mat("lawn", 0.30f, 0.25f, 0.45f, 0.18f, TextureId::kGrass, 1.0f));
    const std::uint16_t bark =
        b.addMaterial(mat("bark", 0.25f, 0.35f, 0.27f, 0.2f, TextureId::kBark, 0.6f));
    const std::uint16_t leaf =
        b.addMaterial(mat("leaf", 0.45f, 0.2f, 0.5f, 0.15f, TextureId::kFoliage, 0.3f));
    const double W = 30.0, D = 24.0, H = 8.0, T = 0.3;
    b.addBox(Vector3d(-1, -1, -0.1), Vector3d(W + 1, D + 1, 0), paving);
    b.addBox(Vector3d(9, 9, 0), Vector3d(21, 15, 0.02), lawn);
    std::vector<WallOpening> windows;
    for (double x = 1.5; x < W - 2; x += 3.0) {
        windows.push_back({x, x + 1.4, 1.0, 2.4});
    }
    std::vector<WallOpening> upper = windows;
    for (auto& w : upper) {
        w.bottom_m = 4.0;
        w.top_m = 5.6;
    }
    windows.insert(windows.end(), upper.begin(), upper.end());
    b.addWall({0, 0}, {W, 0}, T, 0, H, windows, p.wall_alt);
    b.addWall({W, D}, {0, D}, T, 0, H, windows, p.wall_alt);
    b.addWall({W, 0}, {W, D}, T, 0, H, {}, p.wall);
    b.addWall({0, D}, {0, 0}, T, 0, H, {{10, 12.5, 0, 3.0}}, p.wall);
    // Trees inside the loop (on the lawn) and between the loop and the facades; bushes.
    for (const Vector2d& q :
         {Vector2d(11, 11), Vector2d(15, 12.5), Vector2d(19, 11), Vector2d(13, 14),
          Vector2d(17.5, 14), Vector2d(3, 3), Vector2d(27, 3), Vector2d(3, 21), Vector2d(27, 21),
          Vector2d(15, 2.5), Vector2d(15, 21.5), Vector2d(27.5, 12)}) {
        tree(b, rng, Vector3d(q.x(), q.y(), 0), bark, leaf);
    }
    for (const Vector2d& q :
         {Vector2d(10, 13), Vector2d(20, 13.5), Vector2d(14, 10), Vector2d(2.5, 12), Vector2d(8, 2),
          Vector2d(22, 22.5), Vector2d(22, 2)}) {
        object(b, "bush", [&] { bush(b, rng, Vector3d(q.x(), q.y(), 0.5), bark, leaf); });
    }
    for (double x = 9.5; x < 21; x += 2.5)
        object(b, "bench",
               [&] { b.addBox(Vector3d(x, 8.2, 0), Vector3d(x + 1.6, 8.6, 0.45), p.wood); });
    // Loop around the lawn.
    for (const Vector2d& q :
         {Vector2d(12, 6.5), Vector2d(24, 6.5), Vector2d(24.5, 12), Vector2d(24, 17.5),
          Vector2d(6, 17.5), Vector2d(5.5, 12), Vector2d(6, 6.5)}) {
        s.walk_loop.emplace_back(q.x(), q.y(), kHand);
    }
    s.world.description =
        "courtyard with trees (thin branches, leaves), bushes, benches and facades";
    return s;
}

Scene tunnel() {
    Scene s;
    s.world.name = "tunnel";
    MeshBuilder b(s.world);
    const std::uint16_t concrete =
        b.addMaterial(mat("shotcrete", 0.4f, 0.55f, 0.53f, 0.5f, TextureId::kConcrete, 3.0f));
    const std::uint16_t road =
        b.addMaterial(mat("floor", 0.2f, 0.3f, 0.3f, 0.3f, TextureId::kPlaster, 2.0f));
    const double L = 120.0, half_w = 3.0, wall_h = 2.0, R = 3.0;
    // Horseshoe cross-section: vertical walls to wall_h, then a semicircular vault, floor.
    std::vector<Vector2d> section;  // (y, z)
    section.emplace_back(-half_w, 0.0);
    for (int k = 0; k <= 24; ++k) {
        const double a = std::numbers::pi * k / 24.0;
        section.emplace_back(-R * std::cos(a), wall_h + R * std::sin(a));
    }
    section.emplace_back(half_w, 0.0);
    const int segs = 60;
    for (int i = 0; i < segs; ++i) {
        const double x0 = -5.0 + (L + 10.0) * i / segs, x1 = -5.0 + (L + 10.0) * (i + 1) / segs;
        for (std::size_t k = 0; k + 1 < section.size(); ++k) {
            const Vector2d& a = section[k];
            const Vector2d& c = section[k + 1];
            b.addQuad({x0, a.x(), a.y()}, {x1, a.x(), a.y()}, {x1, c.x(), c.y()},
                      {x0, c.x(), c.y()}, concrete);
        }
        b.addQuad({x0, -half_w, 0.0}, {x0, half_w, 0.0}, {x1, half_w, 0.0}, {x1, -half_w, 0.0},
                  road);
    }
    for (const Vector3d& q : racetrack({5.0, 0.0}, {60.0, 0.0}, 1.3, kHand, 10))
        s.walk_loop.push_back(q);
    s.world.description =
        "120 m straight smooth tunnel (horseshoe section): laser degeneracy along its axis";
    return s;
}

Scene field() {
    Scene s;
    s.world.name = "field";
    MeshBuilder b(s.world);
    const std::uint16_t grass =
        b.addMaterial(mat("grass", 0.3f, 0.3f, 0.5f, 0.2f, TextureId::kGrass, 1.0f));
    const int n = 20;
    const double half = 200.0;
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            const double x0 = -half + 2 * half * i / n, x1 = -half + 2 * half * (i + 1) / n;
            const double y0 = -half + 2 * half * j / n, y1 = -half + 2 * half * (j + 1) / n;
            b.addQuad({x0, y0, 0}, {x1, y0, 0}, {x1, y1, 0}, {x0, y1, 0}, grass);
        }
    }
    for (const Vector3d& q : racetrack({0.0, 0.0}, {25.0, 0.0}, 6.0, kHand, 12))
        s.walk_loop.push_back(q);
    s.world.description = "flat open grass field, 400 m square, nothing else: laser degeneracy";
    return s;
}

}  // namespace

const std::vector<SceneInfo>& sceneCatalogue() {
    static const std::vector<SceneInfo> kScenes = [] {
        std::vector<SceneInfo> v;
        for (const char* name : {"office", "house", "corridor", "courtyard", "tunnel", "field"}) {
            const Scene sc = buildScene(name);
            v.push_back({sc.world.name, sc.world.description});
        }
        return v;
    }();
    return kScenes;
}

Scene buildScene(const std::string& name) {
    if (name == "office") return office();
    if (name == "house") return house();
    if (name == "corridor") return corridor();
    if (name == "courtyard") return courtyard();
    if (name == "tunnel") return tunnel();
    if (name == "field") return field();
    throw std::invalid_argument(
        "unknown scene '" + name +
        "': expected one of office, house, corridor, courtyard, tunnel, field "
        "(or an .obj file path)");
}

}  // namespace handscan::sim
