// A thin interface over the V4L2 calls a capture driver makes (ioctl QUERYCAP, S_FMT, S_PARM,
// REQBUFS, QUERYBUF, QBUF, DQBUF, STREAMON/OFF, S_CTRL/G_CTRL, mmap, poll), with plain mirror
// structs so that only the Linux implementation (src/v4l2_linux.cpp) includes <linux/videodev2.h>.
// The camera driver's buffer handling runs unchanged over the real device, a fake device layer
// in tests, or a replay of recorded buffers.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/core/v4l2_types.hpp"

namespace handscan::transport {

// The plain V4L2 types (handscan/core/v4l2_types.hpp) under their transport names, for the device
// code written against them.
using handscan::fourcc;
using handscan::fourccName;
using handscan::kFourccGrey;
using handscan::kFourccMjpeg;
using handscan::kFourccYuyv;
using handscan::kV4l2BufFlagError;
using handscan::kV4l2BufFlagTimestampCopy;
using handscan::kV4l2BufFlagTimestampMask;
using handscan::kV4l2BufFlagTimestampMonotonic;
using handscan::kV4l2BufFlagTimestampUnknown;
using handscan::kV4l2BufFlagTstampSrcEof;
using handscan::kV4l2BufFlagTstampSrcMask;
using handscan::kV4l2BufFlagTstampSrcSoe;
using handscan::kV4l2CapDeviceCaps;
using handscan::kV4l2CapStreaming;
using handscan::kV4l2CapVideoCapture;
using handscan::kV4l2CidExposureAbsolute;
using handscan::kV4l2CidExposureAuto;
using handscan::kV4l2ExposureAperturePriority;
using handscan::kV4l2ExposureManual;
using handscan::kV4l2FieldNone;
using handscan::V4l2Buffer;
using handscan::V4l2Capability;
using handscan::V4l2Fraction;
using handscan::V4l2PixFormat;

class V4l2Device {
public:
    virtual ~V4l2Device() = default;
    virtual Status open() = 0;  // O_RDWR | O_NONBLOCK
    virtual void close() = 0;
    virtual Result<V4l2Capability> queryCapability() = 0;  // VIDIOC_QUERYCAP
    virtual Result<V4l2PixFormat> setFormat(
        const V4l2PixFormat& f) = 0;  // VIDIOC_S_FMT (driver adjusts)
    virtual Result<V4l2Fraction> setFrameInterval(
        V4l2Fraction t) = 0;  // VIDIOC_S_PARM timeperframe
    virtual Result<std::uint32_t> requestBuffers(std::uint32_t count) = 0;  // VIDIOC_REQBUFS, MMAP
    virtual Result<V4l2Buffer> queryBuffer(std::uint32_t index) = 0;        // VIDIOC_QUERYBUF
    virtual Result<std::span<std::uint8_t>> map(std::uint32_t offset,
                                                std::uint32_t length) = 0;  // mmap
    virtual void unmap(std::span<std::uint8_t> mapping) = 0;                // munmap
    virtual Status queueBuffer(std::uint32_t index) = 0;                    // VIDIOC_QBUF
    virtual Result<V4l2Buffer> dequeueBuffer() = 0;  // VIDIOC_DQBUF; kTimeout on EAGAIN
    virtual Status streamOn() = 0;
    virtual Status streamOff() = 0;
    virtual Result<bool> waitReadable(TimeNs timeout) = 0;                // poll(POLLIN)
    virtual Status setControl(std::uint32_t id, std::int32_t value) = 0;  // VIDIOC_S_CTRL
    virtual Result<std::int32_t> getControl(std::uint32_t id) = 0;        // VIDIOC_G_CTRL
    virtual std::string describe() const = 0;                             // "v4l2 /dev/video0"
};

// The Linux implementation (V4L2 ioctls on a /dev/videoN node).
std::unique_ptr<V4l2Device> makeLinuxV4l2Device(std::string path);

}  // namespace handscan::transport
