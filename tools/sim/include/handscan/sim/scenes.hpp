// The built-in procedural scenes (covering what the paper tests: structured rooms, a multi-floor
// house, a long corridor, vegetation, a smooth tunnel and a flat field) and OBJ import. Each
// built-in scene comes with a closed walking loop that stays clear of every surface: the device
// positions (metres, {W}) an operator's hand passes through, doors and stairs included.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "handscan/sim/world.hpp"

namespace handscan::sim {

struct SceneInfo {
    std::string name;
    std::string description;  // one line
};

struct Scene {
    World world;
    // Closed loop of device positions (the last point connects back to the first); smoothed into
    // a path by the trajectory generator. Empty for imported meshes.
    std::vector<Eigen::Vector3d> walk_loop;
};

// The built-in scenes, in --list-scenes order.
const std::vector<SceneInfo>& sceneCatalogue();

// Builds a built-in scene; throws std::invalid_argument naming the valid scenes otherwise.
Scene buildScene(const std::string& name);

// Imports a Wavefront OBJ (+ MTL) file as a scene: diffuse colour and texture name set each
// material's colour and texture; reflectivity is the mean diffuse colour. Throws
// std::runtime_error with the file and the parser's message on failure.
Scene importObj(const std::string& path);

}  // namespace handscan::sim
