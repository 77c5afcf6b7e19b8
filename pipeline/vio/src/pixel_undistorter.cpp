#include "handscan/vio/pixel_undistorter.hpp"

#include <opencv2/calib3d.hpp>
#include <stdexcept>
#include <string>

namespace handscan::vio {

PixelUndistorter::PixelUndistorter(const CameraIntrinsics& cam)
    : K_(cam.intrinsics[0], 0.0, cam.intrinsics[2], 0.0, cam.intrinsics[1], cam.intrinsics[3], 0.0,
         0.0, 1.0),
      width_(cam.resolution[0]),
      height_(cam.resolution[1]) {
    if (cam.camera_model != "pinhole") {
        throw std::invalid_argument("tracking camera: camera_model '" + cam.camera_model +
                                    "' is not supported (pinhole only); recalibrate cam0 with "
                                    "Kalibr's pinhole-equi or pinhole-radtan");
    }
    if (cam.intrinsics[0] <= 0 || cam.intrinsics[1] <= 0 || width_ <= 0 || height_ <= 0) {
        throw std::invalid_argument(
            "tracking camera: intrinsics and resolution must be positive; check cam0 in "
            "camchain.yaml");
    }
    const std::string& model = cam.distortion_model;
    if (model == "none" || cam.distortion_coeffs.empty()) return;
    if (model != "radtan" && model != "equidistant") {
        throw std::invalid_argument("tracking camera: distortion_model '" + model +
                                    "' is not supported (radtan, equidistant, none)");
    }
    if (cam.distortion_coeffs.size() != 4) {
        throw std::invalid_argument("tracking camera: " + model +
                                    " needs 4 distortion_coeffs in camchain.yaml cam0, got " +
                                    std::to_string(cam.distortion_coeffs.size()));
    }
    D_ = cam.distortion_coeffs;
    fisheye_ = model == "equidistant";
    distorted_ = true;
}

void PixelUndistorter::undistort(const std::vector<cv::Point2f>& px,
                                 std::vector<Eigen::Vector2d>& out) const {
    out.resize(px.size());
    if (px.empty()) return;
    std::vector<cv::Point2f> norm;
    if (!distorted_) {
        for (std::size_t i = 0; i < px.size(); ++i) {
            out[i] = {(px[i].x - K_(0, 2)) / K_(0, 0), (px[i].y - K_(1, 2)) / K_(1, 1)};
        }
        return;
    }
    // Iterative inversions; 10 iterations (OpenCV's radtan default is 5) keep the error far
    // below a tenth of a pixel out to the corners of a wide-angle lens.
    const cv::TermCriteria term(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 10, 1e-10);
    if (fisheye_) {
        cv::fisheye::undistortPoints(px, norm, K_, D_, cv::noArray(), cv::noArray(), term);
    } else {
        cv::undistortPoints(px, norm, K_, D_, cv::noArray(), cv::noArray(), term);
    }
    for (std::size_t i = 0; i < px.size(); ++i) out[i] = {norm[i].x, norm[i].y};
}

Eigen::Vector2d PixelUndistorter::undistort(const cv::Point2f& px) const {
    std::vector<Eigen::Vector2d> out;
    undistort(std::vector<cv::Point2f>{px}, out);
    return out.front();
}

}  // namespace handscan::vio
