// The sidecar of a screenshot: the exact status strings the frame showed and the camera it used,
// so tests can compare the screen with the published status block and project points themselves.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "export_preview.hpp"
#include "handscan/core/status.hpp"
#include "handscan/ui/map_renderer.hpp"
#include "handscan/ui/status_texts.hpp"
#include "handscan/ui/view_camera.hpp"
#include "screen_layout.hpp"

namespace handscan::ui {

struct FrameFacts {
    CameraMode camera = CameraMode::kFollow;
    ColourMode colour = ColourMode::kRgb;
    bool coverage = false;
    int framebuffer_w = 0, framebuffer_h = 0;
    Rect view_px;  // 3D viewport in framebuffer pixels, origin top-left
    Eigen::Matrix4f view_proj = Eigen::Matrix4f::Identity();
    std::size_t points_drawn = 0;
    std::size_t track_points = 0;
    std::uint64_t epoch = 0;
    std::size_t change_cells_drawn = 0;  // a continued scan's change cells on the 3D view
    PreviewFacts preview;                // the export screen's picture of the map
    // Continue scan: the picker open, its scans and their buttons (window pixels);
    bool picking = false;
    struct PickerButton {
        std::string name;
        Rect button;
    };
    std::vector<PickerButton> picker;
    // placing the start on the earlier map, and the pose placed ("" if none).
    bool placing = false;
    bool placed = false;
    std::string placed_pose;
};

std::string statusJson(const StatusTexts& texts, const FrameFacts& facts);
[[nodiscard]] Status writeTextFile(const std::string& path, const std::string& text);

}  // namespace handscan::ui
