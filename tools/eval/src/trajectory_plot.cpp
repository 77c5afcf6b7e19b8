#include "handscan/eval/trajectory_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace handscan::eval {

Status plotTopView(const std::string& png_path, const std::vector<PosePair>& pairs,
                   const Eigen::Isometry3d& T_gt_est, int size_px) {
    if (pairs.empty())
        return Status(StatusCode::kInvalidArgument, "plot: no associated poses to draw");
    std::vector<Eigen::Vector2d> gt, est;
    Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
    for (const PosePair& p : pairs) {
        gt.push_back(p.gt.translation().head<2>());
        est.push_back((T_gt_est * p.est).translation().head<2>());
        for (const auto& q : {gt.back(), est.back()}) {
            lo = lo.cwiseMin(q);
            hi = hi.cwiseMax(q);
        }
    }
    const int margin = 50;
    const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-3});
    const double scale = (size_px - 2 * margin) / span;  // px per metre
    auto px = [&](const Eigen::Vector2d& q) {
        return cv::Point(static_cast<int>(margin + (q.x() - lo.x()) * scale),
                         static_cast<int>(size_px - margin - (q.y() - lo.y()) * scale));  // y up
    };
    cv::Mat img(size_px, size_px, CV_8UC3, cv::Scalar(255, 255, 255));
    auto draw = [&](const std::vector<Eigen::Vector2d>& path, const cv::Scalar& colour) {
        std::vector<cv::Point> pts;
        pts.reserve(path.size());
        for (const auto& q : path) pts.push_back(px(q));
        cv::polylines(img, pts, false, colour, 2, cv::LINE_AA);
    };
    draw(gt, cv::Scalar(0, 160, 0));
    draw(est, cv::Scalar(0, 0, 220));
    cv::circle(img, px(gt.front()), 7, cv::Scalar(0, 0, 0), 2, cv::LINE_AA);
    cv::putText(img, "ground truth", {margin, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 160, 0), 2);
    cv::putText(img, "estimate (SE(3)-aligned)", {margin + 170, 25}, cv::FONT_HERSHEY_SIMPLEX, 0.6,
                cv::Scalar(0, 0, 220), 2);
    // Scale bar: a round length near a fifth of the span.
    const double bar = std::pow(10.0, std::floor(std::log10(span / 5.0)));
    const cv::Point b0(margin, size_px - 20);
    cv::line(img, b0, b0 + cv::Point(static_cast<int>(bar * scale), 0), cv::Scalar(0, 0, 0), 3);
    cv::putText(img, fmt::format("{:g} m", bar),
                b0 + cv::Point(static_cast<int>(bar * scale) + 10, 5), cv::FONT_HERSHEY_SIMPLEX,
                0.5, cv::Scalar(0, 0, 0), 1);
    if (!cv::imwrite(png_path, img)) {
        return Status(
            StatusCode::kIoError,
            fmt::format("plot: cannot write {} (directory exists? .png name?)", png_path));
    }
    return Status::ok();
}

}  // namespace handscan::eval
