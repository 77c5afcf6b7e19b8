#include "handscan/ui/status_texts.hpp"

#include <cmath>
#include <cstdio>

#include "handscan/shm/text_field.hpp"

namespace handscan::ui {
namespace {

std::vector<Line> describeCalibration(const shm::CalibrationStatus& c) {
    std::vector<Line> out;
    const std::string msg(shm::getText(c.message));
    switch (static_cast<shm::CalibrationState>(c.state)) {
        case shm::CalibrationState::kIdle:
            return out;
        case shm::CalibrationState::kRunning: {
            char head[64];
            std::snprintf(head, sizeof head, "Calibrating %.0f%%: ", 100.0 * c.progress);
            out.push_back({head + msg, Health::kWarning});
            return out;
        }
        case shm::CalibrationState::kFailed:
            out.push_back({"Calibration FAILED: " + msg, Health::kError});
            return out;
        case shm::CalibrationState::kDone:
            out.push_back({msg, Health::kOk});
            break;
    }
    for (std::uint8_t i = 0; i < std::min<std::uint8_t>(c.value_count, shm::kCalibrationValues);
         ++i) {
        const shm::CalibrationValue& v = c.values[i];
        char line[160];
        if (v.written)
            std::snprintf(line, sizeof line, "%s: %.3f +- %.3f %s (was %.3f)",
                          std::string(shm::getText(v.name)).c_str(), v.value, v.std,
                          std::string(shm::getText(v.unit)).c_str(), v.start);
        else
            std::snprintf(line, sizeof line, "%s: kept (not determined by the walk)",
                          std::string(shm::getText(v.name)).c_str());
        out.push_back({line, v.written ? Health::kOk : Health::kWarning});
    }
    return out;
}

std::string format(const char* fmt, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

}  // namespace

const char* toString(Health h) {
    switch (h) {
        case Health::kOk:
            return "ok";
        case Health::kWarning:
            return "warning";
        case Health::kError:
            return "error";
    }
    return "?";
}

const char* toString(DofSource s) {
    switch (s) {
        case DofSource::kImu:
            return "imu";
        case DofSource::kVio:
            return "vio";
        case DofSource::kScan:
            return "scan";
    }
    return "?";
}

std::string groupThousands(std::uint64_t n) {
    std::string digits = std::to_string(n);
    std::string out;
    for (std::size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

std::string formatDuration(double seconds) {
    const auto total = static_cast<long long>(std::max(0.0, std::floor(seconds)));
    char buf[32];
    if (total >= 3600) {
        std::snprintf(buf, sizeof buf, "%lld:%02lld:%02lld", total / 3600, (total / 60) % 60,
                      total % 60);
    } else {
        std::snprintf(buf, sizeof buf, "%02lld:%02lld", total / 60, total % 60);
    }
    return buf;
}

std::string formatBytes(double bytes) {
    if (bytes >= 1024.0 * 1024 * 1024) return format("%.1f GiB", bytes / (1024.0 * 1024 * 1024));
    if (bytes >= 1024.0 * 1024) return format("%.0f MiB", bytes / (1024.0 * 1024));
    return format("%.0f KiB", bytes / 1024.0);
}

std::string dofList(std::uint8_t mask) {
    std::string out;
    for (int i = 0; i < shm::kDofCount; ++i) {
        if (!(mask & (1u << i))) continue;
        if (!out.empty()) out += '+';
        out += shm::kDofNames[i];
    }
    return out;
}

StatusTexts describeStatus(shm::Connection connection, const std::string& connection_message,
                           const std::optional<shm::StatusBlock>& status,
                           const std::optional<shm::PoseRecord>& pose,
                           const WarningLimits& limits) {
    using shm::getText;
    StatusTexts t;
    t.connection.text =
        connection == shm::Connection::kConnected ? "connected" : connection_message;
    t.connection.health =
        connection == shm::Connection::kConnected ? Health::kOk
        : connection == shm::Connection::kIncompatible || connection == shm::Connection::kStale
            ? Health::kError
            : Health::kWarning;
    if (connection == shm::Connection::kStale) {
        t.warnings.push_back(
            {"Pipeline not responding: the map is frozen. Wait, or restart the device.",
             Health::kError});
    }
    if (!status) {
        t.scan_state =
            connection == shm::Connection::kWaiting ? "WAITING FOR PIPELINE" : "NO STATUS";
        return t;
    }
    const shm::StatusBlock& s = *status;
    switch (static_cast<shm::ScanState>(s.scan_state)) {
        case shm::ScanState::kIdle:
            t.scan_state = "IDLE";
            break;
        case shm::ScanState::kScanning:
            t.scan_state = "SCANNING";
            break;
        case shm::ScanState::kStopped:
            t.scan_state = "STOPPED";
            break;
    }
    t.elapsed = formatDuration(s.elapsed_s);
    t.distance = format("%.1f m", s.distance_m);
    t.points = groupThousands(s.point_count) + " points";
    t.storage.text = "free " + formatBytes(static_cast<double>(s.free_storage_bytes)) + " of " +
                     formatBytes(static_cast<double>(s.total_storage_bytes));
    if (s.total_storage_bytes > 0 &&
        static_cast<double>(s.free_storage_bytes) < limits.min_free_storage_bytes) {
        t.storage.health = Health::kWarning;
        t.warnings.push_back({"Storage low (" +
                                  formatBytes(static_cast<double>(s.free_storage_bytes)) +
                                  " free): export and delete old scans.",
                              Health::kWarning});
    }

    const std::uint32_t nsensors = std::min<std::uint32_t>(s.sensor_count, shm::kMaxSensors);
    for (std::uint32_t i = 0; i < nsensors; ++i) {
        const shm::SensorStatus& ss = s.sensors[i];
        const std::string name(getText(ss.name));
        Line l;
        if (!ss.connected) {
            l = {name + " LOST", Health::kError};
            std::string what = "Sensor lost: " + name;
            if (!getText(ss.last_error).empty())
                what += " (" + std::string(getText(ss.last_error)) + ")";
            t.warnings.push_back({what, Health::kError});
        } else {
            l.text = name + format(" %.1f Hz", ss.rate_hz);
            if (ss.expected_rate_hz > 0 &&
                ss.rate_hz < limits.min_rate_fraction * ss.expected_rate_hz) {
                l.health = Health::kWarning;
                t.warnings.push_back({name + format(" slow: %.1f Hz", ss.rate_hz) +
                                          format(" of %.0f Hz expected", ss.expected_rate_hz),
                                      Health::kWarning});
            } else if (!getText(ss.last_error).empty()) {
                l.health = Health::kWarning;
            }
        }
        t.sensors.push_back(l);
    }

    const std::uint32_t nmodules = std::min<std::uint32_t>(s.module_count, shm::kMaxModules);
    for (std::uint32_t i = 0; i < nmodules; ++i) {
        const shm::ModuleStatus& m = s.modules[i];
        const std::string name(getText(m.name));
        Line l;
        switch (static_cast<shm::ModuleState>(m.state)) {
            case shm::ModuleState::kOff:
                l = {name + " off", Health::kWarning};
                break;
            case shm::ModuleState::kActive:
                l = {name + " active", Health::kOk};
                break;
            case shm::ModuleState::kBypassed:
                l = {name + " bypassed", Health::kWarning};
                break;
        }
        if (m.degenerate_dof_mask != 0 &&
            static_cast<shm::ModuleState>(m.state) == shm::ModuleState::kActive) {
            l = {name + " degenerate " + dofList(m.degenerate_dof_mask), Health::kWarning};
            if (name == "scan-match") {
                t.warnings.push_back({"Laser degenerate along " + dofList(m.degenerate_dof_mask) +
                                          ": scan towards walls, corners or objects.",
                                      Health::kWarning});
            }
        }
        t.modules.push_back(l);
    }

    if (s.linear_speed_mps > limits.max_speed_mps ||
        s.angular_speed_radps > limits.max_turn_radps) {
        t.warnings.push_back({format("Moving too fast (%.1f m/s, ", s.linear_speed_mps) +
                                  format("%.0f deg/s): slow down.",
                                         s.angular_speed_radps * 180.0 / 3.14159265358979),
                              Health::kWarning});
    }
    // Only a pipeline that runs a camera reports its brightness (a laser + IMU replay does not).
    bool has_camera = false;
    for (std::uint32_t i = 0; i < std::min<std::uint32_t>(s.sensor_count, shm::kMaxSensors); ++i) {
        if (shm::getText(s.sensors[i].name).find("cam") != std::string_view::npos)
            has_camera = true;
    }
    if (has_camera && s.camera_brightness < limits.min_camera_brightness) {
        t.warnings.push_back(
            {format("Camera dark (brightness %.0f/255): turn on lights.", s.camera_brightness),
             Health::kWarning});
    }

    const shm::ExportStatus& e = s.export_status;
    switch (static_cast<shm::ExportState>(e.state)) {
        case shm::ExportState::kIdle:
            break;
        case shm::ExportState::kRunning:
            t.export_line = {
                format("Exporting %.0f%% - do not remove the USB stick", 100.0 * e.progress),
                Health::kWarning};
            break;
        case shm::ExportState::kDone:
            t.export_line = {e.safe_to_remove ? "Export done: SAFE TO REMOVE the USB stick"
                                              : "Export done, syncing - wait",
                             e.safe_to_remove ? Health::kOk : Health::kWarning};
            break;
        case shm::ExportState::kFailed:
            t.export_line = {"Export FAILED: " + std::string(getText(e.message)), Health::kError};
            break;
    }
    t.calibration = describeCalibration(s.calibration);
    t.message = std::string(getText(s.message));
    t.can_continue = s.can_continue != 0;
    switch (static_cast<shm::LocalizationState>(s.localization)) {
        case shm::LocalizationState::kNone:
            break;
        case shm::LocalizationState::kSearching:
            t.localization = {"SEARCHING FOR THE EARLIER SCAN: walk where it went",
                              Health::kWarning};
            break;
        case shm::LocalizationState::kLocked:
            t.localization = {"LOCKED ON THE EARLIER SCAN", Health::kOk};
            break;
        case shm::LocalizationState::kNotLocked:
            t.localization = {"NOT LOCKED: walk to where the earlier scan started", Health::kError};
            break;
    }

    if (pose) {
        t.dof_valid = true;
        for (int i = 0; i < shm::kDofCount; ++i) {
            t.vio_dof[i] = pose->vio_dof_mask & (1u << i);
            t.scan_dof[i] = pose->scan_dof_mask & (1u << i);
            // Figure 14's combination: the camera's update has priority, the laser's fills in,
            // the IMU prediction holds what neither solved.
            t.dof[i] = t.vio_dof[i]    ? DofSource::kVio
                       : t.scan_dof[i] ? DofSource::kScan
                                       : DofSource::kImu;
        }
    }
    return t;
}

void describeChanges(const shm::ChangeReport& r, StatusTexts& t) {
    t.changes_appeared = r.appeared;
    t.changes_vanished = r.vanished;
    const std::uint64_t total = std::uint64_t{r.appeared} + r.vanished;
    if (total == 0) {
        t.changes = {};
        return;
    }
    std::string text = "CHANGED SINCE THE EARLIER SCAN: " + groupThousands(r.appeared) +
                       " appeared (orange), " + groupThousands(r.vanished) + " vanished (blue)";
    if (r.count < total) text += ", the " + groupThousands(r.count) + " largest drawn";
    t.changes = {text, Health::kWarning};
}

}  // namespace handscan::ui
