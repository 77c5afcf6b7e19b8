// MotionOverride: a motion the laser-inertial odometry is told to use in place of its own IMU
// prediction. It is how a tool measures the scan matcher and the map alone, apart from the
// prediction (`handscan replay --reference-motion GT.tum`: the ground truth, see
// replay::ReferenceMotion). The estimator knows nothing of where the motion comes from; the
// device never sets one.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "handscan/core/time.hpp"
#include "handscan/scan/scan_matcher.hpp"
#include "handscan/scan/sweep.hpp"

namespace handscan::lio {

class MotionOverride {
public:
    virtual ~MotionOverride() = default;
    // The body pose at t: places every laser step while a sweep is assembled, and stands in for
    // the visual-inertial pose of section 7 in the 200 Hz output (the last match carried forward
    // by its increments). Defined for any t of the input.
    virtual Eigen::Isometry3d poseAt(TimeNs t) const = 0;
    // The prior a sweep is matched from. `matched_before`: sweeps matched so far (0: this one
    // founds the map). With an override the matches do not correct the IMU predictor.
    virtual std::vector<scan::PosePrior> matchPrior(const scan::Sweep& sweep,
                                                    std::uint64_t matched_before) const = 0;
};

}  // namespace handscan::lio
