#include "start_placement_panel.hpp"

#include <cmath>

namespace handscan::ui {
namespace {

// Map point -> window pixel under the view's camera (none behind the eye).
bool toScreen(const Eigen::Matrix4f& vp, const Rect& v, const Eigen::Vector3f& p, ImVec2& out) {
    const Eigen::Vector4f c = vp * p.homogeneous();
    if (c.w() <= 1e-6f) return false;
    out = ImVec2(v.x + (c.x() / c.w() + 1.0f) / 2.0f * v.w,
                 v.y + (1.0f - c.y() / c.w()) / 2.0f * v.h);
    return true;
}

}  // namespace

void StartPlacementPanel::handleInput(const ScreenLayout& l, const Eigen::Matrix4f& view_proj,
                                      std::span<const shm::TrackPoint> path) {
    const ImGuiIO& io = ImGui::GetIO();
    const ImVec2 m = io.MousePos;
    const Rect& v = l.view;
    const bool inside = m.x >= v.x && m.x < v.x + v.w && m.y >= v.y && m.y < v.y + v.h;
    if (!ImGui::IsMouseDown(ImGuiMouseButton_Left)) pressing_ = false;
    if (io.WantCaptureMouse && !pressing_) return;
    // The plane of the earlier path (its start's height) for the ray; the placed point then
    // takes the height of the path nearest it.
    const float plane_z = path.empty() ? 0.0f : path.front().z_m;
    auto at = screenToMap(view_proj, v.x, v.y, v.w, v.h, m.x, m.y, plane_z);
    if (!at) return;
    if (inside && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
        pressing_ = true;
        if (auto z = pathHeightNear(path, at->x(), at->y())) at->z() = *z;
        placement_.press(*at);
    } else if (pressing_) {
        placement_.drag(*at);
    }
}

void StartPlacementPanel::drawOverlay(const ScreenLayout& l, const Eigen::Matrix4f& view_proj,
                                      ImFont* big) const {
    ImDrawList* dl = ImGui::GetForegroundDrawList();
    ImGui::PushFont(big);
    const char* say = placement_.placed() ? "Drag from your place the way you face, then START HERE"
                                          : "Tap where you stand on the earlier scan's map";
    dl->AddRectFilled(ImVec2(l.view.x + 20, l.view.y + 10),
                      ImVec2(l.view.x + 40 + ImGui::CalcTextSize(say).x,
                             l.view.y + 22 + ImGui::GetTextLineHeight()),
                      IM_COL32(20, 60, 120, 230), 8);
    dl->AddText(ImVec2(l.view.x + 30, l.view.y + 16), IM_COL32_WHITE, say);
    ImGui::PopFont();
    if (!placement_.placed()) return;
    const Eigen::Vector3f p = *placement_.position();
    const float a = placement_.headingRad();
    const Eigen::Vector3f tip = p + 1.5f * Eigen::Vector3f(std::cos(a), std::sin(a), 0.0f);
    ImVec2 sp, st;
    if (!toScreen(view_proj, l.view, p, sp) || !toScreen(view_proj, l.view, tip, st)) return;
    const ImU32 c = IM_COL32(255, 220, 40, 255);
    dl->AddCircleFilled(sp, 12.0f * l.scale, c);
    dl->AddLine(sp, st, c, 5.0f * l.scale);
    dl->AddCircleFilled(st, 6.0f * l.scale, c);
}

StartPlacementPanel::Action StartPlacementPanel::drawButtons(float w, float h,
                                                             std::string& argument) {
    Action out = Action::kNone;
    const auto button = [&](const char* label, ImVec4 colour, bool enabled) {
        if (!enabled) ImGui::BeginDisabled();
        ImGui::PushStyleColor(ImGuiCol_Button, colour);
        const bool pressed = ImGui::Button(label, ImVec2(w, h));
        ImGui::PopStyleColor();
        if (!enabled) ImGui::EndDisabled();
        return pressed && enabled;
    };
    if (button(again_ ? "I AM HERE" : "START HERE", ImVec4(0.1f, 0.55f, 0.2f, 1),
               placement_.placed())) {
        argument = "pose=" + placement_.poseText();
        out = Action::kContinue;
    }
    if (!again_ && button("FROM ITS START", ImVec4(0.15f, 0.35f, 0.7f, 1), true)) {
        argument.clear();
        out = Action::kContinue;
    }
    if (button("CANCEL", ImVec4(0.3f, 0.3f, 0.35f, 1), true)) out = Action::kCancel;
    if (out != Action::kNone) active_ = false;
    return out;
}

}  // namespace handscan::ui
