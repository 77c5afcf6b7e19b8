#include "handscan/vio/depth_map.hpp"

#include <algorithm>
#include <cmath>
#include <nanoflann.hpp>

namespace handscan::vio {
namespace {

// The two angular coordinates of a direction in the camera frame (z forward): azimuth about
// the y axis and elevation from the x-z plane. Near the optical axis the Euclidean distance of
// these coordinates is the angle between the directions.
Eigen::Vector2d sphereCoordinates(const Eigen::Vector3d& d) {
    return {std::atan2(d.x(), d.z()), std::atan2(d.y(), std::hypot(d.x(), d.z()))};
}

}  // namespace

struct DepthMap::Sphere {
    std::vector<Eigen::Vector2d> angles;  // on the unit sphere
    std::vector<Eigen::Vector3d> points;  // the same points in the camera frame
    std::size_t kdtree_get_point_count() const { return angles.size(); }
    double kdtree_get_pt(std::size_t i, std::size_t dim) const {
        return angles[i][static_cast<int>(dim)];
    }
    template <class Box>
    bool kdtree_get_bbox(Box& /*bb*/) const {
        return false;
    }
    using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Sphere>,
                                                     Sphere, 2, std::uint32_t>;
    std::unique_ptr<Tree> tree;
};

DepthMap::DepthMap(const DepthMapConfig& config)
    : config_(config), sphere_(std::make_unique<Sphere>()) {}
DepthMap::~DepthMap() = default;
DepthMap::DepthMap(DepthMap&&) noexcept = default;
DepthMap& DepthMap::operator=(DepthMap&&) noexcept = default;

std::size_t DepthMap::size() const { return sphere_->angles.size(); }

std::size_t DepthMap::storedPoints() const {
    std::size_t n = 0;
    for (const Batch& b : batches_) n += b.points_world.size();
    return n;
}

void DepthMap::addPoints(TimeNs t, const std::vector<Eigen::Vector3d>& points_world) {
    Batch b{t, {}};
    b.points_world.reserve(points_world.size());
    for (const Eigen::Vector3d& p : points_world) {
        if (p.allFinite()) b.points_world.push_back(p.cast<float>());
    }
    if (!b.points_world.empty()) batches_.push_back(std::move(b));
}

std::size_t DepthMap::build(TimeNs t, const Eigen::Isometry3d& T_world_cam) {
    const TimeNs keep = static_cast<TimeNs>(config_.keep_s * 1e9);
    while (!batches_.empty() && batches_.front().t < t - keep) batches_.pop_front();

    // One point per angular cell, the nearest to the camera. The cells lie on a dense grid:
    // a point within max_half_fov_rad of the optical axis has both angular coordinates within
    // it, so the grid spans [-fov, fov] in each (plus a margin for the neighbour check below);
    // an index into it costs less than a hash (the build was 11 ms per key-frame with one).
    const Eigen::Isometry3f T_cam_world = T_world_cam.inverse().cast<float>();
    const float cos_fov = static_cast<float>(std::cos(config_.max_half_fov_rad));
    const float min_d = static_cast<float>(config_.min_depth_m);
    const float max_d = static_cast<float>(config_.max_depth_m);
    const double inv_cell = 1.0 / config_.cell_rad;
    const auto half = static_cast<std::int64_t>(std::ceil(config_.max_half_fov_rad * inv_cell)) + 2;
    const std::int64_t side = 2 * half + 1;
    grid_.assign(static_cast<std::size_t>(side * side), -1);
    cells_.clear();
    auto cellIndex = [&](std::int64_t i, std::int64_t j) {
        return static_cast<std::size_t>((j + half) * side + (i + half));
    };
    for (const Batch& b : batches_) {
        for (const Eigen::Vector3f& pw : b.points_world) {
            const Eigen::Vector3f p = T_cam_world * pw;
            const float r = p.norm();
            if (p.z() < min_d || r > max_d || p.z() < cos_fov * r) continue;
            const Eigen::Vector2d a = sphereCoordinates(p.cast<double>());
            const auto i = static_cast<std::int64_t>(std::floor(a.x() * inv_cell));
            const auto j = static_cast<std::int64_t>(std::floor(a.y() * inv_cell));
            if (i <= -half || i >= half || j <= -half || j >= half) continue;  // not reached
            std::int32_t& slot = grid_[cellIndex(i, j)];
            if (slot < 0) {
                slot = static_cast<std::int32_t>(cells_.size());
                cells_.push_back({r, i, j, p});
            } else if (r < cells_[static_cast<std::size_t>(slot)].range) {
                cells_[static_cast<std::size_t>(slot)].range = r;
                cells_[static_cast<std::size_t>(slot)].point = p;
            }
        }
    }
    sphere_->tree.reset();
    sphere_->angles.clear();
    sphere_->points.clear();
    sphere_->angles.reserve(cells_.size());
    sphere_->points.reserve(cells_.size());
    const float spread = static_cast<float>(config_.spread_m);
    const float spread_fraction = static_cast<float>(config_.spread_fraction);
    for (const Cell& cell : cells_) {
        // A farther surface seen through a gap between the nearer one's points (cells the
        // nearer surface left empty): hidden when a neighbouring cell holds a point much closer.
        const float hidden_beyond = cell.range - (spread + spread_fraction * cell.range);
        bool hidden = false;
        for (std::int64_t di = -1; di <= 1 && !hidden; ++di) {
            for (std::int64_t dj = -1; dj <= 1 && !hidden; ++dj) {
                if (di == 0 && dj == 0) continue;
                const std::int32_t other = grid_[cellIndex(cell.i + di, cell.j + dj)];
                hidden =
                    other >= 0 && cells_[static_cast<std::size_t>(other)].range < hidden_beyond;
            }
        }
        if (hidden) continue;
        const Eigen::Vector3d p = cell.point.cast<double>();
        sphere_->points.push_back(p);
        sphere_->angles.push_back(sphereCoordinates(p));
    }
    if (!sphere_->angles.empty()) {
        sphere_->tree = std::make_unique<Sphere::Tree>(
            2, *sphere_, nanoflann::KDTreeSingleIndexAdaptorParams(10));
    }
    return sphere_->angles.size();
}

std::optional<double> DepthMap::depthOf(const Eigen::Vector2d& xbar) const {
    if (!sphere_->tree || sphere_->angles.size() < 3) return std::nullopt;
    const Eigen::Vector3d ray(xbar.x(), xbar.y(), 1.0);
    const Eigen::Vector2d q = sphereCoordinates(ray);
    // The three closest points that span a plane. A spinning 2D laser lays its points along scan
    // lines a cell apart and the lines several cells apart, so the three nearest are often on
    // one line: their plane turns freely about it and the depth it gives is noise (measured on
    // a simulated office walk: 35 % of the features were refused by the incidence check). The
    // third point is the nearest that leaves the line of the first two.
    constexpr std::size_t kCandidates = 24;  // reaches the next line where lines lie 4 cells apart
    std::uint32_t idx[kCandidates];
    double d2[kCandidates];
    const double query[2] = {q.x(), q.y()};
    const std::size_t found = sphere_->tree->knnSearch(query, kCandidates, idx, d2);
    if (found < 3) return std::nullopt;
    if (d2[0] > config_.max_neighbour_angle_rad * config_.max_neighbour_angle_rad)
        return std::nullopt;
    const Eigen::Vector3d& p0 = sphere_->points[idx[0]];
    const Eigen::Vector3d& p1 = sphere_->points[idx[1]];
    const Eigen::Vector3d* third = nullptr;
    const double min_sin2 = config_.min_triangle_sin * config_.min_triangle_sin;
    for (std::size_t k = 2; k < found && third == nullptr; ++k) {
        const Eigen::Vector3d& c = sphere_->points[idx[k]];
        const Eigen::Vector3d a = p1 - p0, b = c - p0;
        if (a.cross(b).squaredNorm() >= min_sin2 * a.squaredNorm() * b.squaredNorm()) third = &c;
    }
    if (third == nullptr) return std::nullopt;  // all on one line: no plane
    const Eigen::Vector3d& p2 = *third;
    // Spread check: three points far apart in space likely lie on different objects.
    const double limit = config_.spread_m + config_.spread_fraction * p0.z();
    const double l2 = limit * limit;
    if ((p0 - p1).squaredNorm() > l2 || (p0 - p2).squaredNorm() > l2 ||
        (p1 - p2).squaredNorm() > l2)
        return std::nullopt;
    // Planar interpolation: the ray z * (x, y, 1) meets the plane n.(X - p0) = 0.
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0);
    const double nn = n.norm();
    if (nn < 1e-12) return std::nullopt;  // collinear
    const double denom = n.dot(ray);
    if (std::abs(denom) < config_.min_incidence_cos * nn * ray.norm()) return std::nullopt;
    const double z = n.dot(p0) / denom;
    // The patch must hold the depth: no extrapolation beyond the three points' range.
    const double lo = std::min({p0.z(), p1.z(), p2.z()}) - limit;
    const double hi = std::max({p0.z(), p1.z(), p2.z()}) + limit;
    if (!(z > config_.min_depth_m) || z < lo || z > hi) return std::nullopt;
    return z;
}

}  // namespace handscan::vio
