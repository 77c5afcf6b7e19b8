// How well two sessions' maps agree where they see the same surfaces (no doubled walls): each
// sampled point of the later session is measured to the plane of its nearest neighbours in the
// earlier one (point-to-plane, so the earlier map's point spacing does not count); points with no
// neighbour within `overlap_m` (new ground, moved things) are outside the overlap.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace handscan::merge {

struct Consistency {
    std::uint64_t sampled = 0;         // later-session points tested
    std::uint64_t overlap_points = 0;  // of those, with the earlier map close by
    double median_m = 0.0;             // point-to-plane distance over the overlap
    double p90_m = 0.0;
    double mean_m = 0.0;
};

struct ConsistencyOptions {
    double overlap_m = 0.1;         // nearest earlier point farther than this: not overlapping
    int neighbours = 10;            // plane fit
    double max_thickness_m = 0.03;  // a neighbourhood thicker than this is no plane (skipped)
    std::size_t samples = 20000;    // later points tested (evenly picked)
};

Consistency measureConsistency(const std::vector<Eigen::Vector3f>& earlier,
                               const std::vector<Eigen::Vector3f>& later,
                               const ConsistencyOptions& options = {});

}  // namespace handscan::merge
