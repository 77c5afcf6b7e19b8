// EarlierScan: a scan on the device's storage that a new one continues ("continue scan",
// section 9): its feature map in voxels (what the localizer matches to), and what the touch
// screen shows of it while the new scan finds its place and after (its map thinned to the display
// map's 5 cm voxels, its trajectory). Loaded off the pipeline thread (the command handler's),
// then handed to it whole.
//
// The command's argument, "scan=NAME pose=x,y,z,qx,qy,qz,qw" (both optional, any order): which
// scan (a directory under the journal root) and where the operator stands on its map.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/localize/prior_map.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::pipeline_daemon {

struct EarlierScan {
    std::string dir;
    std::shared_ptr<const localize::PriorMap> prior;
    std::vector<shm::DisplayPoint> display;           // one point per display voxel
    std::vector<journal::TrajectoryPose> trajectory;  // as journaled
};

struct ContinueRequest {
    std::string scan;                               // a directory name under the journal root
    std::optional<Eigen::Isometry3d> initial_pose;  // in that scan's frame
};

// Parses the continue command's argument; errors name the token and the form expected.
Result<ContinueRequest> parseContinueArgument(const std::string& argument);

// The directory of `journal_root` holding the newest scan that can be continued (one with a
// journal; its feature map, if it has none, is made from the journal's points), or kNotFound.
Result<std::string> newestContinuableScan(const std::string& journal_root);
bool canContinue(const std::string& scan_dir);
// The scans of `journal_root` that can be continued, newest first, for the touch screen's picker
// (at most shm::kMaxListedScans; `total` counts them all). `own_dir`: the daemon's current scan,
// marked `current` when it is stopped (its map is on the screen), left out while it is scanning.
shm::ScanList continuableScans(const std::string& journal_root, const std::string& own_dir,
                               bool own_scanning);

Result<std::shared_ptr<const EarlierScan>> loadEarlierScan(const std::string& scan_dir);

}  // namespace handscan::pipeline_daemon
