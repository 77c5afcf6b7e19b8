// Xbus framing (Xsens MT low-level protocol): FA | BID | MID | LEN | [EXTLEN u16 BE] | DATA | CS.
// Pure encode/decode of single frames, the message ids the driver and the simulator use, and the
// checksum rule (every byte after the preamble, checksum included, sums to 0 mod 256). The
// incremental parser for a byte stream is in xbus_parser.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::xsens {

constexpr std::uint8_t kPreamble = 0xFA;
constexpr std::uint8_t kBusIdMaster = 0xFF;  // the only bus id an MTi sends and accepts
constexpr std::uint8_t kExtendedLengthMarker = 0xFF;
constexpr std::size_t kMaxStandardPayload = 254;
// Largest payload we accept; the extended length field could say 65535, but no MTi message is
// longer than this (xsens-go uses the same limit), so longer ones are treated as garbage.
constexpr std::size_t kMaxPayload = 2048;
constexpr std::size_t kFrameOverhead = 5;  // FA BID MID LEN CS

// Message ids used by the driver, the fake device and the simulator (xsxbusmessageid.h).
// An acknowledgement has the request's id + 1.
enum class MessageId : std::uint8_t {
    kReqDid = 0x00,
    kDeviceId = 0x01,
    kGoToMeasurement = 0x10,
    kGoToMeasurementAck = 0x11,
    kSetBaudrate = 0x18,
    kSetBaudrateAck = 0x19,
    kReqProductCode = 0x1C,
    kProductCode = 0x1D,
    kGoToConfig = 0x30,
    kGoToConfigAck = 0x31,
    kMtData2 = 0x36,
    kWakeUp = 0x3E,
    kWakeUpAck = 0x3F,
    kReset = 0x40,
    kResetAck = 0x41,
    kError = 0x42,
    kSetOutputConfiguration = 0xC0,
    kSetOutputConfigurationAck = 0xC1,
};

constexpr std::uint8_t toByte(MessageId mid) { return static_cast<std::uint8_t>(mid); }
constexpr MessageId ackOf(MessageId request) { return static_cast<MessageId>(toByte(request) + 1); }
// "GoToConfig", "MTData2", ... or "0x5A" style text for ids this table does not name.
std::string messageName(std::uint8_t mid);

// One decoded frame. `payload` views the buffer it was decoded from.
struct XbusFrameView {
    std::uint8_t bus_id = kBusIdMaster;
    std::uint8_t mid = 0;
    std::span<const std::uint8_t> payload;
};

// Checksum byte that makes Σ(BID..CS) ≡ 0 (mod 256) for the given BID, MID and payload.
std::uint8_t xbusChecksum(std::uint8_t bus_id, std::uint8_t mid,
                          std::span<const std::uint8_t> payload);

// Appends one complete frame (standard or, above 254 bytes, extended length) to `out`.
// Payloads longer than kMaxPayload are a programming error: kInvalidArgument.
Status appendFrame(std::vector<std::uint8_t>& out, std::uint8_t mid,
                   std::span<const std::uint8_t> payload, std::uint8_t bus_id = kBusIdMaster);
// A complete frame as a new buffer (throws std::length_error above kMaxPayload: build-time use).
std::vector<std::uint8_t> encodeFrame(MessageId mid, std::span<const std::uint8_t> payload = {},
                                      std::uint8_t bus_id = kBusIdMaster);
std::vector<std::uint8_t> encodeFrame(std::uint8_t mid, std::span<const std::uint8_t> payload = {},
                                      std::uint8_t bus_id = kBusIdMaster);

// Decodes exactly one frame occupying all of `bytes` (no leading garbage, nothing after it).
Result<XbusFrameView> decodeFrame(std::span<const std::uint8_t> bytes);

}  // namespace handscan::xsens
