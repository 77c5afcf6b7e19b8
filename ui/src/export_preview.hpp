// The export screen's picture of the map: once an export is done, the PNG the pipeline left beside
// the live-map region (shm::exportPreviewPath: the scan report's map from above, the image
// report.html and report.pdf show first) is loaded into a texture and drawn under the export's
// status in the buttons panel. A missing or unreadable file shows nothing (the export itself is
// what matters); a new export's picture replaces the old one.
#pragma once

#include <filesystem>
#include <string>

#include "handscan/shm/layout.hpp"

namespace handscan::ui {

struct PreviewFacts {
    std::string path;  // the PNG shown ("" when none)
    int width = 0, height = 0;
    float drawn[4] = {0, 0, 0, 0};  // x, y, w, h in window pixels (0 when not drawn)
};

class ExportPreview {
public:
    explicit ExportPreview(std::string path) : path_(std::move(path)) {}
    // The texture, while the GL context is still current (the UI's destructor calls it).
    void release();
    ExportPreview(const ExportPreview&) = delete;
    ExportPreview& operator=(const ExportPreview&) = delete;

    // Loads the picture when an export has finished since (and forgets it when a new one runs).
    void update(const shm::ExportStatus* status);
    // Draws it `width` wide (at most `max_height` high) at ImGui's cursor.
    void draw(float width, float max_height);
    const PreviewFacts& facts() const { return facts_; }

private:
    std::string path_;
    unsigned texture_ = 0;
    std::filesystem::file_time_type loaded_mtime_{};
    PreviewFacts facts_;
};

}  // namespace handscan::ui
