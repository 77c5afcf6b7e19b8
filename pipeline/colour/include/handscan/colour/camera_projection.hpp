// Forward projection of a Kalibr camchain camera: pinhole with radtan (k1 k2 p1 p2, the same
// polynomial as OpenCV's projectPoints with four coefficients) or equidistant (k1..k4 on the
// incidence angle, OpenCV's fisheye model) distortion, or none. Pixel coordinates follow Kalibr:
// (0, 0) is the centre of the top-left pixel.
#pragma once

#include <Eigen/Core>
#include <array>
#include <optional>

#include "handscan/core/config.hpp"

namespace handscan::colour {

class CameraProjection {
public:
    enum class Distortion { kNone, kRadtan, kEquidistant };

    // Throws std::invalid_argument (start-up only) when the model or coefficient count is not one
    // we can project, naming the camera so the camchain can be fixed.
    explicit CameraProjection(const CameraIntrinsics& cam);

    int width() const { return width_; }
    int height() const { return height_; }
    Distortion distortion() const { return distortion_; }

    // Pixel of a point in the camera frame; nullopt when it is not in front (z <= 0) or beyond the
    // radius where the distortion polynomial stops being monotonic (it would fold far off-axis
    // points back into the image).
    std::optional<Eigen::Vector2d> project(const Eigen::Vector3d& p_cam) const;
    // Distorted normalised coordinates of an undistorted normalised point (x/z, y/z).
    Eigen::Vector2d distort(const Eigen::Vector2d& m) const;
    // Pixel of distorted normalised coordinates.
    Eigen::Vector2d toPixel(const Eigen::Vector2d& m_distorted) const {
        return {fu_ * m_distorted.x() + pu_, fv_ * m_distorted.y() + pv_};
    }

private:
    double fu_ = 0, fv_ = 0, pu_ = 0, pv_ = 0;
    std::array<double, 4> k_{};
    Distortion distortion_ = Distortion::kNone;
    double max_r2_ = 1e30;  // squared undistorted radius where the model stays one-to-one
    int width_ = 0, height_ = 0;
};

}  // namespace handscan::colour
