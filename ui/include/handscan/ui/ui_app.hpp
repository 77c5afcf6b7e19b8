// The touch-screen process: a GLFW window with the live map, the status bar and large buttons.
// It only reads the live-map region and sends commands; it runs without a pipeline ("waiting for
// pipeline") and follows a pipeline that restarts.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

#include "handscan/ui/map_renderer.hpp"
#include "handscan/ui/status_texts.hpp"
#include "handscan/ui/view_camera.hpp"

namespace handscan::ui {

struct UiOptions {
    std::string shm_name = shm::kDefaultRegionName;
    int width = 1280, height = 800;
    bool fullscreen = false;
    CameraMode camera = CameraMode::kFollow;
    ColourMode colour = ColourMode::kRgb;
    bool coverage = false;
    float point_size_px = 2.0f;
    // Points drawn per frame: 0 = adapt to keep frames near 40 ms (a software renderer draws
    // ~1 M points/s on a loaded dual core), N = at most N. Screenshots always draw every point.
    std::size_t max_draw_points = 0;
    std::optional<Eigen::Vector3f> camera_eye, camera_target;  // fixed free camera (tests, figures)
    float fov_y_deg = 60.0f;
    std::string export_target;  // argument of the export command ("" = pipeline's default)
    std::string font_path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    // --screenshot mode
    std::string screenshot_path;  // non-empty: render until the map is there, save, exit
    std::uint64_t wait_points = 1;
    double timeout_s = 10.0;
    std::string status_json_path;  // defaults to the screenshot path with .json
    double max_seconds = 0;        // > 0: exit after this long (demos, tests)
};

// Runs the UI until the window is closed (or the screenshot is taken). Returns the exit code.
int runUi(const UiOptions& options);

}  // namespace handscan::ui
