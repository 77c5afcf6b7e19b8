#include "handscan/gpio/gpio_panel.hpp"

#include <algorithm>

namespace handscan::gpio {

const char* toString(PanelEventKind k) {
    switch (k) {
        case PanelEventKind::kPressed:
            return "pressed";
        case PanelEventKind::kReleased:
            return "released";
        case PanelEventKind::kTrigger:
            return "trigger";
    }
    return "?";
}

GpioPanel::GpioPanel(GpioChip& chip, PanelConfig config, RawTap* tap)
    : chip_(chip), cfg_(config), tap_(tap) {}

void GpioPanel::tap(const GpioRecord& r) {
    if (tap_ == nullptr) return;
    const auto bytes = encodeGpioRecord(r);
    tap_->onRaw(r.t_host, bytes);
}

Status GpioPanel::start() {
    inputs_.clear();
    leds_.clear();
    const auto addInput = [&](std::optional<unsigned> offset, PanelRole role,
                              const InputRequest& req, bool debounce) -> Status {
        if (!offset) return Status::ok();
        auto line = chip_.requestInput(*offset, req);
        if (!line)
            return {line.status().code(),
                    std::string(toString(role)) + ": " + line.status().message()};
        auto level = (*line)->value();
        Input in{std::move(*line), role, std::nullopt};
        if (debounce) in.debouncer.emplace(cfg_.debounce, level && *level);
        inputs_.push_back(std::move(in));
        return Status::ok();
    };
    if (Status s = addInput(cfg_.scan_button, PanelRole::kScanButton, cfg_.buttons, true); !s)
        return s;
    if (Status s = addInput(cfg_.export_button, PanelRole::kExportButton, cfg_.buttons, true); !s)
        return s;
    if (Status s = addInput(cfg_.camera_trigger, PanelRole::kCameraTrigger, cfg_.trigger, false);
        !s)
        return s;
    const std::pair<std::optional<unsigned>, PanelRole> leds[] = {
        {cfg_.led_ready, PanelRole::kLedReady},
        {cfg_.led_scanning, PanelRole::kLedScanning},
        {cfg_.led_fault, PanelRole::kLedFault},
        {cfg_.led_exporting, PanelRole::kLedExporting}};
    for (const auto& [offset, role] : leds) {
        if (!offset) continue;
        auto line = chip_.requestOutput(*offset, cfg_.leds_active_low, false);
        if (!line)
            return {line.status().code(),
                    std::string(toString(role)) + ": " + line.status().message()};
        leds_.push_back({std::move(*line), role, LedPattern::kOff, chip_.now(), false});
    }
    return Status::ok();
}

GpioPanel::Led* GpioPanel::findLed(PanelRole role) {
    for (Led& l : leds_) {
        if (l.role == role) return &l;
    }
    return nullptr;
}

LedPattern GpioPanel::led(PanelRole role) const {
    for (const Led& l : leds_) {
        if (l.role == role) return l.pattern;
    }
    return LedPattern::kOff;
}

Status GpioPanel::setLed(PanelRole role, LedPattern pattern) {
    Led* l = findLed(role);
    if (l == nullptr) return Status::ok();
    if (l->pattern != pattern) {
        l->pattern = pattern;
        l->since = chip_.now();  // patterns start with their on-phase, so the change shows at once
    }
    return updateLeds(chip_.now());
}

Status GpioPanel::updateLeds(TimeNs now) {
    for (Led& l : leds_) {
        const bool level = ledLevel(l.pattern, now - l.since);
        if (level == l.level) continue;
        if (Status s = l.line->set(level); !s) return s;
        l.level = level;
        ++stats_.led_writes;
        tap({now, l.line->offset(), level ? GpioRecordKind::kOutputOn : GpioRecordKind::kOutputOff,
             l.role});
    }
    return Status::ok();
}

Result<std::vector<PanelEvent>> GpioPanel::poll(TimeNs timeout) {
    std::vector<PanelEvent> out;
    const TimeNs now0 = chip_.now();
    TimeNs wake = now0 + timeout;
    for (const Input& in : inputs_) {
        if (in.debouncer) wake = std::min(wake, in.debouncer->deadline());
    }
    for (const Led& l : leds_) {
        const TimeNs next = nextLedChange(l.pattern, now0 - l.since);
        if (next != INT64_MAX) wake = std::min(wake, l.since + next);
    }
    std::vector<GpioInput*> lines;
    for (const Input& in : inputs_) lines.push_back(in.line.get());
    auto ready = chip_.waitAny(lines, std::max<TimeNs>(0, wake - now0));
    if (!ready) return ready.status();
    for (std::size_t i : *ready) {
        Input& in = inputs_[i];
        auto e = in.line->readEvent();
        if (!e) return e.status();
        ++stats_.edges;
        tap({e->t_host, e->line,
             e->edge == GpioEdgeType::kRising ? GpioRecordKind::kRisingEdge
                                              : GpioRecordKind::kFallingEdge,
             in.role});
        if (!in.debouncer) {
            if (e->edge == GpioEdgeType::kRising) {
                ++stats_.triggers;
                out.push_back({e->t_host, in.role, PanelEventKind::kTrigger});
            }
            continue;
        }
        const std::uint64_t before = in.debouncer->bounces();
        for (const ButtonChange& c : in.debouncer->onEdge(e->t_host, e->edge)) {
            out.push_back({c.t_host, in.role,
                           c.pressed ? PanelEventKind::kPressed : PanelEventKind::kReleased});
        }
        stats_.bounces += in.debouncer->bounces() - before;
    }
    const TimeNs now = chip_.now();
    for (Input& in : inputs_) {
        if (!in.debouncer) continue;
        if (auto c = in.debouncer->onTime(now)) {
            out.push_back({c->t_host, in.role,
                           c->pressed ? PanelEventKind::kPressed : PanelEventKind::kReleased});
        }
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const PanelEvent& a, const PanelEvent& b) { return a.t_host < b.t_host; });
    if (Status s = updateLeds(now); !s) return s;
    return out;
}

}  // namespace handscan::gpio
