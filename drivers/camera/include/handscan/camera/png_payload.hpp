// Lossless storage of an uncompressed V4L2 buffer as a PNG file (libpng), so that recordings of
// raw camera streams stay small without changing a single byte the driver sees: the PNG decodes
// back to exactly the buffer's bytes, line padding included.
//
//   GREY: an 8-bit greyscale PNG of (stride x height) pixels, one pixel per buffer byte.
//   YUYV: an 8-bit grey+alpha PNG of (stride / 2 x height) pixels: Y in grey, U or V in alpha,
//         so the PNG filters predict luma from luma and chroma from chroma.
// Only buffers of exactly stride * height bytes are stored this way (canStorePng()); anything
// else (a short last line, compressed formats) is stored as it is.
//
// The encoder uses a fixed PNG filter and zlib's Huffman-only strategy: camera images are mostly
// sensor noise around a smooth signal, where LZ77 matches are rare and a per-line filter search
// costs more time than it saves bytes (see tests/bench/camera).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "handscan/camera/frame_record.hpp"
#include "handscan/core/status.hpp"

namespace handscan::camera {

// Whether a buffer with this header can be stored as PNG (uncompressed format, whole lines).
bool canStorePng(const FrameRecordHeader& header);
// The PNG file of `buffer` (header.bytesused bytes, canStorePng(header) must hold).
[[nodiscard]] Result<std::vector<std::uint8_t>> encodePngPayload(
    const FrameRecordHeader& header, std::span<const std::uint8_t> buffer);
// Decodes a PNG payload back into the buffer's bytes; the PNG's size and pixel type must be the
// ones the header implies (kProtocolError otherwise, naming what differs).
[[nodiscard]] Status decodePngPayload(const FrameRecordHeader& header,
                                      std::span<const std::uint8_t> png,
                                      std::vector<std::uint8_t>& buffer);

}  // namespace handscan::camera
