#include "status_json.hpp"

#include <fstream>

#include "handscan/core/json.hpp"

namespace handscan::ui {
namespace {

Json line(const Line& l) { return {{"text", l.text}, {"health", toString(l.health)}}; }

Json lines(const std::vector<Line>& ls) {
    Json out = Json::array();
    for (const Line& l : ls) out.push_back(line(l));
    return out;
}

}  // namespace

std::string statusJson(const StatusTexts& t, const FrameFacts& f) {
    Json j;
    j["connection"] = line(t.connection);
    j["scan_state"] = t.scan_state;
    j["elapsed"] = t.elapsed;
    j["distance"] = t.distance;
    j["points"] = t.points;
    j["storage"] = line(t.storage);
    j["sensors"] = lines(t.sensors);
    j["modules"] = lines(t.modules);
    j["warnings"] = lines(t.warnings);
    j["export"] = line(t.export_line);
    j["calibration"] = lines(t.calibration);
    j["message"] = t.message;
    j["localization"] = line(t.localization);
    j["can_continue"] = t.can_continue;
    j["changes"] = {{"text", t.changes.text},
                    {"health", toString(t.changes.health)},
                    {"appeared", t.changes_appeared},
                    {"vanished", t.changes_vanished},
                    {"cells_drawn", f.change_cells_drawn}};
    j["dof"] = Json::array();
    for (int i = 0; t.dof_valid && i < shm::kDofCount; ++i) j["dof"].push_back(toString(t.dof[i]));
    Json view_proj = Json::array();
    for (int i = 0; i < 16; ++i) view_proj.push_back(f.view_proj.data()[i]);
    j["view"] = {{"camera", toString(f.camera)},
                 {"colour", toString(f.colour)},
                 {"coverage", f.coverage},
                 {"framebuffer", {f.framebuffer_w, f.framebuffer_h}},
                 {"viewport", {f.view_px.x, f.view_px.y, f.view_px.w, f.view_px.h}},
                 {"view_proj_col_major", view_proj}};
    const PreviewFacts& p = f.preview;
    j["export_preview"] = {{"path", p.path},
                           {"size", {p.width, p.height}},
                           {"drawn", {p.drawn[0], p.drawn[1], p.drawn[2], p.drawn[3]}}};
    j["map"] = {
        {"points_drawn", f.points_drawn}, {"track_points", f.track_points}, {"epoch", f.epoch}};
    j["placement"] = {{"active", f.placing}, {"placed", f.placed}, {"pose", f.placed_pose}};
    Json scans = Json::array();
    for (const FrameFacts::PickerButton& b : f.picker)
        scans.push_back(
            {{"name", b.name}, {"button", {b.button.x, b.button.y, b.button.w, b.button.h}}});
    j["picker"] = {{"active", f.picking}, {"scans", scans}};
    return jsonText(j, 2) + "\n";
}

Status writeTextFile(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::trunc);
    out << text;
    out.close();
    if (!out) return {StatusCode::kIoError, path + ": cannot write (does the directory exist?)"};
    return Status::ok();
}

}  // namespace handscan::ui
