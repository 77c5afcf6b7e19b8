// V4L2 formats and buffer metadata as plain types: the fourcc codes, the capability, format,
// frame-interval and buffer structs of <linux/videodev2.h> mirrored field by field, and the flag
// values the camera codec reads (timestamp type and source). The camera's codecs (recorded buffer
// records, PNG payloads, pixel conversion, frame timing) use them without any transport header;
// only drivers/transport/src/v4l2_linux.cpp includes videodev2.h and checks these values against
// it.
#pragma once

#include <cstdint>
#include <string>

#include "handscan/core/time.hpp"

namespace handscan {

constexpr std::uint32_t fourcc(char a, char b, char c, char d) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(a)) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(b)) << 8) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(c)) << 16) |
           (static_cast<std::uint32_t>(static_cast<unsigned char>(d)) << 24);
}
constexpr std::uint32_t kFourccGrey = fourcc('G', 'R', 'E', 'Y');
constexpr std::uint32_t kFourccYuyv = fourcc('Y', 'U', 'Y', 'V');
constexpr std::uint32_t kFourccMjpeg = fourcc('M', 'J', 'P', 'G');
std::string fourccName(std::uint32_t code);  // "GREY"; non-printable bytes as '?'

// videodev2.h values (checked against the header by static_asserts in v4l2_linux.cpp).
constexpr std::uint32_t kV4l2CapVideoCapture = 0x00000001;
constexpr std::uint32_t kV4l2CapStreaming = 0x04000000;
constexpr std::uint32_t kV4l2CapDeviceCaps = 0x80000000;
constexpr std::uint32_t kV4l2BufFlagError = 0x00000040;
constexpr std::uint32_t kV4l2BufFlagTimestampMask = 0x0000E000;
constexpr std::uint32_t kV4l2BufFlagTimestampUnknown = 0x00000000;
constexpr std::uint32_t kV4l2BufFlagTimestampMonotonic = 0x00002000;
constexpr std::uint32_t kV4l2BufFlagTimestampCopy = 0x00004000;
constexpr std::uint32_t kV4l2BufFlagTstampSrcMask = 0x00070000;
constexpr std::uint32_t kV4l2BufFlagTstampSrcEof = 0x00000000;
constexpr std::uint32_t kV4l2BufFlagTstampSrcSoe = 0x00010000;
constexpr std::uint32_t kV4l2CidExposureAuto = 0x009A0901;  // V4L2_CID_EXPOSURE_AUTO
constexpr std::uint32_t kV4l2CidExposureAbsolute =
    0x009A0902;  // V4L2_CID_EXPOSURE_ABSOLUTE, 100 us units
constexpr std::int32_t kV4l2ExposureManual = 1;
constexpr std::int32_t kV4l2ExposureAperturePriority = 3;
constexpr std::uint32_t kV4l2FieldNone = 1;

struct V4l2Capability {
    std::string driver;
    std::string card;
    std::string bus_info;
    std::uint32_t capabilities = 0;
    std::uint32_t device_caps = 0;
    // The capabilities of this node (device_caps when the driver fills it, as V4L2 recommends).
    std::uint32_t nodeCaps() const {
        return (capabilities & kV4l2CapDeviceCaps) ? device_caps : capabilities;
    }
};

struct V4l2PixFormat {
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t pixelformat = 0;  // fourcc
    std::uint32_t field = kV4l2FieldNone;
    std::uint32_t bytesperline = 0;  // 0 for compressed formats
    std::uint32_t sizeimage = 0;
};

struct V4l2Fraction {
    std::uint32_t numerator = 0;
    std::uint32_t denominator = 0;
};

// struct v4l2_buffer for VIDEO_CAPTURE + MEMORY_MMAP, timestamp converted to ns.
struct V4l2Buffer {
    std::uint32_t index = 0;
    std::uint32_t bytesused = 0;
    std::uint32_t flags = 0;
    std::uint32_t field = kV4l2FieldNone;
    std::uint32_t sequence = 0;
    TimeNs timestamp_ns = 0;   // tv_sec * 1e9 + tv_usec * 1e3
    std::uint32_t offset = 0;  // m.offset: the mmap cookie
    std::uint32_t length = 0;  // buffer size
};

}  // namespace handscan
