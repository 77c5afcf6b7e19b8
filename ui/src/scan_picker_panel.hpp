// The "continue scan" picker: the scans on the device that can be continued (shm::ScanList, as
// the pipeline lists them, newest first), one big button each (its name, when it was last
// written, how big), and CANCEL. The scan stopped now (its map already on the screen) goes on to
// the start placement; another one is continued from its start, its map and path come onto the
// screen, and the operator then places themselves on it (PLACE ME's placement). Drawn with Dear
// ImGui in the button column.
#pragma once

#include <imgui.h>

#include <string>
#include <vector>

#include "handscan/shm/layout.hpp"
#include "screen_layout.hpp"

namespace handscan::ui {

class ScanPickerPanel {
public:
    enum class Action { kNone, kPick, kCancel };
    struct Listed {
        std::string name;
        bool current = false;  // the scan stopped now
        Rect button;           // on the screen, last frame (for --status-json)
    };

    bool active() const { return active_; }
    void open(const shm::ScanList& list);
    void close() { active_ = false; }
    const std::vector<Listed>& listed() const { return listed_; }

    // The panel's buttons (in the button column's window); kPick with `picked` set.
    Action drawButtons(float w, float h, Listed& picked);

private:
    bool active_ = false;
    std::vector<Listed> listed_;
    std::vector<std::string> labels_;  // "name\nwhen, size"
    std::uint32_t left_out_ = 0;       // older scans the list had no room for
};

// A listed scan's button label: its name, then "25 Nov 14:03 UTC, 12.3 MiB" (and "stopped now").
std::string listedScanLabel(const shm::ListedScan& scan);

}  // namespace handscan::ui
