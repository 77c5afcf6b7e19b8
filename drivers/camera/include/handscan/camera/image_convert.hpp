// Pixel conversions of delivered frames: YUYV (4:2:2, BT.601) to grey or BGR, MJPEG decoded with
// libjpeg-turbo (UVC cameras' MJPEG frames often omit the Huffman tables; libjpeg-turbo supplies
// the standard ones). The output is packed (stride = width * channels) with the input's time,
// sequence and exposure.
#pragma once

#include <cstdint>
#include <optional>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"

namespace handscan::camera {

std::optional<PixelFormat> pixelFormatFromFourcc(std::uint32_t fourcc);
std::uint32_t fourccFromPixelFormat(PixelFormat format);
const char* toString(PixelFormat format);

[[nodiscard]] Result<Image> toGrey(const Image& in);
[[nodiscard]] Result<Image> toBgr(const Image& in);

}  // namespace handscan::camera
