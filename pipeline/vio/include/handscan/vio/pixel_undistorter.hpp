// Pixel -> normalised image coordinates (x/z, y/z) for a Kalibr camchain camera, the inverse of
// colour::CameraProjection: pinhole with radtan (k1 k2 p1 p2: OpenCV's undistortPoints) or
// equidistant (k1..k4: OpenCV's fisheye model) distortion, or none. The VIO works on normalised
// coordinates X_bar = [x, y, 1] (section 5.1); pixels follow Kalibr ((0, 0) is the centre of the
// top-left pixel, as OpenCV).
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <vector>

#include "handscan/core/config.hpp"

namespace handscan::vio {

class PixelUndistorter {
public:
    // Throws std::invalid_argument (start-up only) for a camera model we cannot invert, naming
    // the field of camchain.yaml to fix.
    explicit PixelUndistorter(const CameraIntrinsics& cam);

    int width() const { return width_; }
    int height() const { return height_; }
    double focalLength() const { return 0.5 * (K_(0, 0) + K_(1, 1)); }

    // Normalised coordinates of each pixel in `px`.
    void undistort(const std::vector<cv::Point2f>& px, std::vector<Eigen::Vector2d>& out) const;
    Eigen::Vector2d undistort(const cv::Point2f& px) const;
    // The other way (OpenCV's projectPoints with the same model): the pixel of each point in the
    // camera frame, for predicting where features move. A point not in front (z <= 0) gets
    // (-1, -1), outside every image.
    void project(const std::vector<Eigen::Vector3d>& p_cam, std::vector<cv::Point2f>& px) const;

private:
    cv::Matx33d K_;
    std::vector<double> D_;
    bool fisheye_ = false;
    bool distorted_ = false;
    int width_ = 0;
    int height_ = 0;
};

}  // namespace handscan::vio
