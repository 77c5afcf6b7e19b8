// Checks shared by the e2e tests that look at a handscan-ui screenshot.
#pragma once

#include <opencv2/imgproc.hpp>

namespace handscan::test {

// The fraction of pixels that differ from the background (the most common grey level): near 0
// for a blank or uniform frame.
inline double nonBackgroundFraction(const cv::Mat& grey) {
    cv::Mat hist;
    const int channels[] = {0};
    const int bins[] = {256};
    const float range[] = {0, 256};
    const float* ranges[] = {range};
    cv::calcHist(&grey, 1, channels, cv::Mat(), hist, 1, bins, ranges);
    double background = 0;
    cv::minMaxLoc(hist, nullptr, &background);
    return 1.0 - background / static_cast<double>(grey.total());
}

}  // namespace handscan::test
