#include "handscan/xsens/xbus_frame.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>

namespace handscan::xsens {

std::string messageName(std::uint8_t mid) {
    switch (static_cast<MessageId>(mid)) {
        case MessageId::kReqDid:
            return "ReqDID";
        case MessageId::kDeviceId:
            return "DeviceID";
        case MessageId::kGoToMeasurement:
            return "GoToMeasurement";
        case MessageId::kGoToMeasurementAck:
            return "GoToMeasurementAck";
        case MessageId::kSetBaudrate:
            return "SetBaudrate";
        case MessageId::kSetBaudrateAck:
            return "SetBaudrateAck";
        case MessageId::kReqProductCode:
            return "ReqProductCode";
        case MessageId::kProductCode:
            return "ProductCode";
        case MessageId::kGoToConfig:
            return "GoToConfig";
        case MessageId::kGoToConfigAck:
            return "GoToConfigAck";
        case MessageId::kMtData2:
            return "MTData2";
        case MessageId::kWakeUp:
            return "WakeUp";
        case MessageId::kWakeUpAck:
            return "WakeUpAck";
        case MessageId::kReset:
            return "Reset";
        case MessageId::kResetAck:
            return "ResetAck";
        case MessageId::kError:
            return "Error";
        case MessageId::kSetOutputConfiguration:
            return "SetOutputConfiguration";
        case MessageId::kSetOutputConfigurationAck:
            return "SetOutputConfigurationAck";
    }
    char text[8];
    std::snprintf(text, sizeof text, "0x%02X", mid);
    return text;
}

std::uint8_t xbusChecksum(std::uint8_t bus_id, std::uint8_t mid,
                          std::span<const std::uint8_t> payload) {
    unsigned sum = bus_id + mid;
    const std::size_t n = payload.size();
    if (n > kMaxStandardPayload) {
        sum += kExtendedLengthMarker + ((n >> 8) & 0xFF) + (n & 0xFF);
    } else {
        sum += static_cast<unsigned>(n);
    }
    for (std::uint8_t b : payload) sum += b;
    return static_cast<std::uint8_t>(-sum & 0xFF);
}

Status appendFrame(std::vector<std::uint8_t>& out, std::uint8_t mid,
                   std::span<const std::uint8_t> payload, std::uint8_t bus_id) {
    const std::size_t n = payload.size();
    if (n > kMaxPayload) {
        return {StatusCode::kInvalidArgument,
                "Xbus " + messageName(mid) + ": payload of " + std::to_string(n) +
                    " bytes exceeds the " + std::to_string(kMaxPayload) +
                    "-byte limit; split the data over several messages"};
    }
    out.push_back(kPreamble);
    out.push_back(bus_id);
    out.push_back(mid);
    if (n > kMaxStandardPayload) {
        out.push_back(kExtendedLengthMarker);
        out.push_back(static_cast<std::uint8_t>(n >> 8));
        out.push_back(static_cast<std::uint8_t>(n & 0xFF));
    } else {
        out.push_back(static_cast<std::uint8_t>(n));
    }
    out.insert(out.end(), payload.begin(), payload.end());
    out.push_back(xbusChecksum(bus_id, mid, payload));
    return Status::ok();
}

std::vector<std::uint8_t> encodeFrame(std::uint8_t mid, std::span<const std::uint8_t> payload,
                                      std::uint8_t bus_id) {
    std::vector<std::uint8_t> out;
    out.reserve(payload.size() + kFrameOverhead + 2);
    const Status s = appendFrame(out, mid, payload, bus_id);
    if (!s) throw std::length_error(s.message());
    return out;
}

std::vector<std::uint8_t> encodeFrame(MessageId mid, std::span<const std::uint8_t> payload,
                                      std::uint8_t bus_id) {
    return encodeFrame(toByte(mid), payload, bus_id);
}

Result<XbusFrameView> decodeFrame(std::span<const std::uint8_t> bytes) {
    if (bytes.size() < kFrameOverhead) {
        return Status{StatusCode::kTruncated,
                      "Xbus frame: " + std::to_string(bytes.size()) +
                          " bytes, a frame has at least 5 (FA BID MID LEN CS)"};
    }
    if (bytes[0] != kPreamble) {
        return Status{StatusCode::kProtocolError,
                      "Xbus frame: first byte is not the 0xFA preamble"};
    }
    std::size_t header = 4;
    std::size_t n = bytes[3];
    if (n == kExtendedLengthMarker) {
        if (bytes.size() < 7)
            return Status{StatusCode::kTruncated, "Xbus frame: extended length field cut off"};
        n = (std::size_t{bytes[4]} << 8) | bytes[5];
        header = 6;
    }
    if (bytes.size() != header + n + 1) {
        return Status{StatusCode::kTruncated,
                      "Xbus frame: length field says " + std::to_string(n) +
                          " payload bytes, the buffer holds " + std::to_string(bytes.size()) +
                          " bytes in all (expected " + std::to_string(header + n + 1) + ")"};
    }
    unsigned sum = 0;
    for (std::size_t i = 1; i < bytes.size(); ++i) sum += bytes[i];
    if ((sum & 0xFF) != 0) {
        return Status{
            StatusCode::kChecksumError,
            "Xbus " + messageName(bytes[2]) + " frame: checksum does not add up (sum ends in " +
                std::to_string(sum & 0xFF) + ", expected 0); the frame was damaged on the wire"};
    }
    return XbusFrameView{bytes[1], bytes[2], bytes.subspan(header, n)};
}

}  // namespace handscan::xsens
