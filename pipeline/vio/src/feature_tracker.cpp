#include "handscan/vio/feature_tracker.hpp"

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace handscan::vio {
namespace {

struct Candidate {
    float response;
    cv::Point2f px;
};

}  // namespace

FeatureTracker::FeatureTracker(const FeatureTrackerConfig& config) : config_(config) {}

void FeatureTracker::reset() {
    features_.clear();
    prev_pyramid_.clear();
}

int FeatureTracker::cellOf(const cv::Point2f& px) const {
    const auto cols = static_cast<float>(config_.grid_cols);
    const auto rows = static_cast<float>(config_.grid_rows);
    const int c = std::clamp(static_cast<int>(px.x * cols / static_cast<float>(size_.width)), 0,
                             config_.grid_cols - 1);
    const int r = std::clamp(static_cast<int>(px.y * rows / static_cast<float>(size_.height)), 0,
                             config_.grid_rows - 1);
    return r * config_.grid_cols + c;
}

TrackerFrameStats FeatureTracker::track(const cv::Mat& grey,
                                        const std::vector<cv::Point2f>* predicted) {
    TrackerFrameStats stats;
    const cv::Size win(config_.klt_window_px, config_.klt_window_px);
    if (grey.size() != size_) {
        reset();
        size_ = grey.size();
    }
    cv::buildOpticalFlowPyramid(grey, pyramid_, win, config_.klt_pyramid_levels);
    if (!features_.empty() && !prev_pyramid_.empty()) {
        std::vector<cv::Point2f> prev_px(features_.size());
        for (std::size_t i = 0; i < features_.size(); ++i) prev_px[i] = features_[i].px;
        // Start from the predicted position where there is one (the gyro's rotation, which
        // makes most of a hand-held camera's image motion), else from the previous one; the
        // pyramid's reach of about 2^levels * window/2 pixels covers the rest.
        const bool guided = predicted != nullptr && predicted->size() == features_.size();
        if (guided) next_px_ = *predicted;
        cv::calcOpticalFlowPyrLK(prev_pyramid_, pyramid_, prev_px, next_px_, status_, error_, win,
                                 config_.klt_pyramid_levels,
                                 cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                                  config_.klt_max_iterations, config_.klt_epsilon),
                                 guided ? cv::OPTFLOW_USE_INITIAL_FLOW : 0);
        const float lo = static_cast<float>(config_.border_px);
        const float hi_x = static_cast<float>(size_.width - 1 - config_.border_px);
        const float hi_y = static_cast<float>(size_.height - 1 - config_.border_px);
        std::size_t kept = 0;
        for (std::size_t i = 0; i < features_.size(); ++i) {
            const cv::Point2f p = next_px_[i];
            const bool ok = status_[i] != 0 && error_[i] <= config_.klt_max_error && p.x >= lo &&
                            p.y >= lo && p.x <= hi_x && p.y <= hi_y;
            if (!ok) continue;
            TrackedFeature f = features_[i];
            f.px = p;
            ++f.age;
            features_[kept++] = f;
        }
        stats.lost = static_cast<int>(features_.size() - kept);
        features_.resize(kept);
        stats.tracked = static_cast<int>(kept);
    } else {
        features_.clear();
    }
    detect(grey, stats);
    std::swap(prev_pyramid_, pyramid_);
    return stats;
}

void FeatureTracker::detect(const cv::Mat& grey, TrackerFrameStats& stats) {
    const int cells = config_.grid_rows * config_.grid_cols;
    const int quota = std::max(1, config_.max_features / cells);
    std::vector<int> count(static_cast<std::size_t>(cells), 0);
    for (const TrackedFeature& f : features_) ++count[static_cast<std::size_t>(cellOf(f.px))];

    // New corners keep min_distance from every tracked one and from the border.
    mask_.create(size_, CV_8UC1);
    mask_.setTo(0);
    const int b = config_.border_px;
    mask_(cv::Rect(b, b, size_.width - 2 * b, size_.height - 2 * b)).setTo(255);
    const int radius = static_cast<int>(config_.min_distance_px);
    for (const TrackedFeature& f : features_) {
        cv::circle(mask_, f.px, radius, cv::Scalar(0), cv::FILLED);
    }

    const double min_d2 = config_.min_distance_px * config_.min_distance_px;
    std::vector<Candidate> candidates;
    std::vector<cv::Point2f> accepted;
    for (int cell = 0; cell < cells; ++cell) {
        // Tracks drift between cells, so a cell's quota alone could exceed max_features.
        const int room = config_.max_features - static_cast<int>(features_.size());
        const int need = std::min(room, quota - count[static_cast<std::size_t>(cell)]);
        if (count[static_cast<std::size_t>(cell)] >= config_.refill_fraction * quota || need <= 0)
            continue;
        const int r = cell / config_.grid_cols;
        const int c = cell % config_.grid_cols;
        const int x0 = c * size_.width / config_.grid_cols;
        const int x1 = (c + 1) * size_.width / config_.grid_cols;
        const int y0 = r * size_.height / config_.grid_rows;
        const int y1 = (r + 1) * size_.height / config_.grid_rows;
        const cv::Rect roi(x0, y0, x1 - x0, y1 - y0);
        // cornerHarris on a sub-matrix reads the parent image across the cell's edges.
        cv::cornerHarris(grey(roi), response_, config_.harris_block_size, 3, config_.harris_k);
        double max_response = 0.0;
        cv::minMaxLoc(response_, nullptr, &max_response);
        const float threshold = static_cast<float>(
            std::max(config_.min_harris_response, config_.quality_level * max_response));
        if (max_response < config_.min_harris_response) continue;
        // Local maxima (3x3) above the threshold, strongest first.
        candidates.clear();
        const cv::Mat cell_mask = mask_(roi);
        for (int y = 1; y + 1 < roi.height; ++y) {
            const float* rm = response_.ptr<float>(y - 1);
            const float* r0 = response_.ptr<float>(y);
            const float* rp = response_.ptr<float>(y + 1);
            const unsigned char* m = cell_mask.ptr<unsigned char>(y);
            for (int x = 1; x + 1 < roi.width; ++x) {
                const float v = r0[x];
                if (v < threshold || m[x] == 0) continue;
                if (v < r0[x - 1] || v < r0[x + 1] || v < rm[x - 1] || v < rm[x] || v < rm[x + 1] ||
                    v < rp[x - 1] || v < rp[x] || v < rp[x + 1])
                    continue;
                candidates.push_back(
                    {v, cv::Point2f(static_cast<float>(x0 + x), static_cast<float>(y0 + y))});
            }
        }
        std::sort(candidates.begin(), candidates.end(),
                  [](const Candidate& x, const Candidate& y) { return x.response > y.response; });
        accepted.clear();
        for (const Candidate& cand : candidates) {
            if (static_cast<int>(accepted.size()) >= need) break;
            bool far = true;
            for (const cv::Point2f& a : accepted) {
                const cv::Point2f d = a - cand.px;
                if (d.dot(d) < min_d2) {
                    far = false;
                    break;
                }
            }
            if (!far) continue;
            accepted.push_back(cand.px);
            features_.push_back({next_id_++, cand.px, 0});
            ++stats.detected;
        }
    }
}

void FeatureTracker::drop(const std::vector<std::uint64_t>& ids) {
    if (ids.empty()) return;
    std::erase_if(features_, [&](const TrackedFeature& f) {
        return std::find(ids.begin(), ids.end(), f.id) != ids.end();
    });
}

}  // namespace handscan::vio
