// The evaluation's trajectories are TUM files (firmware/tum), under the eval names.
#pragma once

#include "handscan/tum/tum_file.hpp"

namespace handscan::eval {

using tum::formatTumLine;
using tum::parseTum;
using tum::readTum;
using tum::StampedPose;
using tum::Trajectory;
using tum::writeTum;

}  // namespace handscan::eval
