#include "png_writer.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "gl_api.hpp"

namespace handscan::ui {

Status saveFramebufferPng(const std::string& path, int width, int height) {
    std::vector<unsigned char> rgba(static_cast<std::size_t>(width) * height * 4);
    while (glGetError() != GL_NO_ERROR) {
    }  // errors of earlier calls are not ours to report
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    if (const GLenum err = glGetError(); err != GL_NO_ERROR) {
        return {StatusCode::kDeviceError,
                "glReadPixels failed with GL error " + std::to_string(err)};
    }
    cv::Mat img(height, width, CV_8UC4, rgba.data());
    cv::Mat bgr;
    cv::cvtColor(img, bgr, cv::COLOR_RGBA2BGR);
    cv::flip(bgr, bgr, 0);  // OpenGL rows go bottom-up
    try {
        if (!cv::imwrite(path, bgr))
            return {StatusCode::kIoError, path + ": cannot write PNG (does the directory exist?)"};
    } catch (const cv::Exception& e) {
        return {StatusCode::kIoError, path + ": " + e.what()};
    }
    return Status::ok();
}

}  // namespace handscan::ui
