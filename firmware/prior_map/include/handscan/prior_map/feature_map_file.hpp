// feature_map.hsf: a scan's edge and planar feature map (scan::FeatureMapPoints: the points the
// odometry's voxel map kept, with the laser centre that saw each planar point), in the scan's
// world frame, beside its journal, so that a later session can localize on it (section 9)
// without re-extracting features. Little-endian:
//
//   "HSFM" | u16 version (1) | u16 0 | u32 edges | u32 planars
//   | edges x f32[3] | planars x f32[3] | planars x f32[3] origins (NaN: unknown)
//   | u32 CRC-32 (zlib) of everything before it
#pragma once

#include <string>

#include "handscan/core/status.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::prior_map {

inline constexpr const char* kFeatureMapFile = "feature_map.hsf";

// Written safely (temporary name, fsync, read back, rename).
Status writeFeatureMap(const std::string& path, const scan::FeatureMapPoints& map);
// Errors name the file and what is wrong (truncated, bad magic or version, CRC mismatch).
Result<scan::FeatureMapPoints> readFeatureMap(const std::string& path);

}  // namespace handscan::prior_map
