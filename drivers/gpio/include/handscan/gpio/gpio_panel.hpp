// The scanner's button-and-LED panel on GPIO lines: scan start/stop and export buttons
// (debounced, press time = first contact), an optional camera trigger input (rising edges, not
// debounced), and four LEDs (ready, scanning, fault, exporting) driven with blink patterns.
// poll() sleeps until an edge, the end of a bounce window or the next LED level change.
// Every raw input edge and LED write goes to the recording tap as a GpioRecord.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "handscan/core/raw_tap.hpp"
#include "handscan/gpio/button_debouncer.hpp"
#include "handscan/gpio/gpio_lines.hpp"
#include "handscan/gpio/gpio_record.hpp"
#include "handscan/gpio/led_pattern.hpp"

namespace handscan::gpio {

struct PanelConfig {
    std::optional<unsigned> scan_button;
    std::optional<unsigned> export_button;
    std::optional<unsigned> camera_trigger;
    std::optional<unsigned> led_ready;
    std::optional<unsigned> led_scanning;
    std::optional<unsigned> led_fault;
    std::optional<unsigned> led_exporting;
    InputRequest buttons{true, Bias::kPullUp};
    InputRequest trigger{false, Bias::kAsIs};
    bool leds_active_low = false;
    TimeNs debounce = 20 * kNsPerMs;
};

enum class PanelEventKind : std::uint8_t { kPressed, kReleased, kTrigger };
const char* toString(PanelEventKind k);

struct PanelEvent {
    TimeNs t_host = 0;
    PanelRole role = PanelRole::kOther;
    PanelEventKind kind = PanelEventKind::kPressed;
};

struct PanelStats {
    std::uint64_t edges = 0;
    std::uint64_t bounces = 0;
    std::uint64_t triggers = 0;
    std::uint64_t led_writes = 0;
};

class GpioPanel {
public:
    GpioPanel(GpioChip& chip, PanelConfig config, RawTap* tap = nullptr);

    [[nodiscard]] Status start();
    [[nodiscard]] Result<std::vector<PanelEvent>> poll(TimeNs timeout);
    // Roles kLedReady..kLedExporting; an LED that is not configured is ignored.
    [[nodiscard]] Status setLed(PanelRole led, LedPattern pattern);
    LedPattern led(PanelRole led) const;
    const PanelStats& stats() const { return stats_; }

private:
    struct Input {
        std::unique_ptr<GpioInput> line;
        PanelRole role;
        std::optional<ButtonDebouncer> debouncer;  // none for the trigger
    };
    struct Led {
        std::unique_ptr<GpioOutput> line;
        PanelRole role;
        LedPattern pattern = LedPattern::kOff;
        TimeNs since = 0;
        bool level = false;
    };
    Status updateLeds(TimeNs now);
    void tap(const GpioRecord& r);
    Led* findLed(PanelRole role);

    GpioChip& chip_;
    PanelConfig cfg_;
    RawTap* tap_;
    std::vector<Input> inputs_;
    std::vector<Led> leds_;
    PanelStats stats_;
};

}  // namespace handscan::gpio
