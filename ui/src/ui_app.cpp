// The UI's main loop: read what is new in the live map, draw the 3D view (or the coverage view),
// the status bar, the operator's buttons and warnings; in --screenshot mode, save a frame once
// the map is there.
#include "handscan/ui/ui_app.hpp"

#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <limits>
#include <thread>

#include "change_cells_renderer.hpp"
#include "export_preview.hpp"
#include "gl_api.hpp"
#include "handscan/core/log.hpp"
#include "handscan/shm/export_preview.hpp"
#include "handscan/shm/live_map_reader.hpp"
#include "handscan/shm/text_field.hpp"
#include "handscan/ui/coverage_grid.hpp"
#include "png_writer.hpp"
#include "scan_picker_panel.hpp"
#include "screen_layout.hpp"
#include "start_placement_panel.hpp"
#include "status_json.hpp"

namespace handscan::ui {
namespace {

constexpr std::size_t kUploadBudgetPoints =
    2'000'000;  // per frame: keeps frames short while catching up

ImVec4 colourOf(Health h) {
    switch (h) {
        case Health::kOk:
            return {0.35f, 0.9f, 0.45f, 1.0f};
        case Health::kWarning:
            return {1.0f, 0.72f, 0.15f, 1.0f};
        case Health::kError:
            return {1.0f, 0.32f, 0.3f, 1.0f};
    }
    return {1, 1, 1, 1};
}

// Figure 14's colours: IMU prediction orange, visual-inertial odometry green, scan matching blue.
ImU32 dofColour(DofSource s) {
    switch (s) {
        case DofSource::kImu:
            return IM_COL32(245, 150, 40, 255);
        case DofSource::kVio:
            return IM_COL32(70, 200, 90, 255);
        case DofSource::kScan:
            return IM_COL32(60, 120, 235, 255);
    }
    return IM_COL32_WHITE;
}

constexpr ImGuiWindowFlags kPanelFlags =
    ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoMove |
    ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoScrollbar |
    ImGuiWindowFlags_NoBringToFrontOnFocus;

struct PendingCommand {
    std::uint64_t seq = 0;
    shm::CommandType type = shm::CommandType::kNone;
    Line result;
    bool finished = false;
};

class UiApp {
public:
    explicit UiApp(UiOptions o)
        : o_(std::move(o)),
          reader_(readerOptions(o_.shm_name)),
          preview_(shm::exportPreviewPath(o_.shm_name)) {
        camera_.mode = o_.camera;
        camera_.fov_y_deg = o_.fov_y_deg;
        if (o_.camera_eye && o_.camera_target)
            camera_.setExplicit(*o_.camera_eye, *o_.camera_target);
        colour_ = o_.colour;
        coverage_view_ = o_.coverage;
    }
    ~UiApp();
    int run();

private:
    static shm::ReaderOptions readerOptions(const std::string& name) {
        shm::ReaderOptions r;
        r.name = name;
        return r;
    }
    Status initWindow();
    void ingest();
    void updateCamera();
    void handleViewInput(const ScreenLayout& l);
    void drawView(const ScreenLayout& l);
    void drawStatusBar(const ScreenLayout& l);
    void drawButtons(const ScreenLayout& l);
    void drawOverlay(const ScreenLayout& l);
    void drawCoverage(const ScreenLayout& l);
    void drawDegeneracyBar(ImDrawList* dl, ImVec2 origin, float cell);
    void readChanges();
    void drawChangesLegend(ImDrawList* dl, const ScreenLayout& l);
    void send(shm::CommandType type, const std::string& argument = {});
    void trackCommand();
    bool bigButton(const char* label, ImVec4 colour, float w, float h, bool enabled = true);
    int finishScreenshot(bool timed_out);
    void openStartPlacement(const ScreenLayout& l, bool again = false);
    void writeStatusJsonNow();

