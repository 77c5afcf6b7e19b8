// The button-and-LED panel thread: GpioPanel on the gpiod chip. A press of the scan button or
// the export button becomes the same command the touch screen sends; the LEDs follow the
// patterns the daemon sets. A missing chip is reported and looked for again.
#include <chrono>
#include <thread>

#include "handscan/gpio/gpio_panel.hpp"
#include "handscan/pipeline_daemon/sensor_sources.hpp"

namespace handscan::pipeline_daemon {
namespace {

gpio::PanelConfig panelConfig(const GpioConfig& c) {
    gpio::PanelConfig p;
    p.scan_button = static_cast<unsigned>(c.start_button_line);
    p.export_button = static_cast<unsigned>(c.export_button_line);
    p.led_ready = static_cast<unsigned>(c.led_ready_line);
    p.led_scanning = static_cast<unsigned>(c.led_scanning_line);
    p.led_fault = static_cast<unsigned>(c.led_fault_line);
    p.led_exporting = static_cast<unsigned>(c.led_exporting_line);
    p.debounce = fromSeconds(c.debounce_ms * 1e-3);
    return p;
}

class GpioSource final : public SensorSource {
public:
    GpioSource(const SourceContext& c, PanelLeds& leds, std::function<void(ButtonAction)> on_button)
        : SensorSource("buttons", 0.0f),
          config_(c.config.gpio),
          c_(c),
          leds_(leds),
          on_button_(std::move(on_button)) {}
    ~GpioSource() override { stop(); }

private:
    void run() override {
        runSessions(kNsPerSec, 10 * kNsPerSec, "gpio " + config_.chip,
                    " (buttons and LEDs unavailable; retrying)", [this] { return session(); });
    }

    Status session() {
        auto chip = c_.links.gpioChip(config_);
        if (!chip.isOk()) return chip.status();
        gpio::GpioPanel panel(**chip, panelConfig(config_));
        if (Status s = panel.start(); !s.isOk()) return s;
        health_.setConnected();
        health_.markAttempted();
        const std::pair<gpio::PanelRole, std::atomic<gpio::LedPattern>*> leds[] = {
            {gpio::PanelRole::kLedReady, &leds_.ready},
            {gpio::PanelRole::kLedScanning, &leds_.scanning},
            {gpio::PanelRole::kLedFault, &leds_.fault},
            {gpio::PanelRole::kLedExporting, &leds_.exporting}};
        constexpr TimeNs kSlice = 50 * kNsPerMs;
        while (!stopping()) {
            for (const auto& [role, pattern] : leds) {
                const gpio::LedPattern want = pattern->load(std::memory_order_relaxed);
                if (panel.led(role) != want) {
                    if (Status s = panel.setLed(role, want); !s.isOk()) return s;
                }
            }
            const TimeNs t0 = monotonicNow();
            auto events = panel.poll(kSlice);
            if (!events.isOk()) return events.status();
            for (const gpio::PanelEvent& e : *events) {
                health_.addSample(e.t_host);
                if (e.kind != gpio::PanelEventKind::kPressed) continue;
                if (e.role == gpio::PanelRole::kScanButton) on_button_(ButtonAction::kToggleScan);
                if (e.role == gpio::PanelRole::kExportButton) on_button_(ButtonAction::kExport);
            }
            // A line layer on a virtual clock returns at once; keep the loop at the slice's pace.
            if (events->empty()) {
                const TimeNs left = t0 + kSlice - monotonicNow();
                if (left > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(left));
            }
        }
        return Status::ok();
    }

    GpioConfig config_;
    SourceContext c_;
    PanelLeds& leds_;
    std::function<void(ButtonAction)> on_button_;
};

}  // namespace

std::unique_ptr<SensorSource> makeGpioSource(const SourceContext& c, PanelLeds& leds,
                                             std::function<void(ButtonAction)> on_button) {
    return std::make_unique<GpioSource>(c, leds, std::move(on_button));
}

}  // namespace handscan::pipeline_daemon
