// The panel over the fake line layer: debounced buttons, trigger edges, LED blink writes, tap.
#include "handscan/gpio/gpio_panel.hpp"

#include <gtest/gtest.h>

#include "handscan/gpio/fake_gpio_chip.hpp"

namespace handscan::gpio {
namespace {

constexpr TimeNs ms = kNsPerMs;

PanelConfig panel() {
    PanelConfig c;
    c.scan_button = 5;
    c.export_button = 6;
    c.camera_trigger = 7;
    c.led_ready = 20;
    c.led_scanning = 21;
    c.led_fault = 22;
    c.led_exporting = 23;
    return c;
}

struct Tap : RawTap {
    void onRaw(TimeNs, std::span<const std::uint8_t> b) override {
        auto r = decodeGpioRecord(b);
        ASSERT_TRUE(r);
        records.push_back(*r);
    }
    std::vector<GpioRecord> records;
};

std::vector<PanelEvent> runUntil(GpioPanel& p, FakeGpioChip& chip, TimeNs until) {
    std::vector<PanelEvent> all;
    while (chip.now() < until) {
        auto r = p.poll(until - chip.now());
        EXPECT_TRUE(r) << r.status().message();
        if (!r) break;
        all.insert(all.end(), r->begin(), r->end());
    }
    return all;
}

TEST(GpioPanel, DebouncesButtonsAndKeepsFirstContactTimes) {
    FakeGpioChip chip;
    Tap tap;
    GpioPanel p(chip, panel(), &tap);
    ASSERT_TRUE(p.start());
    chip.injectBouncyPress(5, 100 * ms, 4, ms, true);   // press with 4 bounces
    chip.injectBouncyPress(5, 600 * ms, 3, ms, false);  // release with 3 bounces
    chip.injectBouncyPress(6, 700 * ms, 0, ms, true);
    chip.inject(6, 705 * ms, GpioEdgeType::kFalling);  // a 5 ms tap
    const auto ev = runUntil(p, chip, kNsPerSec);
    ASSERT_EQ(ev.size(), 4u);
    EXPECT_EQ(ev[0].role, PanelRole::kScanButton);
    EXPECT_EQ(ev[0].kind, PanelEventKind::kPressed);
    EXPECT_EQ(ev[0].t_host, 100 * ms);
    EXPECT_EQ(ev[1].kind, PanelEventKind::kReleased);
    EXPECT_EQ(ev[1].t_host, 600 * ms);
    EXPECT_EQ(ev[2].role, PanelRole::kExportButton);
    EXPECT_EQ(ev[2].kind, PanelEventKind::kPressed);
    EXPECT_EQ(ev[3].kind, PanelEventKind::kReleased);
    EXPECT_EQ(ev[3].t_host, 705 * ms);
    EXPECT_EQ(p.stats().bounces, 8u + 6u + 1u);
    // Every raw edge was recorded, before debouncing.
    std::size_t edges = 0;
    for (const auto& r : tap.records)
        edges += r.kind == GpioRecordKind::kRisingEdge || r.kind == GpioRecordKind::kFallingEdge;
    EXPECT_EQ(edges, 9u + 7u + 2u);
}

TEST(GpioPanel, ReportsCameraTriggerRisingEdgesUndebounced) {
    FakeGpioChip chip;
    GpioPanel p(chip, panel());
    ASSERT_TRUE(p.start());
    for (int i = 0; i < 10; ++i) {
        chip.inject(7, (10 + 33 * i) * ms, GpioEdgeType::kRising);
        chip.inject(7, (10 + 33 * i) * ms + 100 * kNsPerUs, GpioEdgeType::kFalling);
    }
    const auto ev = runUntil(p, chip, 500 * ms);
    ASSERT_EQ(ev.size(), 10u);
    for (int i = 0; i < 10; ++i) {
        EXPECT_EQ(ev[static_cast<std::size_t>(i)].kind, PanelEventKind::kTrigger);
        EXPECT_EQ(ev[static_cast<std::size_t>(i)].t_host, (10 + 33 * i) * ms);
    }
}

TEST(GpioPanel, DrivesLedPatternsOnTime) {
    FakeGpioChip chip;
    Tap tap;
    GpioPanel p(chip, panel(), &tap);
    ASSERT_TRUE(p.start());
    ASSERT_TRUE(p.setLed(PanelRole::kLedScanning, LedPattern::kOn));
    ASSERT_TRUE(p.setLed(PanelRole::kLedFault, LedPattern::kBlinkFast));
    EXPECT_TRUE(chip.outputLevel(21));
    EXPECT_TRUE(chip.outputLevel(22));
    (void)runUntil(p, chip, kNsPerSec);
    std::vector<TimeNs> fault_writes;
    for (const auto& w : chip.writes()) {
        if (w.line == 22) fault_writes.push_back(w.t);
    }
    ASSERT_EQ(fault_writes.size(), 9u);  // on at 0, then a flip every 125 ms up to 1 s
    for (std::size_t i = 0; i < fault_writes.size(); ++i)
        EXPECT_EQ(fault_writes[i], static_cast<TimeNs>(i) * 125 * ms);
    ASSERT_TRUE(p.setLed(PanelRole::kLedFault, LedPattern::kOff));
    EXPECT_FALSE(chip.outputLevel(22));
    EXPECT_EQ(p.led(PanelRole::kLedScanning), LedPattern::kOn);
    std::size_t outputs = 0;
    for (const auto& r : tap.records)
        outputs += r.kind == GpioRecordKind::kOutputOn || r.kind == GpioRecordKind::kOutputOff;
    EXPECT_EQ(outputs, chip.writes().size());
}

TEST(GpioPanel, NamesTheLineThatCannotBeRequested) {
    FakeGpioChip chip(7);  // lines 0..6: the trigger (7) does not exist
    GpioPanel p(chip, panel());
    Status s = p.start();
    ASSERT_FALSE(s);
    EXPECT_NE(s.message().find("camera_trigger"), std::string::npos) << s.message();
    EXPECT_NE(s.message().find("no line 7"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace handscan::gpio
