// DepthMap (section 5.3, Figure 5): the laser points of the last few seconds, registered in {W},
// seen from a key-frame's camera. At build(): points in the camera's field of view are kept,
// downsampled to one point per cell of an angular grid (the nearest: constant density on the
// sphere; a point is dropped where a neighbouring cell holds a much nearer one, so a surface
// behind a nearer one does not leak through its gaps), projected on the unit sphere
// around the camera centre and put in a 2D k-d tree (nanoflann) on their two angular coordinates.
// depthOf() finds the three nearest points on the sphere for a feature that span a plane (not
// three on one scan line), rejects them when they
// lie too far apart in Cartesian space (likely two objects, e.g. a wall and something in front
// of it), and interpolates the depth on the plane through them.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "handscan/core/time.hpp"

namespace handscan::vio {

struct DepthMapConfig {
    double keep_s = 3.0;            // laser points older than this leave the depth map
    double cell_rad = 0.006;        // angular downsampling (0.34 deg, ~2 pixels at f = 290)
    double max_half_fov_rad = 1.2;  // points further off the optical axis are not kept
    double min_depth_m = 0.15;
    double max_depth_m = 60.0;
    // A feature farther than this from its nearest laser point on the sphere has no coverage.
    double max_neighbour_angle_rad = 0.02;
    // The three points must lie within spread_m + spread_fraction * depth of each other.
    double spread_m = 0.1;
    double spread_fraction = 0.05;
    // The three points must span a plane: the angle at the nearest between the other two has a
    // sine of at least this (else the next nearest point is tried as the third).
    double min_triangle_sin = 0.3;
    // The plane must not be seen edge-on: |cos| between its normal and the ray at least this.
    double min_incidence_cos = 0.1;
};

class DepthMap {
public:
    explicit DepthMap(const DepthMapConfig& config = {});
    ~DepthMap();
    DepthMap(DepthMap&&) noexcept;
    DepthMap& operator=(DepthMap&&) noexcept;

    // Registered laser points in {W} measured at about time t (a scan line, or a sweep).
    void addPoints(TimeNs t, const std::vector<Eigen::Vector3d>& points_world);
    // Builds the depth map seen from camera pose T_world_cam at time t (drops points older than
    // t - keep_s). Returns the number of points on the sphere.
    std::size_t build(TimeNs t, const Eigen::Isometry3d& T_world_cam);
    // Depth (z in the camera frame of the last build) of the feature with normalised coordinates
    // xbar = (x/z, y/z); nullopt without laser coverage or when the check fails.
    std::optional<double> depthOf(const Eigen::Vector2d& xbar) const;

    std::size_t size() const;          // points on the sphere after the last build
    std::size_t storedPoints() const;  // raw points kept
    const DepthMapConfig& config() const { return config_; }

private:
    struct Batch {
        TimeNs t;
        std::vector<Eigen::Vector3f> points_world;
    };
    // The nearest point of one angular cell (i, j) at build().
    struct Cell {
        float range;
        std::int64_t i, j;
        Eigen::Vector3f point;
    };
    struct Sphere;

    DepthMapConfig config_;
    std::deque<Batch> batches_;
    std::vector<std::int32_t> grid_;  // per angular cell: its index in cells_, or -1 (build())
    std::vector<Cell> cells_;         // reused between builds
    std::unique_ptr<Sphere> sphere_;
};

}  // namespace handscan::vio
