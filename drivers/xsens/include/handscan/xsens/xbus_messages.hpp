// Payloads of the Xbus control messages the driver and the fake device exchange: the config
// handshake (GoToConfig, ReqDID, ReqProductCode, SetBaudrate, SetOutputConfiguration,
// GoToMeasurement, WakeUp, Reset) and the Error message (MID 0x42) with a clear text per code.
// Pure encode/decode; each function names the message it belongs to.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/xsens/xbus_frame.hpp"

namespace handscan::xsens {

// ---- Error (0x42): 1 byte code (a DeviceError may carry more bytes, which we keep) ----
enum class ErrorCode : std::uint8_t {
    kNoBus = 0x01,
    kBusNotReady = 0x02,
    kInvalidPeriod = 0x03,
    kInvalidMessage = 0x04,
    kTimerOverflow = 0x1E,
    kInvalidBaudrate = 0x20,
    kInvalidParameter = 0x21,
    kDeviceError = 0x28,
    kDataOverflow = 0x29,
    kBufferOverflow = 0x2A,
};

struct XbusError {
    std::uint8_t code = 0;
    std::vector<std::uint8_t> extra;  // bytes after the code (DeviceError detail), as sent
};

// "InvalidPeriod (0x03): the sampling period sent is out of range ..." and what to do about it.
std::string errorText(std::uint8_t code);
Result<XbusError> decodeError(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encodeErrorFrame(ErrorCode code);

// ---- SetOutputConfiguration (0xC0) and its ack (0xC1, which echoes the configuration) ----
// Rate 0xFFFF (or 0) means "in every packet" (PacketCounter, SampleTimeFine, StatusWord).
constexpr std::uint16_t kEveryPacket = 0xFFFF;
constexpr std::size_t kMaxOutputEntries = 32;

struct OutputConfigEntry {
    std::uint16_t xdi = 0;      // data identifier incl. precision / coordinate-system bits
    std::uint16_t rate_hz = 0;  // output rate, or kEveryPacket
    bool operator==(const OutputConfigEntry&) const = default;
};

std::vector<std::uint8_t> encodeOutputConfiguration(std::span<const OutputConfigEntry> entries);
Result<std::vector<OutputConfigEntry>> decodeOutputConfiguration(
    std::span<const std::uint8_t> payload);

// ---- SetBaudrate (0x18): 1 byte baud-rate id ----
// Baud ids: 0x80 (and the older 0x0A) = 921600, 00 = 460800, 01 = 230400, 02 = 115200 (default),
// 04 = 57600, 05 = 38400, 07 = 19200, 09 = 9600. nullopt for a rate the MTi does not offer.
std::optional<std::uint8_t> baudrateId(int baud);
std::optional<int> baudrateFromId(std::uint8_t id);

// ---- DeviceID (0x01): u32 device id; ProductCode (0x1D): ASCII, space padded ----
Result<std::uint32_t> decodeDeviceId(std::span<const std::uint8_t> payload);
std::vector<std::uint8_t> encodeDeviceId(std::uint32_t device_id);
std::string decodeProductCode(
    std::span<const std::uint8_t> payload);  // trailing spaces/NULs trimmed
std::vector<std::uint8_t> encodeProductCode(const std::string& code);

// ---- Big-endian helpers shared by the codecs ----
inline void putU16(std::vector<std::uint8_t>& out, std::uint16_t v) {
    out.push_back(static_cast<std::uint8_t>(v >> 8));
    out.push_back(static_cast<std::uint8_t>(v));
}
inline void putU32(std::vector<std::uint8_t>& out, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}
inline void putU64(std::vector<std::uint8_t>& out, std::uint64_t v) {
    for (int s = 56; s >= 0; s -= 8) out.push_back(static_cast<std::uint8_t>(v >> s));
}
inline std::uint16_t getU16(const std::uint8_t* p) {
    return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
}
inline std::uint32_t getU32(const std::uint8_t* p) {
    return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
           p[3];
}
inline std::uint64_t getU64(const std::uint8_t* p) {
    return (std::uint64_t{getU32(p)} << 32) | getU32(p + 4);
}

}  // namespace handscan::xsens
