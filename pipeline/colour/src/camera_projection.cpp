#include "handscan/colour/camera_projection.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace handscan::colour {

CameraProjection::CameraProjection(const CameraIntrinsics& cam) {
    if (cam.camera_model != "pinhole") {
        throw std::invalid_argument(
            "colour camera: camera_model '" + cam.camera_model +
            "' is not supported (pinhole only); recalibrate cam1 with Kalibr's pinhole-radtan");
    }
    fu_ = cam.intrinsics[0];
    fv_ = cam.intrinsics[1];
    pu_ = cam.intrinsics[2];
    pv_ = cam.intrinsics[3];
    width_ = cam.resolution[0];
    height_ = cam.resolution[1];
    if (fu_ <= 0 || fv_ <= 0 || width_ <= 0 || height_ <= 0) {
        throw std::invalid_argument(
            "colour camera: intrinsics/resolution must be positive (got fu " + std::to_string(fu_) +
            ", fv " + std::to_string(fv_) + ", " + std::to_string(width_) + "x" +
            std::to_string(height_) + "); check cam1 in camchain.yaml");
    }
    const std::string& model = cam.distortion_model;
    if (model == "none" || cam.distortion_coeffs.empty()) {
        distortion_ = Distortion::kNone;
        return;
    }
    if (model == "radtan") {
        distortion_ = Distortion::kRadtan;
    } else if (model == "equidistant") {
        distortion_ = Distortion::kEquidistant;
    } else {
        throw std::invalid_argument("colour camera: distortion_model '" + model +
                                    "' is not supported (radtan, equidistant, none)");
    }
    if (cam.distortion_coeffs.size() != 4) {
        throw std::invalid_argument("colour camera: " + model + " needs 4 distortion_coeffs, got " +
                                    std::to_string(cam.distortion_coeffs.size()));
    }
    for (std::size_t i = 0; i < 4; ++i) k_[i] = cam.distortion_coeffs[i];
    if (distortion_ == Distortion::kRadtan) {
        // d(r * (1 + k1 r^2 + k2 r^4))/dr = 1 + 3 k1 r^2 + 5 k2 r^4 must stay positive: find where
        // it first fails (up to r = 10, i.e. 84 degrees off-axis) and reject points beyond.
        for (double r = 0.0; r <= 10.0; r += 0.001) {
            const double r2 = r * r;
            if (1.0 + 3.0 * k_[0] * r2 + 5.0 * k_[1] * r2 * r2 <= 0.0) {
                max_r2_ = r2;
                break;
            }
        }
    }
}

Eigen::Vector2d CameraProjection::distort(const Eigen::Vector2d& m) const {
    const double x = m.x(), y = m.y();
    switch (distortion_) {
        case Distortion::kNone:
            return m;
        case Distortion::kRadtan: {
            // Kalibr RadialTangentialDistortion (= Brown-Conrady, OpenCV k1 k2 p1 p2).
            const double r2 = x * x + y * y;
            const double radial = 1.0 + k_[0] * r2 + k_[1] * r2 * r2;
            const double xy = x * y;
            return {x * radial + 2.0 * k_[2] * xy + k_[3] * (r2 + 2.0 * x * x),
                    y * radial + k_[2] * (r2 + 2.0 * y * y) + 2.0 * k_[3] * xy};
        }
        case Distortion::kEquidistant: {
            // Kalibr EquidistantDistortion: theta_d = theta (1 + k1 th^2 + k2 th^4 + k3 th^6 + k4
            // th^8).
            const double r = std::sqrt(x * x + y * y);
            if (r < 1e-12) return m;
            const double th = std::atan(r), th2 = th * th;
            const double thd =
                th * (1.0 + th2 * (k_[0] + th2 * (k_[1] + th2 * (k_[2] + th2 * k_[3]))));
            return m * (thd / r);
        }
    }
    return m;
}

std::optional<Eigen::Vector2d> CameraProjection::project(const Eigen::Vector3d& p_cam) const {
    if (!(p_cam.z() > 0.0)) return std::nullopt;
    const Eigen::Vector2d m(p_cam.x() / p_cam.z(), p_cam.y() / p_cam.z());
    if (m.squaredNorm() >= max_r2_) return std::nullopt;
    return toPixel(distort(m));
}

}  // namespace handscan::colour
