// Motion compensation of an assembled sweep with the current motion estimate. The assembler
// places each step with the prediction available when its scan arrived; with IMU feedback the
// predictor is corrected while a sweep is still being assembled (the previous sweep's match
// re-integrates the IMU from that sweep's start), so a sweep would mix points placed before and
// after the correction, and its start frame would be the uncorrected one. Before matching, every
// point is placed again from its body-frame coordinates at its own time (SweepPoint::p_body) with
// one consistent motion estimate: p_start = T(t_start)^-1 T(t) p_body (section 6.1).
#pragma once

#include <Eigen/Geometry>
#include <functional>

#include "handscan/core/status.hpp"
#include "handscan/scan/sweep.hpp"

namespace handscan::lio {

// The body pose at time t, or an error when the estimate does not cover t.
using PoseQuery = std::function<Result<Eigen::Isometry3d>(TimeNs)>;

// Re-places every point of `sweep` and sets its T_world_start_odom. The motion is sampled every
// `sample_period` and interpolated per point (the IMU runs at 200 Hz; finer is pointless). On an
// error (a time the estimate does not cover) the sweep is left unchanged.
[[nodiscard]] Status recompensateSweep(scan::Sweep& sweep, const PoseQuery& pose_at,
                                       TimeNs sample_period = 2 * kNsPerMs);

}  // namespace handscan::lio
