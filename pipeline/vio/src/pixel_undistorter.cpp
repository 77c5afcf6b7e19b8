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

void PixelUndistorter::project(const std::vector<Eigen::Vector3d>& p_cam,
                               std::vector<cv::Point2f>& px) const {
    px.assign(p_cam.size(), cv::Point2f(-1.0f, -1.0f));
    std::vector<cv::Point3f> front;
    std::vector<std::size_t> index;
    front.reserve(p_cam.size());
    index.reserve(p_cam.size());
    for (std::size_t i = 0; i < p_cam.size(); ++i) {
        if (!(p_cam[i].z() > 1e-9)) continue;
        front.emplace_back(static_cast<float>(p_cam[i].x() / p_cam[i].z()),
                           static_cast<float>(p_cam[i].y() / p_cam[i].z()), 1.0f);
        index.push_back(i);
    }
    if (front.empty()) return;
    std::vector<cv::Point2f> out;
    const cv::Vec3d zero(0.0, 0.0, 0.0);
    const std::vector<double> none;
    if (fisheye_) {
        cv::fisheye::projectPoints(front, out, zero, zero, K_, D_);
    } else {
        cv::projectPoints(front, zero, zero, K_, distorted_ ? D_ : none, out);
    }
    for (std::size_t k = 0; k < index.size(); ++k) px[index[k]] = out[k];
}

}  // namespace handscan::vio
