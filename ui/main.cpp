// handscan-ui: the touch-screen process. Reads the live map from shared memory, sends the
// operator's commands back; see handscan/ui/ui_app.hpp.
#include <CLI/CLI.hpp>

#include "handscan/core/log.hpp"
#include "handscan/ui/ui_app.hpp"

namespace {

bool parseVec3(const std::string& s, Eigen::Vector3f& v) {
    return std::sscanf(s.c_str(), "%f,%f,%f", &v.x(), &v.y(), &v.z()) == 3;
}

}  // namespace

int main(int argc, char** argv) {
    using namespace handscan;
    ui::UiOptions o;
    CLI::App app{"handscan-ui: live map, status and controls of the handheld scanner"};
    std::string camera = "follow", colour = "rgb", eye, target;
    int verbosity = 0;
    app.add_option("--shm-name", o.shm_name, "live-map shared-memory name")->capture_default_str();
    app.add_option("--width", o.width, "window width")->capture_default_str();
    app.add_option("--height", o.height, "window height")->capture_default_str();
    app.add_flag("--fullscreen", o.fullscreen, "full screen on the primary monitor (kiosk)");
    app.add_option("--camera", camera, "follow, top-down or free")
        ->check(CLI::IsMember({"follow", "top-down", "free"}));
    app.add_option("--colour", colour, "rgb, height or intensity")
        ->check(CLI::IsMember({"rgb", "height", "intensity"}));
    app.add_flag("--coverage", o.coverage, "start in the coverage view");
    app.add_option("--camera-eye", eye, "fixed free camera: eye position x,y,z in metres");
    app.add_option("--camera-target", target, "fixed free camera: look-at point x,y,z in metres");
    app.add_option("--fov", o.fov_y_deg, "vertical field of view, degrees")->capture_default_str();
    app.add_option("--point-size", o.point_size_px, "point size in pixels")->capture_default_str();
    app.add_option("--max-draw-points", o.max_draw_points,
                   "points drawn per frame (0 = adapt to the renderer's speed)")
        ->capture_default_str();
    app.add_option("--export-target", o.export_target, "directory passed with the export command");
    app.add_option("--font", o.font_path, "TrueType font")->capture_default_str();
    app.add_option("--screenshot", o.screenshot_path,
                   "render until the map is there, save this PNG and exit");
    app.add_option("--wait-points", o.wait_points, "with --screenshot: points the map must hold")
        ->capture_default_str();
    app.add_option("--timeout", o.timeout_s, "with --screenshot: seconds to wait for them")
        ->capture_default_str();
    app.add_option("--status-json", o.status_json_path,
                   "with --screenshot: where to write the shown status texts "
                   "(default: screenshot path with .json); without: rewritten 4 times a second "
                   "while the UI runs (tests)");
    app.add_option("--max-seconds", o.max_seconds, "exit after this many seconds (demos)");
    app.add_flag("-v,--verbose", verbosity, "more logging");
    CLI11_PARSE(app, argc, argv);
    initLogging("handscan-ui", verbosity);
    o.camera = camera == "top-down" ? ui::CameraMode::kTopDown
               : camera == "free"   ? ui::CameraMode::kFree
                                    : ui::CameraMode::kFollow;
    o.colour = colour == "height"      ? ui::ColourMode::kHeight
               : colour == "intensity" ? ui::ColourMode::kIntensity
                                       : ui::ColourMode::kRgb;
    if (!eye.empty() || !target.empty()) {
        Eigen::Vector3f e, t;
        if (!parseVec3(eye, e) || !parseVec3(target, t)) {
            log().error(
                "--camera-eye and --camera-target need both to be given as x,y,z (got '{}' and "
                "'{}')",
                eye, target);
            return 2;
        }
        o.camera_eye = e;
        o.camera_target = t;
    }
    return ui::runUi(o);
}
