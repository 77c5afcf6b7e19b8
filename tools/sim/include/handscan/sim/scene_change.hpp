// Changes between two visits of the same scene (issue 14: a second session months later): some
// of the scene's movable objects (World::objects: furniture, benches, bushes) are moved and
// turned, deterministically per seed, so a localizer must hold its lock on what stayed and can
// report what changed.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "handscan/sim/scenes.hpp"

namespace handscan::sim {

struct MovedObject {
    std::string name;
    Eigen::Vector3d centre_before = Eigen::Vector3d::Zero();  // of its vertices, {W}
    Eigen::Vector3d centre_after = Eigen::Vector3d::Zero();
    double turn_deg = 0.0;  // about the vertical through its centre
};

// Moves `count` of the scene's objects (all of them when it has fewer): each is turned by
// 15-35 degrees about the vertical through its centre and shifted 0.4-0.7 m horizontally away
// from the walking loop (so the walk stays clear of it). The same seed moves the same objects
// the same way.
std::vector<MovedObject> moveObjects(Scene& scene, int count, std::uint64_t seed);

}  // namespace handscan::sim
