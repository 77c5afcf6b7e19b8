// An earlier scan's directory as a prior map: its feature_map.hsf (features in voxels) and where
// that scan started (the first pose of its journal's trajectory, else of trajectory.tum), the
// localizer's search centre when the new session gives no hint. `handscan replay --prior-map`
// and the daemon's "continue scan" read the same directory layout. A scan without
// feature_map.hsf is read from its journal instead (featuresFromJournal).
#pragma once

#include <memory>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/localize/prior_map.hpp"
#include "handscan/scan/voxel_map.hpp"

namespace handscan::prior_map {

Result<std::shared_ptr<const localize::PriorMap>> loadPriorMap(const std::string& scan_dir);

// A journal's points as a feature map: one planar point per planar leaf of the odometry's map
// (scan::VoxelMapConfig), each with the laser centre of the journaled pose nearest in time, and
// no edges (the journal does not say which points were edges).
Result<scan::FeatureMapPoints> featuresFromJournal(const std::string& journal_path);

// "x,y,z,qx,qy,qz,qw" (TUM order) as a pose; errors say what is wrong.
Result<Eigen::Isometry3d> parsePose(const std::string& text);

}  // namespace handscan::prior_map
