// The "continue scan" screen: the earlier scan's map from above, where the operator taps where
// they stand and drags the way they face (StartPlacement), then starts the continued scan there,
// or where the earlier scan started, or goes back. Drawn with Dear ImGui over the 3D view.
#pragma once

#include <imgui.h>

#include <Eigen/Core>
#include <span>
#include <string>

#include "handscan/shm/layout.hpp"
#include "handscan/ui/start_placement.hpp"
#include "screen_layout.hpp"

namespace handscan::ui {

class StartPlacementPanel {
public:
    enum class Action { kNone, kContinue, kCancel };

    bool active() const { return active_; }
    // `again`: the continued scan is running and has not found its place; the operator says
    // where they stand now (no "where it started", nothing to start).
    void open(bool again = false) {
        active_ = true;
        again_ = again;
        placement_.clear();
    }
    void close() { active_ = false; }
    const StartPlacement& placement() const { return placement_; }

    // Touches in the view: press places, drag turns. `view_proj` is the frame's camera, `path`
    // the earlier scan's (the height of a placed point).
    void handleInput(const ScreenLayout& l, const Eigen::Matrix4f& view_proj,
                     std::span<const shm::TrackPoint> path);
    // The placed start as a marker with its heading, and the instruction.
    void drawOverlay(const ScreenLayout& l, const Eigen::Matrix4f& view_proj, ImFont* big) const;
    // The panel's buttons (in the button column's window); kContinue with `argument` set to the
    // continue command's argument.
    Action drawButtons(float w, float h, std::string& argument);

private:
    bool active_ = false;
    bool again_ = false;
    bool pressing_ = false;
    StartPlacement placement_;
};

}  // namespace handscan::ui
