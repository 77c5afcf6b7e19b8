// The curvature offset of a planar neighbour cluster (eq. 15 on curved surfaces): how far the
// surface that the map points sample lies from their best-fit plane, under a query point.
#pragma once

#include <Eigen/Core>
#include <optional>

namespace handscan::scan {

struct SurfaceOffsetLimits {
    double max_leverage = 2.0;   // fitted height's variance at the query / one point's variance
    double max_rms_m = 0.01;     // rms of the points about the fitted quadric
    double max_offset_m = 0.03;  // larger: not a gently curved surface
};

// Fits h = a + b.u + u^T K u / 2 to the points' heights h above the plane (centroid `c`, unit
// normal `normal`, in-plane axes `t1`, `t2`) and returns that height at the query's in-plane
// position: the plane moved by it along `normal` touches the surface under the query.
// Why: on a curved surface the centroid of a cluster lies on the side the surface curves towards,
// by kappa * var(u) / 2 - 8 to 16 mm for a tunnel vault of 3 m radius and map points 0.2 m
// apart - always the same way, so every point-to-plane residual there carries the same bias and
// the matched pose follows it (the simulated tunnel pitched 1.7 deg over 55 m with ground-truth
// motion). nullopt when the points cannot tell the height there (too few, along one line, the
// query far outside them) or are no smooth surface (a corner, clutter): the plane stands.
std::optional<double> surfaceOffsetAt(const Eigen::Vector3d* points, int n,
                                      const Eigen::Vector3d& c, const Eigen::Vector3d& normal,
                                      const Eigen::Vector3d& t1, const Eigen::Vector3d& t2,
                                      const Eigen::Vector3d& query,
                                      const SurfaceOffsetLimits& limits = {});

}  // namespace handscan::scan
