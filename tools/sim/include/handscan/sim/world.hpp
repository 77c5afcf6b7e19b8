// The simulated world: one triangle mesh in a gravity-aligned world frame {W} (z up, metres) with
// a material per triangle. A material says how the laser sees a surface (reflectivity at 905 nm)
// and how the cameras see it (colour times a procedural texture, see textures.hpp). Scenes are
// built procedurally (scenes.hpp) or imported from OBJ (obj_import.hpp); the mesh is also the
// ground truth for map error (ply_export.hpp).
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace handscan::sim {

enum class TextureId : std::uint8_t {
    kPlain = 0,  // nearly uniform paint (few corners: realistic for walls)
    kPlaster,    // low-contrast multi-octave noise
    kConcrete,   // mid-contrast noise with speckles
    kChecker,    // high-contrast checkerboard (calibration board, tiles)
    kPosters,    // random high-contrast rectangles and blobs (posters, pin boards)
    kWood,       // stripes with grain (doors, furniture)
    kBrick,      // brick courses with mortar lines
    kCarpet,     // fine speckle
    kFoliage,    // leaves: high-frequency dark/light blobs
    kGrass,      // ground vegetation
    kBark,       // vertical streaks
    kCount
};

struct Material {
    std::string name;
    float reflectivity = 0.5f;  // diffuse reflectance at 905 nm (0 black .. 1 white)
    std::array<float, 3> colour{0.7f, 0.7f, 0.7f};  // linear RGB albedo for the cameras
    TextureId texture = TextureId::kPlain;
    float texture_scale_m = 1.0f;  // metres per texture tile
};

// A movable thing of the scene (furniture, a bench, a bush): its vertices, which no other
// primitive shares, so it can be moved between sessions (scene_change.hpp).
struct SceneObject {
    std::string name;
    std::uint32_t first_vertex = 0;
    std::uint32_t end_vertex = 0;  // one past the last
};

struct World {
    std::string name;
    std::string description;
    std::vector<Eigen::Vector3f> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::vector<std::uint16_t> triangle_material;  // index into materials, one per triangle
    std::vector<Material> materials;
    std::vector<SceneObject> objects;  // the movable ones; walls, floors and stairs are not

    std::size_t triangleCount() const { return triangles.size(); }
    // Unit normal of triangle i (right-handed winding).
    Eigen::Vector3f triangleNormal(std::size_t i) const;
    // Axis-aligned bounds of all vertices.
    void bounds(Eigen::Vector3f& lo, Eigen::Vector3f& hi) const;
};

}  // namespace handscan::sim
