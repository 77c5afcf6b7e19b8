#include "handscan/camera/frame_record.hpp"

#include <algorithm>
#include <cstring>
#include <string>

#include "handscan/camera/png_payload.hpp"
#include "handscan/core/v4l2_types.hpp"

namespace handscan::camera {
namespace {

void put(std::vector<std::uint8_t>& out, std::size_t at, std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i)
        out[at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint64_t get(std::span<const std::uint8_t> b, std::size_t at, int n) {
    std::uint64_t v = 0;
    for (int i = 0; i < n; ++i)
        v |= static_cast<std::uint64_t>(b[at + static_cast<std::size_t>(i)]) << (8 * i);
    return v;
}
Status bad(const std::string& what) {
    return {StatusCode::kProtocolError, "camera frame record: " + what};
}

// Minimum bytes per line of an uncompressed format (0 = compressed, no stride).
std::uint64_t minStride(std::uint32_t fourcc, std::uint32_t width) {
    if (fourcc == kFourccGrey) return width;
    if (fourcc == kFourccYuyv) return 2ull * width;
    return 0;
}

}  // namespace

namespace {

// The common 56 header bytes; the caller sets version and header size.
void putHeader(std::vector<std::uint8_t>& out, const FrameRecordHeader& h, std::size_t bytesused) {
    for (std::size_t i = 0; i < kFrameRecordMagic.size(); ++i) out[i] = kFrameRecordMagic[i];
    put(out, 8, h.sequence, 4);
    put(out, 12, h.flags, 4);
    put(out, 16, static_cast<std::uint64_t>(h.timestamp_ns), 8);
    put(out, 24, bytesused, 4);
    put(out, 28, h.fourcc, 4);
    put(out, 32, h.width, 4);
    put(out, 36, h.height, 4);
    put(out, 40, h.stride, 4);
    put(out, 44, h.exposure_us, 4);
    put(out, 48, static_cast<std::uint64_t>(h.t_host_ns), 8);
}

}  // namespace

std::vector<std::uint8_t> encodeFrameRecord(const FrameRecordHeader& h,
                                            std::span<const std::uint8_t> payload) {
    std::vector<std::uint8_t> out(kFrameRecordHeaderSize + payload.size());
    putHeader(out, h, payload.size());
    put(out, 4, kFrameRecordVersion, 2);
    put(out, 6, kFrameRecordHeaderSize, 2);
    if (!payload.empty())
        std::memcpy(out.data() + kFrameRecordHeaderSize, payload.data(), payload.size());
    return out;
}

std::vector<std::uint8_t> encodeFrameRecord(const FrameRecordHeader& h,
                                            std::span<const std::uint8_t> payload,
                                            FrameCoding coding) {
    FrameRecordHeader used = h;
    used.bytesused = static_cast<std::uint32_t>(payload.size());
    if (coding != FrameCoding::kPng || !canStorePng(used)) return encodeFrameRecord(h, payload);
    auto png = encodePngPayload(used, payload);
    if (!png) return encodeFrameRecord(h, payload);  // libpng out of memory: store it as it is
    std::vector<std::uint8_t> out(kFrameRecordCodedHeaderSize + png->size());
    putHeader(out, h, payload.size());
    put(out, 4, kFrameRecordCodedVersion, 2);
    put(out, 6, kFrameRecordCodedHeaderSize, 2);
    put(out, 56, static_cast<std::uint32_t>(FrameCoding::kPng), 4);
    put(out, 60, png->size(), 4);
    std::memcpy(out.data() + kFrameRecordCodedHeaderSize, png->data(), png->size());
    return out;
}

Result<FrameRecordView> decodeFrameRecord(std::span<const std::uint8_t> b, FramePayload want) {
    if (b.size() < 8)
        return Status(StatusCode::kTruncated, "camera frame record: " + std::to_string(b.size()) +
                                                  " bytes, the header alone needs 56");
    if (!std::equal(kFrameRecordMagic.begin(), kFrameRecordMagic.end(), b.begin()))
        return bad("magic is not 'HSVF'");
    const auto version = static_cast<std::uint16_t>(get(b, 4, 2));
    const auto header_size = static_cast<std::uint16_t>(get(b, 6, 2));
    if (version != kFrameRecordVersion && version != kFrameRecordCodedVersion) {
        return bad("version " + std::to_string(version) + ", this reader knows 1 and 2");
    }
    const std::size_t min_header =
        version == kFrameRecordVersion ? kFrameRecordHeaderSize : kFrameRecordCodedHeaderSize;
    if (header_size < min_header)
        return bad("header size " + std::to_string(header_size) + " < " +
                   std::to_string(min_header));
    if (b.size() < header_size)
        return Status(StatusCode::kTruncated,
                      "camera frame record: header cut at " + std::to_string(b.size()) + " bytes");
    FrameRecordView v;
    FrameRecordHeader& h = v.header;
    h.sequence = static_cast<std::uint32_t>(get(b, 8, 4));
    h.flags = static_cast<std::uint32_t>(get(b, 12, 4));
    h.timestamp_ns = static_cast<TimeNs>(get(b, 16, 8));
    h.bytesused = static_cast<std::uint32_t>(get(b, 24, 4));
    h.fourcc = static_cast<std::uint32_t>(get(b, 28, 4));
    h.width = static_cast<std::uint32_t>(get(b, 32, 4));
    h.height = static_cast<std::uint32_t>(get(b, 36, 4));
    h.stride = static_cast<std::uint32_t>(get(b, 40, 4));
    h.exposure_us = static_cast<std::uint32_t>(get(b, 44, 4));
    h.t_host_ns = static_cast<TimeNs>(get(b, 48, 8));
    if (h.width == 0 || h.height == 0 || h.width > kMaxFrameDimension ||
        h.height > kMaxFrameDimension) {
        return bad("size " + std::to_string(h.width) + "x" + std::to_string(h.height) +
                   " outside 1..16384");
    }
    // Timestamps are CLOCK_MONOTONIC-like ns: non-negative, and far from overflow when shifted.
    if (h.timestamp_ns < 0 || h.timestamp_ns > kMaxFrameTimestamp)
        return bad("timestamp " + std::to_string(h.timestamp_ns) + " ns out of range");
    if (h.bytesused > kMaxFramePayload)
        return bad("bytesused " + std::to_string(h.bytesused) + " over 64 MiB");
    if (h.stride > kMaxFrameStride)
        return bad("stride " + std::to_string(h.stride) + " over " +
                   std::to_string(kMaxFrameStride));
    const std::uint64_t min_stride = minStride(h.fourcc, h.width);
    if (min_stride > 0) {
        if (h.stride < min_stride)
            return bad(fourccName(h.fourcc) + " stride " + std::to_string(h.stride) + " < " +
                       std::to_string(min_stride));
        // The last line needs only its pixels, not the padding.
        if (h.bytesused < static_cast<std::uint64_t>(h.stride) * (h.height - 1) + min_stride) {
            return bad(fourccName(h.fourcc) + " payload " + std::to_string(h.bytesused) +
                       " bytes too short for " + std::to_string(h.width) + "x" +
                       std::to_string(h.height) + " stride " + std::to_string(h.stride));
        }
    } else if (h.fourcc != kFourccMjpeg) {
        return bad("unknown pixel format '" + fourccName(h.fourcc) + "'");
    }
    v.stored_size = h.bytesused;
    if (version == kFrameRecordCodedVersion) {
        const auto coding = static_cast<std::uint32_t>(get(b, 56, 4));
        if (coding > static_cast<std::uint32_t>(FrameCoding::kPng))
            return bad("unknown payload coding " + std::to_string(coding));
        v.coding = static_cast<FrameCoding>(coding);
        v.stored_size = static_cast<std::size_t>(get(b, 60, 4));
        if (v.stored_size > kMaxFramePayload)
            return bad("stored size " + std::to_string(v.stored_size) + " over 64 MiB");
        if (v.coding == FrameCoding::kRaw && v.stored_size != h.bytesused) {
            return bad("uncoded payload of " + std::to_string(v.stored_size) +
                       " bytes, bytesused " + std::to_string(h.bytesused));
        }
    }
    const std::size_t total = header_size + v.stored_size;
    if (b.size() < total) {
        return Status(StatusCode::kTruncated, "camera frame record: payload cut (" +
                                                  std::to_string(b.size() - header_size) + " of " +
                                                  std::to_string(v.stored_size) + " bytes)");
    }
    const auto stored = b.subspan(header_size, v.stored_size);
    v.record_size = total;
    if (v.coding == FrameCoding::kRaw) {
        v.payload = stored;
    } else if (want == FramePayload::kDecoded) {
        auto buffer = std::make_shared<std::vector<std::uint8_t>>();
        if (Status s = decodePngPayload(h, stored, *buffer); !s)
            return bad("frame " + std::to_string(h.sequence) + ": " + s.message());
        v.payload = *buffer;
        v.decoded = std::move(buffer);
    }
    return v;
}

Status shiftFrameRecordTimes(std::span<std::uint8_t> record, TimeNs offset) {
    auto view = decodeFrameRecord(record, FramePayload::kHeaderOnly);
    if (!view) return view.status();
    // Only the two time fields change: the rest of the header (version, sizes, coding) stays.
    const auto put64 = [&](std::size_t at, TimeNs v) {
        for (std::size_t i = 0; i < 8; ++i)
            record[at + i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(v) >> (8 * i));
    };
    put64(48, view->header.t_host_ns + offset);
    if ((view->header.flags & kV4l2BufFlagTimestampMask) == kV4l2BufFlagTimestampMonotonic)
        put64(16, view->header.timestamp_ns + offset);
    return Status::ok();
}

}  // namespace handscan::camera