    UiOptions o_;
    shm::LiveMapReader reader_;
    GLFWwindow* window_ = nullptr;
    bool imgui_ready_ = false;
    MapRenderer renderer_;
    ChangeCellsRenderer changes_renderer_;
    shm::ChangesCursor changes_cursor_;
    shm::ChangeReport changes_;  // the one drawn (its epoch the map's), empty if none
    ViewCamera camera_;
    ColourMode colour_;
    bool coverage_view_;
    bool top_down_follows_device_ = true;
    CoverageGrid coverage_;
    unsigned coverage_texture_ = 0;
    CoverageImage coverage_image_;
    bool coverage_dirty_ = false;
    double coverage_uploaded_at_ = -1.0;
    std::vector<shm::TrackPoint> track_cpu_;
    shm::MapCursor cursor_;
    shm::MapDelta delta_;
    std::optional<shm::StatusBlock> status_;
    std::optional<shm::PoseRecord> pose_;
    StatusTexts texts_;
    PendingCommand command_;
    ImFont* font_normal_ = nullptr;
    ImFont* font_big_ = nullptr;
    FrameFacts facts_;
    bool status_seen_ = false;
    std::size_t draw_budget_ = 2'000'000;
    ExportPreview preview_;
    ScanPickerPanel picker_;       // continue scan: which scan
    StartPlacementPanel placing_;  // continue scan: where the operator stands on the earlier map
    // A picked scan's continue command is under way: the placement follows once it is done.
    bool place_after_continue_ = false;
    double status_json_at_ = -1.0;
};

UiApp::~UiApp() {
    if (coverage_texture_) glDeleteTextures(1, &coverage_texture_);
    preview_.release();
    if (imgui_ready_) {
        ImGui_ImplOpenGL3_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
    }
    if (window_) glfwDestroyWindow(window_);
    glfwTerminate();
}

Status UiApp::initWindow() {
    glfwSetErrorCallback(
        [](int code, const char* what) { log().error("GLFW error {}: {}", code, what); });
    if (!glfwInit()) {
        return {StatusCode::kDeviceError,
                "cannot initialise GLFW: no display? (set DISPLAY, or run under Xvfb / xvfb-run)"};
    }
    glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
    glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
    glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
    glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
    GLFWmonitor* monitor = o_.fullscreen ? glfwGetPrimaryMonitor() : nullptr;
    int w = o_.width, h = o_.height;
    if (monitor) {
        const GLFWvidmode* mode = glfwGetVideoMode(monitor);
        w = mode->width;
        h = mode->height;
    }
    window_ = glfwCreateWindow(w, h, "handscan", monitor, nullptr);
    if (!window_)
        return {StatusCode::kDeviceError,
                "cannot create an OpenGL 3.3 core window (Mesa installed? see GLFW error above)"};
    glfwMakeContextCurrent(window_);
    glfwSwapInterval(o_.screenshot_path.empty() ? 1 : 0);
    log().info("OpenGL {} on {}", reinterpret_cast<const char*>(glGetString(GL_VERSION)),
               reinterpret_cast<const char*>(glGetString(GL_RENDERER)));

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;  // a kiosk has no per-user layout to remember
    const float scale = ScreenLayout::compute(static_cast<float>(w), static_cast<float>(h)).scale;
    if (std::filesystem::exists(o_.font_path)) {
        font_normal_ = io.Fonts->AddFontFromFileTTF(o_.font_path.c_str(), 19.0f * scale);
        font_big_ = io.Fonts->AddFontFromFileTTF(o_.font_path.c_str(), 28.0f * scale);
    }
    if (!font_normal_ || !font_big_) {
        log().warn("font {} not found: using ImGui's small built-in font, scaled", o_.font_path);
        font_normal_ = font_big_ = io.Fonts->AddFontDefault();
        io.FontGlobalScale = 1.5f * scale;
    }
    ImGui::StyleColorsDark();
    ImGui::GetStyle().FrameRounding = 8.0f;
    ImGui::GetStyle().TouchExtraPadding = ImVec2(6, 6);  // fingers are less precise than a mouse
    ImGui_ImplGlfw_InitForOpenGL(window_, true);
    ImGui_ImplOpenGL3_Init("#version 330 core");
    imgui_ready_ = true;
    if (Status s = changes_renderer_.init(); !s) return s;
    return renderer_.init();
}

void UiApp::ingest() {
    const shm::Connection c = reader_.poll();
    if (c == shm::Connection::kWaiting || c == shm::Connection::kIncompatible) {
        status_.reset();
        pose_.reset();
        if (changes_.count > 0 || changes_.appeared + changes_.vanished > 0) {
            changes_.count = changes_.appeared = changes_.vanished = 0;
            changes_renderer_.set(changes_);
        }
        changes_cursor_ = {};
    } else {
        if (reader_.readMap(cursor_, delta_, kUploadBudgetPoints)) {
            if (delta_.reset) {
                renderer_.reset();
                coverage_.clear();
                track_cpu_.clear();
                top_down_follows_device_ = true;
                changes_cursor_ = {};  // read the new scan's report again, whatever came first
            }
            renderer_.appendPoints(delta_.points);
            renderer_.appendTrack(delta_.track);
            const auto pose = reader_.latestPose();
            coverage_.add(delta_.points, pose ? static_cast<float>(pose->position_m[2]) - 0.5f
                                              : std::numeric_limits<float>::infinity());
            track_cpu_.insert(track_cpu_.end(), delta_.track.begin(), delta_.track.end());
            if (!delta_.points.empty() || delta_.reset) coverage_dirty_ = true;
        }
        if (auto s = reader_.readStatus()) {
            status_ = s;
            status_seen_ = s->t_ns != 0 || status_seen_;
        }
        pose_ = reader_.latestPose();
        readChanges();
    }
    renderer_.setDevice(pose_);
    texts_ = describeStatus(c, reader_.message(), status_seen_ ? status_ : std::nullopt, pose_);
    describeChanges(changes_, texts_);
    trackCommand();
}

void UiApp::readChanges() {
    shm::ChangeReport r;
    if (!reader_.readChanges(changes_cursor_, r)) return;
    // A report of another scan than the map's (read across a new scan) is not drawn; the new
    // scan's own comes with the next publication, or is read again at the map's reset.
    if (r.epoch != cursor_.epoch) r.count = r.appeared = r.vanished = 0;
    changes_ = r;
    changes_renderer_.set(changes_);
}

void UiApp::updateCamera() {
    if (!pose_) return;
    const Eigen::Vector3f p(static_cast<float>(pose_->position_m[0]),
                            static_cast<float>(pose_->position_m[1]),
                            static_cast<float>(pose_->position_m[2]));
    const Eigen::Quaterniond q(pose_->orientation_xyzw[3], pose_->orientation_xyzw[0],
                               pose_->orientation_xyzw[1], pose_->orientation_xyzw[2]);
    const Eigen::Vector3d x_axis = q.normalized() * Eigen::Vector3d::UnitX();
    camera_.setDevice(p, static_cast<float>(std::atan2(x_axis.y(), x_axis.x())));
    if (camera_.mode == CameraMode::kTopDown && top_down_follows_device_) camera_.target = p;
}

void UiApp::handleViewInput(const ScreenLayout& l) {
    if (placing_.active()) return placing_.handleInput(l, facts_.view_proj, track_cpu_);
    ImGuiIO& io = ImGui::GetIO();
    if (io.WantCaptureMouse) return;
    const ImVec2 m = io.MousePos;
    const bool inside = m.x >= l.view.x && m.x < l.view.x + l.view.w && m.y >= l.view.y &&
                        m.y < l.view.y + l.view.h;
    // Single touch arrives as the left mouse button: drag to orbit (or pan in top-down).
    if (inside && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f)) {
        camera_.drag(io.MouseDelta.x, io.MouseDelta.y);
        if (camera_.mode == CameraMode::kTopDown) top_down_follows_device_ = false;
    }
    if (inside && io.MouseWheel != 0.0f) camera_.zoom(std::pow(0.85f, io.MouseWheel));
}

void UiApp::send(shm::CommandType type, const std::string& argument) {
    auto seq = reader_.sendCommand(type, argument);
    command_ = PendingCommand{};
    command_.type = type;
    if (!seq) {
        command_.result = {seq.status().message(), Health::kError};
        command_.finished = true;
        return;
    }
    command_.seq = *seq;
    command_.result = {std::string(shm::toString(type)) + ": sent", Health::kWarning};
    log().info("sent {} (#{})", shm::toString(type), *seq);
}

void UiApp::trackCommand() {
    if (command_.seq == 0 || command_.finished) return;
    auto r = reader_.commandResult(command_.seq);
    const std::string name = shm::toString(command_.type);
    if (!r) {
        command_.result = {name + ": " + r.status().message(), Health::kError};
        command_.finished = r.status().code() != StatusCode::kTimeout;
        return;
    }
    const auto state = static_cast<shm::CommandState>(r->state);
    const std::string msg(shm::getText(r->message));
    switch (state) {
        case shm::CommandState::kPending:
            command_.result = {name + ": waiting for pipeline", Health::kWarning};
            break;
        case shm::CommandState::kAccepted:
        case shm::CommandState::kInProgress:
            command_.result = {name + ": " + msg, Health::kWarning};
            break;
        case shm::CommandState::kDone:
            command_.result = {name + ": " + msg, Health::kOk};
            command_.finished = true;
            break;
        case shm::CommandState::kFailed:
        case shm::CommandState::kRejected:
            command_.result = {name + " " + shm::toString(state) + ": " + msg, Health::kError};
            command_.finished = true;
            break;
    }
}

bool UiApp::bigButton(const char* label, ImVec4 colour, float w, float h, bool enabled) {
    if (!enabled) ImGui::BeginDisabled();
    ImGui::PushStyleColor(ImGuiCol_Button, colour);
    ImGui::PushStyleColor(ImGuiCol_ButtonHovered,
                          ImVec4(colour.x * 1.15f, colour.y * 1.15f, colour.z * 1.15f, 1));
    ImGui::PushStyleColor(ImGuiCol_ButtonActive,
                          ImVec4(colour.x * 0.8f, colour.y * 0.8f, colour.z * 0.8f, 1));
    const bool pressed = ImGui::Button(label, ImVec2(w, h));
    ImGui::PopStyleColor(3);
    if (!enabled) ImGui::EndDisabled();
    return pressed && enabled;
}

void UiApp::drawStatusBar(const ScreenLayout& l) {
    ImGui::SetNextWindowPos(ImVec2(l.status_bar.x, l.status_bar.y));
    ImGui::SetNextWindowSize(ImVec2(l.status_bar.w, l.status_bar.h));
    ImGui::Begin("status", nullptr, kPanelFlags);
    ImGui::PushFont(font_big_);
    ImGui::TextColored(colourOf(texts_.connection.health), "%s",
                       texts_.connection.health == Health::kOk ? "PIPELINE OK" : "NO PIPELINE");
    const auto item = [](const std::string& s, ImVec4 c = ImVec4(1, 1, 1, 1)) {
        if (s.empty()) return;
        ImGui::SameLine(0, 28);
        ImGui::TextColored(c, "%s", s.c_str());
    };
    item(texts_.scan_state,
         texts_.scan_state == "SCANNING" ? colourOf(Health::kOk) : ImVec4(0.9f, 0.9f, 0.9f, 1));
    item(texts_.elapsed);
    item(texts_.distance);
    item(texts_.points);
    item(texts_.storage.text, colourOf(texts_.storage.health));
    ImGui::PopFont();
    // Second row: every sensor's health and rate, then the modules.
    bool first = true;
    for (const Line& s : texts_.sensors) {
        if (!first) ImGui::SameLine(0, 22);
        first = false;
        ImGui::TextColored(colourOf(s.health), "%s", s.text.c_str());
    }
    if (texts_.sensors.empty())
        ImGui::TextColored(colourOf(texts_.connection.health), "%s",
                           texts_.connection.text.c_str());
    first = true;
    for (const Line& m : texts_.modules) {
        if (!first) ImGui::SameLine(0, 22);
        first = false;
        ImGui::TextColored(colourOf(m.health), "%s", m.text.c_str());
    }
    ImGui::End();
}

void UiApp::drawButtons(const ScreenLayout& l) {
    ImGui::SetNextWindowPos(ImVec2(l.buttons.x, l.buttons.y));
    ImGui::SetNextWindowSize(ImVec2(l.buttons.w, l.buttons.h));
    ImGui::Begin("buttons", nullptr, kPanelFlags);
    const float pad = ImGui::GetStyle().WindowPadding.x;
    const float w = l.buttons.w - 2 * pad;
    const float h = 64.0f * l.scale;
    const float gap = ImGui::GetStyle().ItemSpacing.x;
    const bool connected = reader_.connection() == shm::Connection::kConnected;
    const auto state =
        status_ ? static_cast<shm::ScanState>(status_->scan_state) : shm::ScanState::kIdle;
    const bool exporting = status_ && static_cast<shm::ExportState>(status_->export_status.state) ==
                                          shm::ExportState::kRunning;
    ImGui::PushFont(font_big_);
    if (place_after_continue_ && command_.type == shm::CommandType::kContinueScan &&
        command_.finished) {
        // The picked scan's map and path are on the screen now: where does the operator stand?
        place_after_continue_ = false;
        if (command_.result.health == Health::kOk) openStartPlacement(l, true);
    }
    if (picker_.active()) {
        ScanPickerPanel::Listed picked;
        const auto action = picker_.drawButtons(w, h, picked);
        if (action == ScanPickerPanel::Action::kPick && picked.current) {
            openStartPlacement(l);  // the stopped scan: its map is on the screen already
        } else if (action == ScanPickerPanel::Action::kPick) {
            send(shm::CommandType::kContinueScan, "scan=" + picked.name);
            place_after_continue_ = true;
        }
        ImGui::PopFont();
        ImGui::End();
        return;
    }
    if (placing_.active()) {
        std::string argument;
        const auto action = placing_.drawButtons(w, h * 1.3f, argument);
        if (action == StartPlacementPanel::Action::kContinue)
            send(shm::CommandType::kContinueScan, argument);
        ImGui::PopFont();
        ImGui::End();
        return;
    }
    if (state == shm::ScanState::kScanning) {
        if (bigButton("STOP SCAN", ImVec4(0.75f, 0.15f, 0.12f, 1), w, h * 1.3f, connected))
            send(shm::CommandType::kStopScan);
    } else {
        if (bigButton("START SCAN", ImVec4(0.1f, 0.55f, 0.2f, 1), w, h * 1.3f,
                      connected && !exporting)) {
            send(shm::CommandType::kStartScan);
        }
    }
    const bool stopped = state == shm::ScanState::kStopped;
    if (bigButton("EXPORT TO USB", ImVec4(0.15f, 0.35f, 0.7f, 1), w, h,
                  connected && stopped && !exporting)) {
        send(shm::CommandType::kExport, o_.export_target);
    }
    if (bigButton("NEW SCAN", ImVec4(0.3f, 0.3f, 0.35f, 1), w, h,
                  connected && stopped && !exporting)) {
        send(shm::CommandType::kNewScan);
    }
    // Continue the stopped scan (placing oneself on its map), or the newest earlier one; while a
    // continued scan has not found its place, in the same place: the operator places themselves
    // again.
    const auto lock = status_ ? static_cast<shm::LocalizationState>(status_->localization)
                              : shm::LocalizationState::kNone;
    const bool searching =
        lock == shm::LocalizationState::kSearching || lock == shm::LocalizationState::kNotLocked;
    if (state == shm::ScanState::kScanning) {
        if (bigButton("PLACE ME", ImVec4(0.45f, 0.3f, 0.6f, 1), w, h, connected && searching))
            openStartPlacement(l, true);
    } else if (bigButton("CONTINUE SCAN", ImVec4(0.45f, 0.3f, 0.6f, 1), w, h,
                         connected && !exporting && (stopped || texts_.can_continue))) {
        // Which scan: a choice among the pipeline's list when it has more than one; else the
        // stopped scan (placed on), or the newest (from its start).
        const auto scans = reader_.readScanList();
        if (scans && scans->count > 1)
            picker_.open(*scans);
        else if (stopped)
            openStartPlacement(l);
        else
            send(shm::CommandType::kContinueScan);
    }
    // Self-calibration on the scan just stopped (laser on its shaft, encoder zero, clocks).
    const bool calibrating =
        status_ && static_cast<shm::CalibrationState>(status_->calibration.state) ==
                       shm::CalibrationState::kRunning;
    if (bigButton("CALIBRATE", ImVec4(0.45f, 0.3f, 0.1f, 1), w, h,
                  connected && stopped && !exporting && !calibrating)) {
        send(shm::CommandType::kCalibrate);
    }
    ImGui::PopFont();
    if (calibrating) ImGui::ProgressBar(status_->calibration.progress, ImVec2(w, 26.0f * l.scale));
    for (const Line& c : texts_.calibration) {
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + w);
        ImGui::TextColored(colourOf(c.health), "%s", c.text.c_str());
        ImGui::PopTextWrapPos();
    }
    if (status_ &&
        static_cast<shm::ExportState>(status_->export_status.state) != shm::ExportState::kIdle) {
        ImGui::ProgressBar(status_->export_status.progress, ImVec2(w, 26.0f * l.scale));
    }
    if (!texts_.export_line.text.empty()) {
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + w);
        ImGui::TextColored(colourOf(texts_.export_line.health), "%s",
                           texts_.export_line.text.c_str());
        ImGui::PopTextWrapPos();
    }
    // The exported map as the scan report shows it, once the export is done.
    preview_.update(status_ ? &status_->export_status : nullptr);
    preview_.draw(w, 0.3f * l.buttons.h);
    ImGui::Separator();
    // Camera and colouring: three-way toggles in rows of big buttons.
    const float third = (w - 2 * gap) / 3;
    const ImVec4 on(0.2f, 0.45f, 0.75f, 1), off(0.22f, 0.22f, 0.26f, 1);
    const struct {
        const char* label;
        CameraMode mode;
    } cams[] = {{"Follow", CameraMode::kFollow},
                {"Top", CameraMode::kTopDown},
                {"Free", CameraMode::kFree}};
    for (int i = 0; i < 3; ++i) {
        if (i) ImGui::SameLine();
        if (bigButton(cams[i].label, camera_.mode == cams[i].mode && !coverage_view_ ? on : off,
                      third, h * 0.8f)) {
            if (cams[i].mode == CameraMode::kFree && camera_.mode != CameraMode::kFree && pose_) {
                camera_.target = Eigen::Vector3f(static_cast<float>(pose_->position_m[0]),
                                                 static_cast<float>(pose_->position_m[1]),
                                                 static_cast<float>(pose_->position_m[2]));
            }
            camera_.mode = cams[i].mode;
            coverage_view_ = false;
        }
    }
    const struct {
        const char* label;
        ColourMode mode;
    } cols[] = {{"RGB", ColourMode::kRgb},
                {"Height", ColourMode::kHeight},
                {"Intens.", ColourMode::kIntensity}};
    for (int i = 0; i < 3; ++i) {
        if (i) ImGui::SameLine();
        if (bigButton(cols[i].label, colour_ == cols[i].mode ? on : off, third, h * 0.8f))
            colour_ = cols[i].mode;
    }
    if (bigButton(coverage_view_ ? "COVERAGE: ON" : "COVERAGE", coverage_view_ ? on : off, w, h))
        coverage_view_ = !coverage_view_;
    if (bigButton("-", off, third, h * 0.8f)) camera_.zoom(1.25f);
    ImGui::SameLine();
    if (bigButton("+", off, third, h * 0.8f)) camera_.zoom(0.8f);
    ImGui::SameLine();
    if (bigButton("Centre", off, third, h * 0.8f)) {
        top_down_follows_device_ = true;
        camera_.yaw_rad = 0.0f;
        camera_.pitch_rad = 0.6f;
    }
    if (!command_.result.text.empty()) {
        ImGui::PushTextWrapPos(ImGui::GetCursorPosX() + w);
        ImGui::TextColored(colourOf(command_.result.health), "%s", command_.result.text.c_str());
        ImGui::PopTextWrapPos();
    }
    ImGui::End();
}

