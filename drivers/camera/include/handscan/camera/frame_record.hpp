// The binary record a camera frame is stored as in recordings (channels /camera/track and
// /camera/colour): the V4L2 buffer metadata, then the buffer bytes exactly as the device filled
// them. All integers little-endian; one record per recorded message, and records concatenate
// (a file of records is self-delimiting).
//
//   offset size  field
//    0     4     magic "HSVF"
//    4     2     version (1)
//    6     2     header_size (bytes before the payload; 56 in version 1, readers skip any extra)
//    8     4     sequence       v4l2_buffer.sequence
//   12     4     flags          v4l2_buffer.flags (timestamp type and source, ERROR)
//   16     8     timestamp_ns   v4l2_buffer.timestamp as ns (CLOCK_MONOTONIC when flagged so)
//   24     4     bytesused      payload length
//   28     4     fourcc         pixel format (GREY, YUYV, MJPG)
//   32     4     width          pixels
//   36     4     height         pixels
//   40     4     stride         bytes per line (0 for compressed formats)
//   44     4     exposure_us    exposure time in microseconds (0 = unknown)
//   48     8     t_host_ns      the driver's mid-exposure host time of the frame
//   56     bytesused payload
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::camera {

constexpr std::array<std::uint8_t, 4> kFrameRecordMagic = {'H', 'S', 'V', 'F'};
constexpr std::uint16_t kFrameRecordVersion = 1;
constexpr std::size_t kFrameRecordHeaderSize = 56;
constexpr std::uint32_t kMaxFrameDimension = 16384;
constexpr std::uint32_t kMaxFramePayload = 64u << 20;  // 64 MiB: larger is corruption
constexpr TimeNs kMaxFrameTimestamp = TimeNs{1} << 62;  // ~146 years of ns
constexpr std::uint32_t kMaxFrameStride = 4 * kMaxFrameDimension + 4096;  // 4 bytes/pixel + alignment

struct FrameRecordHeader {
    std::uint32_t sequence = 0;
    std::uint32_t flags = 0;
    TimeNs timestamp_ns = 0;
    std::uint32_t bytesused = 0;
    std::uint32_t fourcc = 0;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t stride = 0;
    std::uint32_t exposure_us = 0;
    TimeNs t_host_ns = 0;
    friend bool operator==(const FrameRecordHeader&, const FrameRecordHeader&) = default;
};

struct FrameRecordView {
    FrameRecordHeader header;
    std::span<const std::uint8_t> payload;
    std::size_t record_size = 0;  // bytes consumed, header + payload
};

// Header (bytesused taken from payload.size()) + payload.
std::vector<std::uint8_t> encodeFrameRecord(const FrameRecordHeader& header, std::span<const std::uint8_t> payload);
// One record from the start of `bytes`; kTruncated when it is incomplete, kProtocolError when
// it is not a frame record or its fields are inconsistent (stride, sizes, dimensions).
Result<FrameRecordView> decodeFrameRecord(std::span<const std::uint8_t> bytes);

}  // namespace handscan::camera
