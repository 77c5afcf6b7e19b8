#include "handscan/xsens/xbus_messages.hpp"

#include <cstdio>

namespace handscan::xsens {

std::string errorText(std::uint8_t code) {
    const char* text = nullptr;
    switch (static_cast<ErrorCode>(code)) {
        case ErrorCode::kNoBus:
            text = "NoBus (0x01): no bus communication possible; check the cable and power";
            break;
        case ErrorCode::kBusNotReady:
            text = "BusNotReady (0x02): the bus is not initialised";
            break;
        case ErrorCode::kInvalidPeriod:
            text =
                "InvalidPeriod (0x03): the sampling period / output rate sent is out of range; use "
                "a rate the "
                "device supports (the MTi-20 runs IMU outputs at up to 400 Hz, rates that divide "
                "400)";
            break;
        case ErrorCode::kInvalidMessage:
            text =
                "InvalidMessage (0x04): the device rejected the message as invalid or not "
                "implemented (wrong "
                "state? configuration messages need config mode: send GoToConfig first)";
            break;
        case ErrorCode::kTimerOverflow:
            text = "TimerOverflow (0x1E): timer overflow during measurement";
            break;
        case ErrorCode::kInvalidBaudrate:
            text = "InvalidBaudrate (0x20): the requested baud rate is not one the device supports";
            break;
        case ErrorCode::kInvalidParameter:
            text =
                "InvalidParameter (0x21): a parameter is invalid or out of range (e.g. an output "
                "the device "
                "does not have, or too many outputs for the baud rate)";
            break;
        case ErrorCode::kDeviceError:
            text =
                "DeviceError (0x28): the device reported an internal error; power-cycle it and "
                "update its "
                "firmware if it persists";
            break;
        case ErrorCode::kDataOverflow:
            text =
                "DataOverflow (0x29): the device produces more data than the link can carry; raise "
                "the baud "
                "rate or lower output rates";
            break;
        case ErrorCode::kBufferOverflow:
            text =
                "BufferOverflow (0x2A): the device's sample buffer overflowed during a "
                "communication outage; "
                "samples were lost";
            break;
    }
    if (text != nullptr) return text;
    char buf[64];
    std::snprintf(buf, sizeof buf, "unknown error code 0x%02X", code);
    return buf;
}

Result<XbusError> decodeError(std::span<const std::uint8_t> payload) {
    if (payload.empty()) {
        return Status{StatusCode::kProtocolError,
                      "Xbus Error (0x42) message without an error code byte"};
    }
    return XbusError{payload[0], std::vector<std::uint8_t>(payload.begin() + 1, payload.end())};
}

std::vector<std::uint8_t> encodeErrorFrame(ErrorCode code) {
    const std::uint8_t b = static_cast<std::uint8_t>(code);
    return encodeFrame(MessageId::kError, std::span<const std::uint8_t>(&b, 1));
}

std::vector<std::uint8_t> encodeOutputConfiguration(std::span<const OutputConfigEntry> entries) {
    std::vector<std::uint8_t> out;
    out.reserve(entries.size() * 4);
    for (const auto& e : entries) {
        putU16(out, e.xdi);
        putU16(out, e.rate_hz);
    }
    return out;
}

Result<std::vector<OutputConfigEntry>> decodeOutputConfiguration(
    std::span<const std::uint8_t> payload) {
    if (payload.size() % 4 != 0) {
        return Status{StatusCode::kProtocolError,
                      "Xbus OutputConfiguration: " + std::to_string(payload.size()) +
                          " bytes is not a multiple of 4 (XDI u16 + rate u16 per entry)"};
    }
    if (payload.size() / 4 > kMaxOutputEntries) {
        return Status{StatusCode::kProtocolError,
                      "Xbus OutputConfiguration: " + std::to_string(payload.size() / 4) +
                          " entries, the device accepts at most 32"};
    }
    std::vector<OutputConfigEntry> entries;
    for (std::size_t i = 0; i < payload.size(); i += 4) {
        entries.push_back({getU16(&payload[i]), getU16(&payload[i + 2])});
    }
    return entries;
}

std::optional<std::uint8_t> baudrateId(int baud) {
    switch (baud) {
        case 921600:
            return 0x80;
        case 460800:
            return 0x00;
        case 230400:
            return 0x01;
        case 115200:
            return 0x02;
        case 57600:
            return 0x04;
        case 38400:
            return 0x05;
        case 19200:
            return 0x07;
        case 9600:
            return 0x09;
        default:
            return std::nullopt;
    }
}

std::optional<int> baudrateFromId(std::uint8_t id) {
    switch (id) {
        case 0x80:
        case 0x0A:
            return 921600;
        case 0x00:
            return 460800;
        case 0x01:
            return 230400;
        case 0x02:
            return 115200;
        case 0x04:
            return 57600;
        case 0x05:
            return 38400;
        case 0x07:
            return 19200;
        case 0x09:
            return 9600;
        default:
            return std::nullopt;
    }
}

Result<std::uint32_t> decodeDeviceId(std::span<const std::uint8_t> payload) {
    if (payload.size() != 4) {
        return Status{StatusCode::kProtocolError, "Xbus DeviceID: expected a 4-byte id, got " +
                                                      std::to_string(payload.size()) + " bytes"};
    }
    return getU32(payload.data());
}

std::vector<std::uint8_t> encodeDeviceId(std::uint32_t device_id) {
    std::vector<std::uint8_t> out;
    putU32(out, device_id);
    return out;
}

std::string decodeProductCode(std::span<const std::uint8_t> payload) {
    std::string s(payload.begin(), payload.end());
    while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
    return s;
}

std::vector<std::uint8_t> encodeProductCode(const std::string& code) {
    // The device pads the product code with spaces to 20 characters.
    std::vector<std::uint8_t> out(code.begin(), code.end());
    while (out.size() < 20) out.push_back(' ');
    return out;
}

}  // namespace handscan::xsens