void UiApp::drawDegeneracyBar(ImDrawList* dl, ImVec2 origin, float cell) {
    // Figure 14: one row per DOF; columns IMU prediction, VIO, scan matching, and the combination
    // the pose carries (white = that module did not solve the DOF).
    const char* heads[] = {"IMU", "VIO", "LSR", "POSE"};
    const float label_w = cell * 1.3f;
    dl->AddRectFilled(ImVec2(origin.x - 6, origin.y - cell - 6),
                      ImVec2(origin.x + label_w + 4 * cell * 1.6f + 6, origin.y + 6 * cell + 6),
                      IM_COL32(0, 0, 0, 160), 6);
    for (int c = 0; c < 4; ++c) {
        dl->AddText(ImVec2(origin.x + label_w + c * cell * 1.6f, origin.y - cell), IM_COL32_WHITE,
                    heads[c]);
    }
    for (int r = 0; r < shm::kDofCount; ++r) {
        const float y = origin.y + r * cell;
        dl->AddText(ImVec2(origin.x, y), IM_COL32_WHITE, shm::kDofNames[r]);
        const ImU32 cells[4] = {
            dofColour(DofSource::kImu),
            texts_.vio_dof[r] ? dofColour(DofSource::kVio) : IM_COL32_WHITE,
            texts_.scan_dof[r] ? dofColour(DofSource::kScan) : IM_COL32_WHITE,
            dofColour(texts_.dof[r]),
        };
        for (int c = 0; c < 4; ++c) {
            const ImVec2 a(origin.x + label_w + c * cell * 1.6f, y + 2);
            dl->AddRectFilled(a, ImVec2(a.x + cell * 1.4f, a.y + cell - 4), cells[c], 3);
        }
    }
}

