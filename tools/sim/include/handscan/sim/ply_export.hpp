// Writes the world mesh as PLY (binary little-endian or ASCII) in world coordinates, with a
// per-face material index and RGB colour: the ground truth surfaces for map error.
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/sim/world.hpp"

namespace handscan::sim {

[[nodiscard]] Status writePly(const World& world, const std::string& path, bool binary = true);

}  // namespace handscan::sim
