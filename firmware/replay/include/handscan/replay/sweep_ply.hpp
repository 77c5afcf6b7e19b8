// `handscan replay --dump-sweeps DIR`: each assembled sweep as a PLY file (the export's PLY
// writer: x y z float, rgb 0, intensity ushort, time double), in the rig (tracking camera) frame
// at the sweep's first point, so other odometry systems can be run on exactly the sweeps we
// matched. `time` is seconds of the scan clock (host CLOCK_MONOTONIC), like an export's.
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/scan/sweep.hpp"

namespace handscan::replay {

[[nodiscard]] Status writeSweepPly(const std::string& path, const scan::Sweep& sweep);

}  // namespace handscan::replay