void UiApp::drawOverlay(const ScreenLayout& l) {
    ImDrawList* dl = ImGui::GetForegroundDrawList();
    ImGui::PushFont(font_big_);
    if (reader_.connection() != shm::Connection::kConnected && renderer_.pointCount() == 0) {
        const std::string big = reader_.connection() == shm::Connection::kWaiting
                                    ? "Waiting for pipeline..."
                                    : std::string(shm::toString(reader_.connection()));
        const ImVec2 sz = ImGui::CalcTextSize(big.c_str());
        dl->AddText(ImVec2(l.view.x + (l.view.w - sz.x) / 2, l.view.y + l.view.h / 2 - sz.y),
                    IM_COL32(255, 200, 80, 255), big.c_str());
    }
    ImGui::PopFont();
    if (reader_.connection() != shm::Connection::kConnected) {
        const ImVec2 sz = ImGui::CalcTextSize(texts_.connection.text.c_str());
        dl->AddText(ImVec2(l.view.x + (l.view.w - sz.x) / 2, l.view.y + l.view.h / 2 + 10),
                    IM_COL32(230, 230, 230, 255), texts_.connection.text.c_str());
    }
    if (texts_.dof_valid) {
        const float cell = 24.0f * l.scale;
        drawDegeneracyBar(dl, ImVec2(l.view.x + 14, l.view.y + l.view.h - 6 * cell - 14), cell);
    }
    drawChangesLegend(dl, l);
    // Warnings the operator can act on, stacked at the top of the view, most severe first.
    if (placing_.active()) return placing_.drawOverlay(l, facts_.view_proj, font_big_);
    std::vector<Line> warnings = texts_.warnings;
    if (!texts_.localization.text.empty()) warnings.push_back(texts_.localization);
    std::stable_sort(warnings.begin(), warnings.end(),
                     [](const Line& a, const Line& b) { return a.health > b.health; });
    float y = l.view.y + 10;
    ImGui::PushFont(font_big_);
    for (const Line& w : warnings) {
        const ImVec2 sz = ImGui::CalcTextSize(w.text.c_str(), nullptr, false, l.view.w - 60);
        const ImVec4 c = colourOf(w.health);
        dl->AddRectFilled(ImVec2(l.view.x + 20, y), ImVec2(l.view.x + 40 + sz.x, y + sz.y + 12),
                          ImGui::GetColorU32(ImVec4(c.x * 0.55f, c.y * 0.35f, c.z * 0.2f, 0.9f)),
                          8);
        dl->AddText(nullptr, 0.0f, ImVec2(l.view.x + 30, y + 6), IM_COL32_WHITE, w.text.c_str(),
                    nullptr, l.view.w - 60);
        y += sz.y + 18;
    }
    ImGui::PopFont();
}

