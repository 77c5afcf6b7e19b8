// A registered sweep's points as the journal and the exports keep them (full resolution, camera
// colour where a colour image saw the point, else the laser intensity as grey), and a pose as a
// journal trajectory sample. Shared by the daemon and replay so both journal the same bytes.
#pragma once

#include <vector>

#include "handscan/colour/colouriser.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"

namespace handscan::live_output {

std::vector<journal::MapPoint> sweepMapPoints(const lio::RegisteredSweep& sweep,
                                              const colour::ColourResult* colours);
journal::TrajectoryPose trajectoryPose(const PoseEstimate& pose);

}  // namespace handscan::live_output
