// PLY files for sweeps and maps (binary little-endian, readable by CloudCompare, Open3D, PCL).
// A sweep file holds x y z intensity (float32) and t (float64, seconds since the sweep's first
// point) in the rig frame at the sweep's first point, so other odometry systems can be run on
// exactly the sweeps we matched (`handscan replay --dump-sweeps`).
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/scan/sweep.hpp"

namespace handscan::scan {

[[nodiscard]] Status writeSweepPly(const std::string& path, const Sweep& sweep);
// A plain x y z cloud (float32), e.g. the registered map.
[[nodiscard]] Status writeCloudPly(const std::string& path,
                                   const std::vector<Eigen::Vector3f>& points);

}  // namespace handscan::scan
