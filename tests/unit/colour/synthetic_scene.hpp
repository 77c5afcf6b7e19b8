// Test scenes for the colouriser: textured planes in the world rendered into a BGR image through
// cam1's model (pixels unprojected with OpenCV's undistortPoints, an implementation independent of
// ours), and laser-like points sampled on the same planes.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <functional>
#include <opencv2/calib3d.hpp>
#include <optional>
#include <vector>

#include "handscan/core/config.hpp"
#include "handscan/core/samples.hpp"

namespace handscan::colour::test {

using Rgb = std::array<double, 3>;

// An axis-aligned rectangle of the plane z_world = z, coloured by a smooth function of (x, y).
struct TexturedPlane {
    double z = 3.0;
    double x_min = -100, x_max = 100, y_min = -100, y_max = 100;
    std::function<Rgb(double, double)> colour;

    bool contains(double x, double y) const {
        return x >= x_min && x <= x_max && y >= y_min && y <= y_max;
    }
    // Distance along the world ray (o + s d) to the plane, if it hits the rectangle in front.
    std::optional<double> hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
        if (std::abs(d.z()) < 1e-12) return std::nullopt;
        const double s = (z - o.z()) / d.z();
        if (s <= 0) return std::nullopt;
        const Eigen::Vector3d p = o + s * d;
        if (!contains(p.x(), p.y())) return std::nullopt;
        return s;
    }
};

// Smooth RGB pattern: bilinear interpolation error stays below one level at cam1's scale.
inline Rgb wavePattern(double x, double y) {
    return {128 + 100 * std::sin(2 * M_PI * x / 0.9), 128 + 100 * std::cos(2 * M_PI * y / 0.7),
            128 + 80 * std::sin(2 * M_PI * (x + y) / 1.3)};
}

inline cv::Mat cameraMatrix(const CameraIntrinsics& c) {
    return (cv::Mat_<double>(3, 3) << c.intrinsics[0], 0, c.intrinsics[2], 0, c.intrinsics[1],
            c.intrinsics[3], 0, 0, 1);
}
inline cv::Mat distCoeffs(const CameraIntrinsics& c) {
    return cv::Mat(c.distortion_coeffs, true).reshape(1, 1);
}

// Unit viewing rays (colour camera frame) of every pixel centre, row-major.
inline std::vector<Eigen::Vector3d> pixelRays(const CameraIntrinsics& cam) {
    const int w = cam.resolution[0], h = cam.resolution[1];
    std::vector<cv::Point2d> px;
    px.reserve(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (int v = 0; v < h; ++v)
        for (int u = 0; u < w; ++u) px.emplace_back(u, v);
    std::vector<cv::Point2d> norm;
    cv::undistortPoints(
        px, norm, cameraMatrix(cam), distCoeffs(cam), cv::noArray(), cv::noArray(),
        cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 60, 1e-14));
    std::vector<Eigen::Vector3d> rays(norm.size());
    for (std::size_t i = 0; i < norm.size(); ++i)
        rays[i] = Eigen::Vector3d(norm[i].x, norm[i].y, 1.0).normalized();
    return rays;
}

// Nearest plane hit along a world ray: (plane index, world point).
inline std::optional<std::pair<std::size_t, Eigen::Vector3d>> castRay(
    const std::vector<TexturedPlane>& planes, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
    std::optional<std::pair<std::size_t, Eigen::Vector3d>> best;
    double best_s = 1e30;
    for (std::size_t k = 0; k < planes.size(); ++k) {
        if (auto s = planes[k].hit(o, d); s && *s < best_s) {
            best_s = *s;
            best = {{k, o + *s * d}};
        }
    }
    return best;
}

// Renders the planes as seen by the colour camera at T_world_colour: packed BGR8, black where no
// plane is hit.
inline Image renderBgr(const CameraIntrinsics& cam, const std::vector<Eigen::Vector3d>& rays,
                       const std::vector<TexturedPlane>& planes,
                       const Eigen::Isometry3d& T_world_colour, TimeNs t, std::uint32_t sequence) {
    Image img;
    img.t_host = t;
    img.sequence = sequence;
    img.format = PixelFormat::kBgr8;
    img.width = cam.resolution[0];
    img.height = cam.resolution[1];
    img.stride_bytes = img.width * 3;
    img.data.assign(
        static_cast<std::size_t>(img.stride_bytes) * static_cast<std::size_t>(img.height), 0);
    const Eigen::Vector3d o = T_world_colour.translation();
    for (std::size_t i = 0; i < rays.size(); ++i) {
        const auto hit = castRay(planes, o, T_world_colour.linear() * rays[i]);
        if (!hit) continue;
        const Rgb c = planes[hit->first].colour(hit->second.x(), hit->second.y());
        for (int ch = 0; ch < 3; ++ch) {
            img.data[i * 3 + static_cast<std::size_t>(2 - ch)] = static_cast<std::uint8_t>(
                std::clamp(std::lround(c[static_cast<std::size_t>(ch)]), 0L, 255L));
        }
    }
    return img;
}

}  // namespace handscan::colour::test
