// The record of one GPIO event in recordings (channel /gpio/events): every input edge as the
// kernel reported it (before debouncing, so replays debounce again) and every LED output change.
// 16 bytes, little-endian:
//   offset size field
//    0     8    t_host_ns  host CLOCK_MONOTONIC time of the edge / output write
//    8     4    line       line offset on the chip
//   12     1    kind       1 rising edge, 2 falling edge (logical levels), 3 output off, 4 output
//   on 13     1    role       1 scan button, 2 export button, 3 camera trigger,
//                          16 LED ready, 17 LED scanning, 18 LED fault, 19 LED exporting, 0 other
//   14     1    magic 'G'
//   15     1    version 1
#pragma once

#include <array>
#include <cstdint>
#include <span>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::gpio {

enum class PanelRole : std::uint8_t {
    kOther = 0,
    kScanButton = 1,
    kExportButton = 2,
    kCameraTrigger = 3,
    kLedReady = 16,
    kLedScanning = 17,
    kLedFault = 18,
    kLedExporting = 19
};
const char* toString(PanelRole r);

enum class GpioRecordKind : std::uint8_t {
    kRisingEdge = 1,
    kFallingEdge = 2,
    kOutputOff = 3,
    kOutputOn = 4
};
const char* toString(GpioRecordKind k);

struct GpioRecord {
    TimeNs t_host = 0;
    std::uint32_t line = 0;
    GpioRecordKind kind = GpioRecordKind::kRisingEdge;
    PanelRole role = PanelRole::kOther;
    friend bool operator==(const GpioRecord&, const GpioRecord&) = default;
};

constexpr std::size_t kGpioRecordSize = 16;
std::array<std::uint8_t, kGpioRecordSize> encodeGpioRecord(const GpioRecord& r);
// Exactly one record from the start of `bytes` (longer input: the rest is the next record).
Result<GpioRecord> decodeGpioRecord(std::span<const std::uint8_t> bytes);

}  // namespace handscan::gpio