void UiApp::drawChangesLegend(ImDrawList* dl, const ScreenLayout& l) {
    // The change cells' legend, bottom right of the view: a swatch and the count of each kind.
    if (texts_.changes.text.empty()) return;
    const float line = ImGui::GetTextLineHeight();
    const float sw = line;  // swatch side
    const std::string title = "CHANGED SINCE THE EARLIER SCAN";
    const std::string rows[2] = {groupThousands(texts_.changes_appeared) + " appeared",
                                 groupThousands(texts_.changes_vanished) + " vanished"};
    const Rgb8 colours[2] = {kAppearedColour, kVanishedColour};
    float w = ImGui::CalcTextSize(title.c_str()).x;
    for (const std::string& r : rows) w = std::max(w, sw + 8 + ImGui::CalcTextSize(r.c_str()).x);
    const float h = 3 * line + 2 * 6;
    const ImVec2 a(l.view.x + l.view.w - w - 34, l.view.y + l.view.h - h - 34);
    dl->AddRectFilled(a, ImVec2(a.x + w + 20, a.y + h + 20), IM_COL32(0, 0, 0, 170), 6);
    dl->AddText(ImVec2(a.x + 10, a.y + 10), IM_COL32_WHITE, title.c_str());
    for (int i = 0; i < 2; ++i) {
        const ImVec2 r(a.x + 10, a.y + 10 + (i + 1) * (line + 6));
        dl->AddRectFilled(r, ImVec2(r.x + sw, r.y + sw),
                          IM_COL32(colours[i].r, colours[i].g, colours[i].b, 255), 3);
        dl->AddText(ImVec2(r.x + sw + 8, r.y), IM_COL32_WHITE, rows[i].c_str());
    }
}

