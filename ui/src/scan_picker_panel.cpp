#include "scan_picker_panel.hpp"

#include <ctime>

#include "handscan/shm/text_field.hpp"
#include "handscan/ui/status_texts.hpp"

namespace handscan::ui {

std::string listedScanLabel(const shm::ListedScan& scan) {
    std::string label(shm::getText(scan.name));
    char when[32] = {};
    const std::time_t t = scan.modified_unix_s;
    std::tm tm{};
    if (scan.modified_unix_s > 0 && gmtime_r(&t, &tm) != nullptr)
        std::strftime(when, sizeof when, "%d %b %H:%M UTC", &tm);
    label += "\n" + std::string(when) + (when[0] != '\0' ? ", " : "") +
             formatBytes(static_cast<double>(scan.journal_bytes));
    if (scan.current) label += ", stopped now";
    return label;
}

void ScanPickerPanel::open(const shm::ScanList& list) {
    active_ = true;
    listed_.clear();
    labels_.clear();
    for (std::uint32_t i = 0; i < list.count && i < shm::kMaxListedScans; ++i) {
        const shm::ListedScan& s = list.scans[i];
        listed_.push_back({std::string(shm::getText(s.name)), s.current != 0, {}});
        labels_.push_back(listedScanLabel(s));
    }
    left_out_ = list.total > list.count ? list.total - list.count : 0;
}

ScanPickerPanel::Action ScanPickerPanel::drawButtons(float w, float h, Listed& picked) {
    Action out = Action::kNone;
    ImGui::TextUnformatted("CONTINUE WHICH SCAN?");
    // The list scrolls (drag its bar) when it is longer than the column; CANCEL stays below it.
    const float cancel_h = h + ImGui::GetStyle().ItemSpacing.y + ImGui::GetStyle().WindowPadding.y;
    ImGui::BeginChild("scans", ImVec2(w, ImGui::GetContentRegionAvail().y - cancel_h), false);
    const float bw = w - ImGui::GetStyle().ScrollbarSize;
    for (std::size_t i = 0; i < listed_.size(); ++i) {
        ImGui::PushID(static_cast<int>(i));
        ImGui::PushStyleColor(ImGuiCol_Button, listed_[i].current ? ImVec4(0.45f, 0.3f, 0.6f, 1)
                                                                  : ImVec4(0.3f, 0.25f, 0.4f, 1));
        if (ImGui::Button(labels_[i].c_str(), ImVec2(bw, h * 1.2f))) {
            picked = listed_[i];
            out = Action::kPick;
        }
        ImGui::PopStyleColor();
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        listed_[i].button = {lo.x, lo.y, hi.x - lo.x, hi.y - lo.y};
        ImGui::PopID();
    }
    if (left_out_ > 0) ImGui::Text("%u older not listed", left_out_);
    ImGui::EndChild();
    ImGui::PushStyleColor(ImGuiCol_Button, ImVec4(0.3f, 0.3f, 0.35f, 1));
    if (ImGui::Button("CANCEL", ImVec2(w, h))) out = Action::kCancel;
    ImGui::PopStyleColor();
    if (out != Action::kNone) active_ = false;
    return out;
}

}  // namespace handscan::ui
