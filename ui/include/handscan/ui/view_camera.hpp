// The 3D view's camera: follow (behind the device, looking where it goes), top-down (orthographic,
// north up, for checking coverage while walking) and free (orbit about a target by dragging). Pure
// math on Eigen; the matrices follow OpenGL conventions (right-handed eye space looking down -z,
// clip space z in [-w, w]) so tests can project points exactly as the GPU does.
#pragma once

#include <Eigen/Core>

namespace handscan::ui {

enum class CameraMode { kFollow = 0, kTopDown = 1, kFree = 2 };
const char* toString(CameraMode mode);

Eigen::Matrix4f lookAt(const Eigen::Vector3f& eye, const Eigen::Vector3f& target,
                       const Eigen::Vector3f& up);
Eigen::Matrix4f perspective(float fov_y_rad, float aspect, float near_m, float far_m);
Eigen::Matrix4f orthographic(float half_width, float half_height, float near_m, float far_m);

class ViewCamera {
public:
    CameraMode mode = CameraMode::kFollow;
    float fov_y_deg = 60.0f;
    float distance_m = 8.0f;  // follow / free: eye distance from the target
    float yaw_rad = 0.0f;     // free: azimuth of the eye around the target; follow: offset
    float pitch_rad = 0.6f;   // elevation of the eye above the target's horizon
    float top_down_half_height_m = 8.0f;
    Eigen::Vector3f target = Eigen::Vector3f::Zero();  // free / top-down centre

    // Fixed eye and target (free mode) as given on the command line; overrides the orbit.
    void setExplicit(const Eigen::Vector3f& eye, const Eigen::Vector3f& look_at);
    // Device pose for follow / top-down (position and heading about +z).
    void setDevice(const Eigen::Vector3f& position, float heading_rad);

    // Touch / mouse: drag by (dx, dy) pixels, zoom by `factor` (< 1 = closer).
    void drag(float dx_px, float dy_px);
    void zoom(float factor);

    Eigen::Matrix4f view() const;
    Eigen::Matrix4f projection(float aspect) const;
    Eigen::Vector3f eye() const;

private:
    bool explicit_ = false;
    Eigen::Vector3f explicit_eye_ = Eigen::Vector3f::Zero();
    Eigen::Vector3f device_ = Eigen::Vector3f::Zero();
    float device_heading_ = 0.0f;
};

}  // namespace handscan::ui
