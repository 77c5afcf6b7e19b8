// The report's module timeline: one inline SVG with a lane per direction (rx .. tz) coloured by
// the module that solved it in each sweep (scan matching blue, visual-inertial odometry green,
// the IMU prediction orange where neither did: figure 14's colours, as the touch screen's
// degeneracy bar), then the VIO's lane (running, bypassed, off), the tracking monitor's verdicts
// and lost intervals, and the laser's and the trajectory's dropouts, on the scan's time axis.
#pragma once

#include <string>

#include "handscan/report/scan_facts.hpp"

namespace handscan::report {

std::string moduleTimelineSvg(const ScanFacts& facts);

}  // namespace handscan::report
