// Everything the status bar, the warnings banner and the degeneracy bar say, as plain strings
// derived from the status block (pure, unit-tested). The UI draws exactly these strings, and
// `--status-json` writes the same object next to a screenshot so tests compare what was shown
// with what was published.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "handscan/shm/layout.hpp"
#include "handscan/shm/live_map_reader.hpp"

namespace handscan::ui {

enum class Health { kOk = 0, kWarning = 1, kError = 2 };
const char* toString(Health h);

// Limits at which the operator is warned (what they can act on).
struct WarningLimits {
    float max_speed_mps = 1.5f;           // walking fast blurs images and thins the map
    float max_turn_radps = 2.0f;          // ~115 deg/s
    float min_camera_brightness = 25.0f;  // mean grey level below which VIO loses features
    double min_free_storage_bytes = 2.0 * (1ull << 30);
    float min_rate_fraction = 0.8f;  // sensor rate below this fraction of nominal
};

struct Line {
    std::string text;
    Health health = Health::kOk;
};

// The DOF rows of the degeneracy bar (paper, Figure 14): which module's update a DOF carries.
enum class DofSource { kImu = 0, kVio = 1, kScan = 2 };
const char* toString(DofSource s);

struct StatusTexts {
    Line connection;             // "connected" / "waiting for pipeline (...)"
    std::string scan_state;      // "IDLE" / "SCANNING" / "STOPPED"
    std::string elapsed;         // "02:05"
    std::string distance;        // "12.3 m"
    std::string points;          // "1,234,567 points"
    Line storage;                // "free 12.3 of 58.0 GiB"
    std::vector<Line> sensors;   // "hokuyo 40.0 Hz", "colour-cam LOST"
    std::vector<Line> modules;   // "vio active", "scan-match degenerate tx"
    std::vector<Line> warnings;  // operator can act on each
    Line export_line;            // "" when idle, "export 45%", "exported ...: safe to remove"
    // The self-calibration (none while idle): its step or outcome, then each value
    // ("encoder zero 0.512 +- 0.004 deg", "... kept: not determined").
    std::vector<Line> calibration;
    std::string message;  // the pipeline's own note
    // A scan continuing an earlier one: "" otherwise, "SEARCHING FOR THE EARLIER SCAN",
    // "LOCKED ON THE EARLIER SCAN", "NOT LOCKED: walk to where the earlier scan started".
    Line localization;
    bool can_continue = false;  // an earlier scan on the device can be continued
    // The continued scan's change report (describeChanges): "" when nothing changed.
    Line changes;
    std::uint32_t changes_appeared = 0, changes_vanished = 0;
    bool dof_valid = false;
    DofSource dof[shm::kDofCount] = {};
    bool vio_dof[shm::kDofCount] = {};
    bool scan_dof[shm::kDofCount] = {};
};

StatusTexts describeStatus(shm::Connection connection, const std::string& connection_message,
                           const std::optional<shm::StatusBlock>& status,
                           const std::optional<shm::PoseRecord>& pose,
                           const WarningLimits& limits = {});

// A continued scan's change report as the legend says it: "CHANGED SINCE THE EARLIER SCAN:
// 2 appeared (orange), 3 vanished (blue)", noting when only the largest cells are drawn; ""
// for an empty report. Sets t.changes and its counts.
void describeChanges(const shm::ChangeReport& report, StatusTexts& t);

// "1,234,567"
std::string groupThousands(std::uint64_t n);
// "02:05" or "1:02:05"
std::string formatDuration(double seconds);
// "12.3 GiB", "512 MiB"
std::string formatBytes(double bytes);
// "tx", "rx+tz", "" for 0
std::string dofList(std::uint8_t mask);

}  // namespace handscan::ui
