// TUM trajectory files ("t tx ty tz qx qy qz qw" per line, t in seconds, '#' comments): the
// format of the ground truth the simulator writes, of `handscan replay`'s trajectory.tum and of
// `replay --reference-motion`. A file format, not evaluation: the device's tool reads it too.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::tum {

struct StampedPose {
    double t_s = 0.0;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
};

using Trajectory = std::vector<StampedPose>;

// Reads a TUM file; errors name the file and line. Poses must have increasing times.
Result<Trajectory> readTum(const std::string& path);
Result<Trajectory> parseTum(const std::string& text, const std::string& name = "<text>");
// Writes with full precision (9 decimals of seconds, 6 of metres, 9 of quaternion).
Status writeTum(const std::string& path, const Trajectory& trajectory);
std::string formatTumLine(const StampedPose& p);

}  // namespace handscan::tum
