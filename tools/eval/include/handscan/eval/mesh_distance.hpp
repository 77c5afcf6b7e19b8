// Exact distance from points to a triangle mesh: the closest point on a triangle (Ericson,
// "Real-Time Collision Detection", 5.1.5: Voronoi regions of vertices, edges and face) in double
// precision, and a BVH over the triangles (Embree's point queries, which shrink the search radius
// as closer triangles are found) so that each query touches only the triangles near the point.
#pragma once

#include <Eigen/Core>
#include <array>
#include <memory>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/eval/ply_reader.hpp"

namespace handscan::eval {

// Closest point to p on triangle (a, b, c).
Eigen::Vector3d closestPointOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                       const Eigen::Vector3d& b, const Eigen::Vector3d& c);
double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                             const Eigen::Vector3d& b, const Eigen::Vector3d& c);

class MeshDistance {
public:
    // Builds the BVH; fails when the mesh has no triangle or Embree cannot start.
    static Result<std::unique_ptr<MeshDistance>> build(PlyGeometry mesh);
    ~MeshDistance();
    MeshDistance(const MeshDistance&) = delete;
    MeshDistance& operator=(const MeshDistance&) = delete;

    // Distance from p to the nearest triangle (exact, double precision).
    double distance(const Eigen::Vector3d& p) const;
    std::size_t triangles() const { return mesh_.triangles.size(); }

private:
    struct Bvh;
    MeshDistance(PlyGeometry mesh, std::unique_ptr<Bvh> bvh);
    PlyGeometry mesh_;
    std::unique_ptr<Bvh> bvh_;
};

struct MapErrorResult {
    std::size_t points = 0;
    double median_m = 0.0, p90_m = 0.0, p99_m = 0.0, mean_m = 0.0, max_m = 0.0;
};
// Distance of each map point to the nearest true triangle, as percentiles.
MapErrorResult computeMapError(const std::vector<Eigen::Vector3d>& map_points,
                               const MeshDistance& mesh);

}  // namespace handscan::eval