void UiApp::drawCoverage(const ScreenLayout& l) {
    const double now = glfwGetTime();
    if (coverage_dirty_ &&
        now - coverage_uploaded_at_ > 0.5) {  // rebuilding is O(area): at most 2 Hz
        coverage_image_ = coverage_.render();
        if (!coverage_texture_) glGenTextures(1, &coverage_texture_);
        glBindTexture(GL_TEXTURE_2D, coverage_texture_);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        if (coverage_image_.width > 0) {
            glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, coverage_image_.width, coverage_image_.height,
                         0, GL_RGBA, GL_UNSIGNED_BYTE, coverage_image_.rgba.data());
        }
        coverage_dirty_ = false;
        coverage_uploaded_at_ = now;
    }
    ImDrawList* dl = ImGui::GetBackgroundDrawList();
    if (coverage_image_.width == 0) return;
    // Fit the grid into the view, north up, same scale on both axes.
    const float s = std::min(l.view.w / static_cast<float>(coverage_image_.width),
                             l.view.h / static_cast<float>(coverage_image_.height)) *
                    0.95f;
    const float w = s * static_cast<float>(coverage_image_.width),
                h = s * static_cast<float>(coverage_image_.height);
    const ImVec2 a(l.view.x + (l.view.w - w) / 2, l.view.y + (l.view.h - h) / 2);
    dl->AddImage(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(coverage_texture_)), a,
                 ImVec2(a.x + w, a.y + h));
    const auto toScreen = [&](float x, float y) {
        return ImVec2(a.x + (x - coverage_image_.min_x_m) / coverage_image_.cell_m * s,
                      a.y + (coverage_image_.max_y_m - y) / coverage_image_.cell_m * s);
    };
    for (std::size_t i = 1; i < track_cpu_.size(); ++i) {
        dl->AddLine(toScreen(track_cpu_[i - 1].x_m, track_cpu_[i - 1].y_m),
                    toScreen(track_cpu_[i].x_m, track_cpu_[i].y_m), IM_COL32(255, 60, 230, 255),
                    2.0f);
    }
    // The change cells from above, as on the 3D view.
    const float half = 0.5f * changes_.cell_m;
    for (std::uint32_t k = 0; k < std::min<std::uint32_t>(changes_.count, shm::kMaxChangeCells);
         ++k) {
        const shm::ChangeCellRecord& c = changes_.cells[k];
        const Rgb8 col = changeColour(static_cast<shm::ChangeKind>(c.kind));
        dl->AddRectFilled(toScreen(c.x_m - half, c.y_m + half),
                          toScreen(c.x_m + half, c.y_m - half), IM_COL32(col.r, col.g, col.b, 200));
    }
    if (pose_) {
        dl->AddCircleFilled(toScreen(static_cast<float>(pose_->position_m[0]),
                                     static_cast<float>(pose_->position_m[1])),
                            8.0f, IM_COL32_WHITE);
    }
    const char* legend = "coverage below hip height: black = not scanned";
    dl->AddText(ImVec2(a.x + w - ImGui::CalcTextSize(legend).x - 8,
                       a.y + h - ImGui::GetTextLineHeight() - 6),
                IM_COL32_WHITE, legend);
}

