#include "export_preview.hpp"

#include <imgui.h>

#include <cstdint>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "gl_api.hpp"
#include "handscan/core/log.hpp"

namespace handscan::ui {

void ExportPreview::release() {
    if (texture_) glDeleteTextures(1, &texture_);
    texture_ = 0;
    facts_ = {};
}

void ExportPreview::update(const shm::ExportStatus* status) {
    const auto state =
        status ? static_cast<shm::ExportState>(status->state) : shm::ExportState::kIdle;
    if (state == shm::ExportState::kRunning) {
        facts_ = {};  // the old picture is not this export's
        return;
    }
    if (state != shm::ExportState::kDone) return;
    std::error_code ec;
    const auto mtime = std::filesystem::last_write_time(path_, ec);
    if (ec || (!facts_.path.empty() && mtime == loaded_mtime_)) return;
    cv::Mat bgr = cv::imread(path_, cv::IMREAD_COLOR);
    if (bgr.empty()) {
        log().warn("export preview {}: cannot read it as an image", path_);
        loaded_mtime_ = mtime;
        return;
    }
    cv::Mat rgba;
    cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
    if (!texture_) glGenTextures(1, &texture_);
    glBindTexture(GL_TEXTURE_2D, texture_);
    // Mipmaps: drawn a third of its size, the picture is averaged, not sampled.
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 rgba.data);
    glGenerateMipmap(GL_TEXTURE_2D);
    loaded_mtime_ = mtime;
    facts_ = {path_, rgba.cols, rgba.rows, {0, 0, 0, 0}};
}

void ExportPreview::draw(float width, float max_height) {
    facts_.drawn[0] = facts_.drawn[1] = facts_.drawn[2] = facts_.drawn[3] = 0;
    if (facts_.path.empty() || facts_.width <= 0 || width <= 0 || max_height <= 0) return;
    const float scale = std::min(width / static_cast<float>(facts_.width),
                                 max_height / static_cast<float>(facts_.height));
    const ImVec2 size(scale * static_cast<float>(facts_.width),
                      scale * static_cast<float>(facts_.height));
    const ImVec2 at = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(texture_)), size);
    facts_.drawn[0] = at.x;
    facts_.drawn[1] = at.y;
    facts_.drawn[2] = size.x;
    facts_.drawn[3] = size.y;
}

}  // namespace handscan::ui
