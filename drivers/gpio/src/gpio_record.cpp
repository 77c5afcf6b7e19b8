#include "handscan/gpio/gpio_record.hpp"

#include <string>

namespace handscan::gpio {

const char* toString(PanelRole r) {
    switch (r) {
        case PanelRole::kOther:
            return "other";
        case PanelRole::kScanButton:
            return "scan_button";
        case PanelRole::kExportButton:
            return "export_button";
        case PanelRole::kCameraTrigger:
            return "camera_trigger";
        case PanelRole::kLedReady:
            return "led_ready";
        case PanelRole::kLedScanning:
            return "led_scanning";
        case PanelRole::kLedFault:
            return "led_fault";
        case PanelRole::kLedExporting:
            return "led_exporting";
    }
    return "?";
}

const char* toString(GpioRecordKind k) {
    switch (k) {
        case GpioRecordKind::kRisingEdge:
            return "rising";
        case GpioRecordKind::kFallingEdge:
            return "falling";
        case GpioRecordKind::kOutputOff:
            return "output_off";
        case GpioRecordKind::kOutputOn:
            return "output_on";
    }
    return "?";
}

std::array<std::uint8_t, kGpioRecordSize> encodeGpioRecord(const GpioRecord& r) {
    std::array<std::uint8_t, kGpioRecordSize> b{};
    for (int i = 0; i < 8; ++i)
        b[static_cast<std::size_t>(i)] =
            static_cast<std::uint8_t>(static_cast<std::uint64_t>(r.t_host) >> (8 * i));
    for (int i = 0; i < 4; ++i)
        b[8 + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(r.line >> (8 * i));
    b[12] = static_cast<std::uint8_t>(r.kind);
    b[13] = static_cast<std::uint8_t>(r.role);
    b[14] = 'G';
    b[15] = 1;
    return b;
}

Result<GpioRecord> decodeGpioRecord(std::span<const std::uint8_t> b) {
    if (b.size() < kGpioRecordSize) {
        return Status(StatusCode::kTruncated,
                      "gpio record: " + std::to_string(b.size()) + " bytes, a record is 16");
    }
    if (b[14] != 'G' || b[15] != 1)
        return Status(StatusCode::kProtocolError, "gpio record: bad magic/version (bytes 14..15)");
    if (b[12] < 1 || b[12] > 4)
        return Status(StatusCode::kProtocolError,
                      "gpio record: kind " + std::to_string(b[12]) + " not 1..4");
    const std::uint8_t role = b[13];
    if (!(role <= 3 || (role >= 16 && role <= 19)))
        return Status(StatusCode::kProtocolError,
                      "gpio record: unknown role " + std::to_string(role));
    GpioRecord r;
    std::uint64_t t = 0;
    for (int i = 0; i < 8; ++i)
        t |= static_cast<std::uint64_t>(b[static_cast<std::size_t>(i)]) << (8 * i);
    r.t_host = static_cast<TimeNs>(t);
    for (int i = 0; i < 4; ++i)
        r.line |= static_cast<std::uint32_t>(b[8 + static_cast<std::size_t>(i)]) << (8 * i);
    r.kind = static_cast<GpioRecordKind>(b[12]);
    r.role = static_cast<PanelRole>(role);
    return r;
}

}  // namespace handscan::gpio