void UiApp::drawView(const ScreenLayout& l) {
    int fbw = 0, fbh = 0, ww = 0, wh = 0;
    glfwGetFramebufferSize(window_, &fbw, &fbh);
    glfwGetWindowSize(window_, &ww, &wh);
    const float sx = ww > 0 ? static_cast<float>(fbw) / static_cast<float>(ww) : 1.0f;
    const float sy = wh > 0 ? static_cast<float>(fbh) / static_cast<float>(wh) : 1.0f;
    glViewport(0, 0, fbw, fbh);
    glDisable(GL_SCISSOR_TEST);
    glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    const Rect v{l.view.x * sx, l.view.y * sy, l.view.w * sx, l.view.h * sy};
    const int vx = static_cast<int>(std::lround(v.x)), vw = static_cast<int>(std::lround(v.w));
    const int vh = static_cast<int>(std::lround(v.h));
    const int vy_gl =
        fbh - static_cast<int>(std::lround(v.y)) - vh;  // GL counts rows from the bottom
    facts_.camera = camera_.mode;
    facts_.colour = colour_;
    facts_.coverage = coverage_view_;
    facts_.framebuffer_w = fbw;
    facts_.framebuffer_h = fbh;
    facts_.view_px = Rect{static_cast<float>(vx), static_cast<float>(fbh - vy_gl - vh),
                          static_cast<float>(vw), static_cast<float>(vh)};
    facts_.points_drawn = renderer_.pointCount();  // screenshots draw every point
    facts_.track_points = renderer_.trackCount();
    facts_.epoch = cursor_.epoch;
    facts_.change_cells_drawn = coverage_view_ ? 0 : changes_renderer_.cells();
    if (coverage_view_ || vw <= 0 || vh <= 0) return;
    glViewport(vx, vy_gl, vw, vh);
    glEnable(GL_SCISSOR_TEST);
    glScissor(vx, vy_gl, vw, vh);
    const Eigen::Matrix4f vp =
        camera_.projection(static_cast<float>(vw) / static_cast<float>(vh)) * camera_.view();
    facts_.view_proj = vp;
    const bool full = !o_.screenshot_path.empty();
    renderer_.draw(vp, colour_, o_.point_size_px,
                   full                     ? 0
                   : o_.max_draw_points > 0 ? o_.max_draw_points
                                            : draw_budget_);
    changes_renderer_.draw(vp);
    glDisable(GL_SCISSOR_TEST);
    glViewport(0, 0, fbw, fbh);
}

