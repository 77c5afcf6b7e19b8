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
//
// Version 2 (header_size 64) stores the payload coded, to keep recordings of uncompressed
// cameras small; decoding gives back exactly the buffer's bytesused bytes:
//   56     4     coding         0 = the buffer's bytes as they are, 1 = PNG (png_payload.hpp:
//                               GREY as 8-bit grey, YUYV as 8-bit grey+alpha, stride x height)
//   60     4     stored_size    bytes of the coded payload
//   64     stored_size payload
// Writers use version 1 for uncoded payloads, so those records are unchanged.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::camera {

constexpr std::array<std::uint8_t, 4> kFrameRecordMagic = {'H', 'S', 'V', 'F'};
constexpr std::uint16_t kFrameRecordVersion = 1;
constexpr std::size_t kFrameRecordHeaderSize = 56;
constexpr std::uint16_t kFrameRecordCodedVersion = 2;
constexpr std::size_t kFrameRecordCodedHeaderSize = 64;
constexpr std::uint32_t kMaxFrameDimension = 16384;
constexpr std::uint32_t kMaxFramePayload = 64u << 20;   // 64 MiB: larger is corruption
constexpr TimeNs kMaxFrameTimestamp = TimeNs{1} << 62;  // ~146 years of ns
constexpr std::uint32_t kMaxFrameStride =
    4 * kMaxFrameDimension + 4096;  // 4 bytes/pixel + alignment

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

// How a record stores the buffer's bytes.
enum class FrameCoding : std::uint32_t { kRaw = 0, kPng = 1 };

// What decodeFrameRecord() does with a coded payload.
enum class FramePayload { kDecoded, kHeaderOnly };

struct FrameRecordView {
    FrameRecordHeader header;
    // The buffer's bytes (header.bytesused) exactly as the device delivered them; empty for a
    // coded record read with FramePayload::kHeaderOnly. Points into the input, or into
    // `decoded` (shared, so copies of the view stay valid).
    std::span<const std::uint8_t> payload;
    std::size_t record_size = 0;  // bytes consumed, header + stored payload
    FrameCoding coding = FrameCoding::kRaw;
    std::size_t stored_size = 0;  // payload bytes in the record (coded size)
    std::shared_ptr<const std::vector<std::uint8_t>> decoded;
};

// Header (bytesused taken from payload.size()) + payload, version 1.
std::vector<std::uint8_t> encodeFrameRecord(const FrameRecordHeader& header,
                                            std::span<const std::uint8_t> payload);
// With `coding` kPng, a version-2 record holding the payload as PNG where the format allows
// (canStorePng()), else the version-1 record.
std::vector<std::uint8_t> encodeFrameRecord(const FrameRecordHeader& header,
                                            std::span<const std::uint8_t> payload,
                                            FrameCoding coding);
// One record from the start of `bytes`; kTruncated when it is incomplete, kProtocolError when
// it is not a frame record or its fields are inconsistent (stride, sizes, dimensions) or a
// coded payload does not decode to the buffer the header describes.
Result<FrameRecordView> decodeFrameRecord(std::span<const std::uint8_t> bytes,
                                          FramePayload payload = FramePayload::kDecoded);

// The record with its clock moved by `offset` (another host's CLOCK_MONOTONIC onto this one's, as
// `handscan hil` plays a recording): t_host_ns, and timestamp_ns when the flags say it is on
// CLOCK_MONOTONIC. The stored payload is kept as it is (no PNG re-coding). kProtocolError when
// `record` does not start with a valid record header.
[[nodiscard]] Status shiftFrameRecordTimes(std::span<std::uint8_t> record, TimeNs offset);

}  // namespace handscan::camera
