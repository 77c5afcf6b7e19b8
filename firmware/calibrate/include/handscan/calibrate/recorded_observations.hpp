// The half-revolution observations of a recording: its laser and encoder decoded (with `device`'s
// latencies, as replay does) and paired with a replayed trajectory (spin_calibration's
// pairObservations).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "handscan/spin_calibration/spin_observations.hpp"

namespace handscan::calibrate {

Result<std::vector<SpinObservation>> loadObservations(
    const std::string& recording, const DeviceConfig& device, const Calibration& base,
    const tum::Trajectory& trajectory, const std::vector<std::pair<double, double>>& excluded_s,
    const std::vector<ImuSample>& imu, const ObservationOptions& options);

}  // namespace handscan::calibrate
