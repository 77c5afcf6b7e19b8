// Writes a calibration.yaml that loadCalibration() reads as is: the transforms as translation and
// roll-pitch-yaw (R = Rz(y) Ry(p) Rx(r), degrees, enough digits to round-trip), the encoder zero,
// the time offsets that are known (`time_offsets`, which replace device.yaml's latencies), the
// camchain path made relative to the new file, and the calibration's story as comments.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/status.hpp"

namespace handscan::calibrate {

// `camchain`: the camchain file's path (absolute or relative to the working directory), or empty.
// `comments`: lines written at the top, each prefixed with "# ".
[[nodiscard]] Status writeCalibrationYaml(const std::string& path, const Calibration& calibration,
                                          const std::string& camchain,
                                          const std::vector<std::string>& comments);

// The camchain file a calibration.yaml names, resolved against that file's folder ("" if none).
std::string camchainPathOf(const std::string& calibration_yaml);

}  // namespace handscan::calibrate
