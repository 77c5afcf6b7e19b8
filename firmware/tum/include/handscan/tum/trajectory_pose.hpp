// The pose of a TUM trajectory at any time: interpolated on SE(3) between the two poses around it,
// clamped to the first or last pose outside the trajectory. `replay --reference-motion` moves the
// sweeps with it; `handscan calibrate` places laser points with the replayed trajectory.
#pragma once

#include <Eigen/Geometry>

#include "handscan/tum/tum_file.hpp"

namespace handscan::tum {

// `trajectory` must not be empty; t_s on the trajectory's clock (seconds).
Eigen::Isometry3d poseAt(const Trajectory& trajectory, double t_s);

}  // namespace handscan::tum