int UiApp::finishScreenshot(bool timed_out) {
    int fbw = 0, fbh = 0;
    glfwGetFramebufferSize(window_, &fbw, &fbh);
    if (timed_out && renderer_.pointCount() == 0) {
        log().error(
            "no live map appeared in shared memory {} within {} s ({}): start the pipeline, "
            "`handscan replay REC.mcap --live` or `handscan shm-demo --autostart`",
            o_.shm_name, o_.timeout_s,
            reader_.message().empty() ? "connected, but no points" : reader_.message());
        return 3;
    }
    if (timed_out) {
        log().warn("timeout after {} s with {} of the {} points asked for: saving what is there",
                   o_.timeout_s, renderer_.pointCount(), o_.wait_points);
    }
    if (Status s = saveFramebufferPng(o_.screenshot_path, fbw, fbh); !s) {
        log().error("{}", s.message());
        return 1;
    }
    std::string json_path = o_.status_json_path;
    if (json_path.empty())
        json_path = std::filesystem::path(o_.screenshot_path).replace_extension(".json").string();
    facts_.preview = preview_.facts();
    if (Status s = writeTextFile(json_path, statusJson(texts_, facts_)); !s) {
        log().error("{}", s.message());
        return 1;
    }
    log().info("saved {} ({}x{}, {} points) and {}", o_.screenshot_path, fbw, fbh,
               renderer_.pointCount(), json_path);
    return 0;
}

void UiApp::openStartPlacement(const ScreenLayout& l, bool again) {
    // The earlier map from above, all of its path in view, north up.
    placing_.open(again);
    coverage_view_ = false;
    camera_.mode = CameraMode::kTopDown;
    top_down_follows_device_ = false;
    if (track_cpu_.empty()) return;
    Eigen::AlignedBox3f box;
    for (const shm::TrackPoint& p : track_cpu_) box.extend(Eigen::Vector3f(p.x_m, p.y_m, p.z_m));
    camera_.target = box.center();
    const float aspect = l.view.h > 0 ? l.view.w / l.view.h : 1.0f;
    const Eigen::Vector3f size = box.sizes();
    camera_.top_down_half_height_m =
        std::max(4.0f, 0.5f * std::max(size.y(), size.x() / aspect) + 3.0f);
}

void UiApp::writeStatusJsonNow() {
    // Beside a running UI (tests): what it shows, replaced whole so a reader never sees half.
    facts_.preview = preview_.facts();
    facts_.picking = picker_.active();
    facts_.picker.clear();
    for (const auto& p : picker_.listed()) facts_.picker.push_back({p.name, p.button});
    facts_.placing = placing_.active();
    facts_.placed = placing_.placement().placed();
    facts_.placed_pose = facts_.placed ? placing_.placement().poseText() : "";
    const std::string tmp = o_.status_json_path + ".tmp";
    if (Status s = writeTextFile(tmp, statusJson(texts_, facts_)); !s) {
        log().warn("{}", s.message());
        return;
    }
    std::error_code ec;
    std::filesystem::rename(tmp, o_.status_json_path, ec);
}

int UiApp::run() {
    if (Status s = initWindow(); !s) {
        log().error("{}", s.message());
        return 2;
    }
    const bool screenshot = !o_.screenshot_path.empty();
    const auto start = std::chrono::steady_clock::now();
    int ready_frames = 0;
    while (!glfwWindowShouldClose(window_)) {
        const auto frame_start = std::chrono::steady_clock::now();
        const double elapsed = std::chrono::duration<double>(frame_start - start).count();
        glfwPollEvents();
        ingest();
        updateCamera();
        int ww = 0, wh = 0;
        glfwGetWindowSize(window_, &ww, &wh);
        const ScreenLayout l =
            ScreenLayout::compute(static_cast<float>(ww), static_cast<float>(wh));

        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        ImGui::PushFont(font_normal_);
        handleViewInput(l);
        drawView(l);
        if (coverage_view_) drawCoverage(l);
        drawStatusBar(l);
        drawButtons(l);
        drawOverlay(l);
        ImGui::PopFont();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());

        if (screenshot) {
            const bool have_map =
                renderer_.pointCount() >= std::max<std::uint64_t>(o_.wait_points, 1);
            // A few frames after the map is complete so ImGui's layout has settled.
            ready_frames = have_map && status_seen_ ? ready_frames + 1 : 0;
            if (ready_frames >= 3) return finishScreenshot(false);
            if (elapsed > o_.timeout_s) return finishScreenshot(true);
        }
        glfwSwapBuffers(window_);
        // Adapt the number of points drawn so that touch input stays responsive (~25 Hz).
        const double frame_s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - frame_start).count();
        if (frame_s > 0.06)
            draw_budget_ =
                std::max<std::size_t>(100'000, static_cast<std::size_t>(draw_budget_ * 0.7));
        if (frame_s < 0.03 && draw_budget_ < renderer_.pointCount())
            draw_budget_ = draw_budget_ * 5 / 4 + 1;
        if (!screenshot && !o_.status_json_path.empty() && elapsed - status_json_at_ >= 0.25) {
            status_json_at_ = elapsed;
            writeStatusJsonNow();
        }
        if (o_.max_seconds > 0 && elapsed > o_.max_seconds) break;
        if (!screenshot)
            std::this_thread::sleep_until(frame_start +
                                          std::chrono::milliseconds(16));  // <= 60 Hz without vsync
    }
    return 0;
}

}  // namespace

int runUi(const UiOptions& options) {
    UiApp app(options);
    return app.run();
}

}  // namespace handscan::ui
