// FeatureTracker (section 5, Figure 4): Harris corners tracked from frame to frame with pyramidal
// Lucas-Kanade (OpenCV), at most `max_features` spread over a grid of cells (5 rows x 6 columns
// on the 640x512 tracking camera) so that the motion problem sees the whole field of view. A cell
// whose features were lost is topped up with its strongest new corners, away from the surviving
// ones. Corners must pass an absolute Harris response as well as the relative quality, so a dark
// or texture-less image yields no features (the VIO then reports its directions unsolved,
// section 8) instead of tracked noise.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace handscan::vio {

struct FeatureTrackerConfig {
    int grid_rows = 5;
    int grid_cols = 6;
    int max_features = 300;
    // A cell is topped up when it holds fewer than this fraction of its quota (max / cells):
    // detection costs more than tracking, so a cell that lost one corner waits.
    double refill_fraction = 0.75;
    double min_distance_px = 10.0;  // between corners (new ones keep away from tracked ones)
    int border_px = 8;              // corners and tracks this close to the edge are dropped
    int harris_block_size = 3;
    double harris_k = 0.04;
    double quality_level = 0.01;  // of the strongest response in the cell
    // Absolute Harris response (OpenCV's cornerHarris scaling, 8-bit image, Sobel 3): sensor
    // noise of a few DN gives ~1e-8, a corner of 10 DN contrast ~3e-7.
    double min_harris_response = 5e-8;
    // 15 x 15 windows on 3 pyramid levels: the gyro's prediction (track()) leaves only the
    // translation's few pixels to find, and half the window area halves KLT's cost (21 x 21 on
    // 4 levels without prediction cost 2.1 ms of a 4.6 ms frame; mean segment drift with
    // --modules all on 30 s seeds 601-602: tunnel 1.8/2.4 -> 1.4/1.4 %, field 4.6/5.0 ->
    // 5.1/5.5 %, within the field's spread from run to run of any change).
    int klt_window_px = 15;
    int klt_pyramid_levels = 2;
    int klt_max_iterations = 30;
    double klt_epsilon = 0.01;
    double klt_max_error = 30.0;  // mean absolute patch difference (DN) above which a track is lost
};

struct TrackedFeature {
    std::uint64_t id = 0;  // unique over the tracker's life
    cv::Point2f px;        // pixel in the current frame
    int age = 0;           // frames tracked (0: detected in this frame)
};

struct TrackerFrameStats {
    int tracked = 0;   // features carried over from the previous frame
    int lost = 0;      // of the previous frame's features
    int detected = 0;  // new corners
};

class FeatureTracker {
public:
    explicit FeatureTracker(const FeatureTrackerConfig& config = {});

    // Tracks the features into `grey` (CV_8UC1) and tops up the grid. The first call only
    // detects. `predicted`, when given, holds where each of features() is expected in `grey`
    // (from the gyro's rotation): the search starts there instead of at the last position.
    TrackerFrameStats track(const cv::Mat& grey,
                            const std::vector<cv::Point2f>* predicted = nullptr);
    // Drops features by id (outliers of the motion estimation); their cells refill next frame.
    void drop(const std::vector<std::uint64_t>& ids);
    void reset();

    const std::vector<TrackedFeature>& features() const { return features_; }
    const FeatureTrackerConfig& config() const { return config_; }
    // Cell index (row-major) of a pixel in an image of the last frame's size.
    int cellOf(const cv::Point2f& px) const;

private:
    void detect(const cv::Mat& grey, TrackerFrameStats& stats);

    FeatureTrackerConfig config_;
    std::vector<TrackedFeature> features_;
    std::vector<cv::Mat> prev_pyramid_;
    cv::Size size_;
    std::uint64_t next_id_ = 1;
    // Scratch, kept between frames to avoid reallocation.
    cv::Mat mask_;
    cv::Mat response_;
    std::vector<cv::Mat> pyramid_;
    std::vector<cv::Point2f> next_px_;
    std::vector<unsigned char> status_;
    std::vector<float> error_;
};

}  // namespace handscan::vio
