#include "handscan/ui/start_placement.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

namespace handscan::ui {

std::optional<Eigen::Vector3f> screenToMap(const Eigen::Matrix4f& view_proj, float vx, float vy,
                                           float vw, float vh, float px, float py, float plane_z) {
    if (vw <= 0 || vh <= 0) return std::nullopt;
    // Window pixels to normalised device coordinates (y up), then back through the camera: the
    // points of the ray on the near and the far plane.
    const float nx = 2.0f * (px - vx) / vw - 1.0f;
    const float ny = 1.0f - 2.0f * (py - vy) / vh;
    const Eigen::Matrix4f inv = view_proj.inverse();
    const Eigen::Vector4f a = inv * Eigen::Vector4f(nx, ny, -1.0f, 1.0f);
    const Eigen::Vector4f b = inv * Eigen::Vector4f(nx, ny, 1.0f, 1.0f);
    if (std::abs(a.w()) < 1e-12f || std::abs(b.w()) < 1e-12f) return std::nullopt;
    const Eigen::Vector3f near = a.head<3>() / a.w(), far = b.head<3>() / b.w();
    const Eigen::Vector3f dir = far - near;
    if (std::abs(dir.z()) < 1e-9f) return std::nullopt;
    const float s = (plane_z - near.z()) / dir.z();
    if (s < 0.0f) return std::nullopt;
    return near + s * dir;
}

std::optional<float> pathHeightNear(std::span<const shm::TrackPoint> path, float x, float y) {
    std::optional<float> z;
    float best = std::numeric_limits<float>::infinity();
    for (const shm::TrackPoint& p : path) {
        const float d = (p.x_m - x) * (p.x_m - x) + (p.y_m - y) * (p.y_m - y);
        if (d < best) {
            best = d;
            z = p.z_m;
        }
    }
    return z;
}

void StartPlacement::press(const Eigen::Vector3f& at_map) { position_ = at_map; }

void StartPlacement::drag(const Eigen::Vector3f& at_map) {
    if (!position_) return;
    const Eigen::Vector2f d = at_map.head<2>() - position_->head<2>();
    if (d.norm() < 0.2f) return;  // a finger's wobble, not a direction
    heading_rad_ = std::atan2(d.y(), d.x());
}

Eigen::Isometry3d StartPlacement::pose() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(heading_rad_, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    if (position_) T.translation() = position_->cast<double>();
    return T;
}

std::string StartPlacement::poseText() const {
    const Eigen::Isometry3d T = pose();
    const Eigen::Quaterniond q(T.linear());
    char buf[160];
    std::snprintf(buf, sizeof(buf), "%.3f,%.3f,%.3f,%.6f,%.6f,%.6f,%.6f", T.translation().x(),
                  T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w());
    return buf;
}

}  // namespace handscan::ui
