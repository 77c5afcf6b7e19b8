// Geometric features of a sweep (section 6.1): the smoothness c of eq. (12) along each scan line;
// edge points (large c) and planar points (small c) picked per sub-region of each line so they are
// spread evenly; points on the boundary of an occluded region (Figure 8, point B) and on surfaces
// nearly parallel to the beam (Figure 8, point D) are never picked.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "handscan/scan/sweep.hpp"

namespace handscan::scan {

struct FeatureConfig {
    int half_window = 5;       // |C| = 2 * half_window neighbours along the line, eq. (12)
    int regions_per_line = 6;  // sub-regions per scan line, each picks its own features
    int max_edges_per_region = 3;
    int max_planars_per_region = 30;
    // Thresholds on c in units of the line's angular step: c of eq. (12) is ~2.1 steps at a 90 deg
    // corner seen head-on and ~sigma/range on a plane, independent of the step size otherwise.
    double edge_threshold_steps = 1.5;
    double planar_threshold_steps = 0.75;
    // Range noise of the laser: on a plane c is ~ sigma / range (the centre point's noise counts
    // 2 * half_window times), so an edge must also stand `edge_noise_factor` times above that.
    double range_noise_m = 0.01;
    double edge_noise_factor = 3.0;
    double occlusion_ratio = 0.1;     // depth jump / range that marks an occluded boundary (B)
    double max_incidence_deg = 75.0;  // beam vs surface normal beyond this: grazing (D), rejected
    double min_range_m = 0.3;         // closer returns are too noisy for features
    double planar_leaf_m = 0.15;  // planar points are thinned to one per leaf (constant density)
};

struct FeatureCloud {
    std::vector<Eigen::Vector3d> edges;           // E_m, body frame at the sweep's start
    std::vector<Eigen::Vector3d> planars;         // H_m
    std::vector<Eigen::Vector3d> planar_origins;  // laser centre that saw each planar point
};

// Per-point smoothness along one line (eq. 12); NaN where the neighbour window is incomplete.
std::vector<double> lineSmoothness(const Sweep& sweep, const ScanLine& line, int half_window);

FeatureCloud extractFeatures(const Sweep& sweep, const FeatureConfig& config);

}  // namespace handscan::scan
