#include "handscan/ui/view_camera.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace handscan::ui {

const char* toString(CameraMode mode) {
    switch (mode) {
        case CameraMode::kFollow:
            return "follow";
        case CameraMode::kTopDown:
            return "top-down";
        case CameraMode::kFree:
            return "free";
    }
    return "?";
}

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                       const Eigen::Vector3f& up) {
    const Eigen::Vector3f f = (target - eye).normalized();
    const Eigen::Vector3f s = f.cross(up).normalized();
    const Eigen::Vector3f u = s.cross(f);
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m.block<1, 3>(0, 0) = s.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -s.dot(eye);
    m(1, 3) = -u.dot(eye);
    m(2, 3) = f.dot(eye);
    return m;
}

Eigen::Matrix4f perspective(float fov_y_rad, float aspect, float near_m, float far_m) {
    const float t = 1.0f / std::tan(fov_y_rad / 2);
    Eigen::Matrix4f m = Eigen::Matrix4f::Zero();
    m(0, 0) = t / aspect;
    m(1, 1) = t;
    m(2, 2) = (far_m + near_m) / (near_m - far_m);
    m(2, 3) = 2 * far_m * near_m / (near_m - far_m);
    m(3, 2) = -1;
    return m;
}

Eigen::Matrix4f orthographic(float half_width, float half_height, float near_m, float far_m) {
    Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
    m(0, 0) = 1.0f / half_width;
    m(1, 1) = 1.0f / half_height;
    m(2, 2) = -2.0f / (far_m - near_m);
    m(2, 3) = -(far_m + near_m) / (far_m - near_m);
    return m;
}

void ViewCamera::setExplicit(const Eigen::Vector3f& eye, const Eigen::Vector3f& look_at) {
    explicit_ = true;
    mode = CameraMode::kFree;
    explicit_eye_ = eye;
    target = look_at;
}

void ViewCamera::setDevice(const Eigen::Vector3f& position, float heading_rad) {
    device_ = position;
    device_heading_ = heading_rad;
}

void ViewCamera::drag(float dx_px, float dy_px) {
    explicit_ = false;
    if (mode == CameraMode::kTopDown) {
        // Pan: one screen height of drag moves the view by its height in metres.
        target.x() -= dx_px * top_down_half_height_m / 300.0f;
        target.y() += dy_px * top_down_half_height_m / 300.0f;
        return;
    }
    yaw_rad -= dx_px * 0.008f;
    pitch_rad = std::clamp(pitch_rad + dy_px * 0.006f, -0.2f, 1.5f);
}

void ViewCamera::zoom(float factor) {
    if (mode == CameraMode::kTopDown) {
        top_down_half_height_m = std::clamp(top_down_half_height_m * factor, 1.0f, 500.0f);
    } else {
        distance_m = std::clamp(distance_m * factor, 0.5f, 500.0f);
    }
}

Eigen::Vector3f ViewCamera::eye() const {
    if (explicit_) return explicit_eye_;
    const Eigen::Vector3f centre = mode == CameraMode::kFollow ? device_ : target;
    // Follow: behind the device's heading (plus the user's yaw offset).
    const float azimuth =
        mode == CameraMode::kFollow ? device_heading_ + 3.14159265f + yaw_rad : yaw_rad;
    const Eigen::Vector3f dir(std::cos(pitch_rad) * std::cos(azimuth),
                              std::cos(pitch_rad) * std::sin(azimuth), std::sin(pitch_rad));
    return centre + distance_m * dir;
}

Eigen::Matrix4f ViewCamera::view() const {
    if (mode == CameraMode::kTopDown) {
        // Straight down from above, +y (north) up on screen.
        const Eigen::Vector3f centre(target.x(), target.y(), 0.0f);
        return lookAt(centre + Eigen::Vector3f(0, 0, 200.0f), centre, Eigen::Vector3f::UnitY());
    }
    const Eigen::Vector3f centre = explicit_ || mode == CameraMode::kFree ? target : device_;
    return lookAt(eye(), centre, Eigen::Vector3f::UnitZ());
}

Eigen::Matrix4f ViewCamera::projection(float aspect) const {
    if (mode == CameraMode::kTopDown) {
        return orthographic(top_down_half_height_m * aspect, top_down_half_height_m, 1.0f, 400.0f);
    }
    return perspective(fov_y_deg * 3.14159265f / 180.0f, aspect, 0.1f, 1000.0f);
}

}  // namespace handscan::ui
