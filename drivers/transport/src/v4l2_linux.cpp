// The only file that includes <linux/videodev2.h>: V4L2 ioctls, mmap and poll on /dev/videoN.
#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "handscan/transport/v4l2_device.hpp"

namespace handscan::transport {

static_assert(V4L2_CAP_VIDEO_CAPTURE == kV4l2CapVideoCapture &&
              V4L2_CAP_STREAMING == kV4l2CapStreaming &&
              V4L2_CAP_DEVICE_CAPS == kV4l2CapDeviceCaps);
static_assert(V4L2_BUF_FLAG_ERROR == kV4l2BufFlagError &&
              V4L2_BUF_FLAG_TIMESTAMP_MASK == kV4l2BufFlagTimestampMask &&
              V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC == kV4l2BufFlagTimestampMonotonic &&
              V4L2_BUF_FLAG_TIMESTAMP_COPY == kV4l2BufFlagTimestampCopy &&
              V4L2_BUF_FLAG_TSTAMP_SRC_MASK == kV4l2BufFlagTstampSrcMask &&
              V4L2_BUF_FLAG_TSTAMP_SRC_SOE == kV4l2BufFlagTstampSrcSoe &&
              V4L2_BUF_FLAG_TSTAMP_SRC_EOF == kV4l2BufFlagTstampSrcEof);
static_assert(V4L2_CID_EXPOSURE_AUTO == kV4l2CidExposureAuto &&
              V4L2_CID_EXPOSURE_ABSOLUTE == kV4l2CidExposureAbsolute &&
              V4L2_EXPOSURE_MANUAL == kV4l2ExposureManual &&
              V4L2_EXPOSURE_APERTURE_PRIORITY == kV4l2ExposureAperturePriority);
static_assert(V4L2_PIX_FMT_GREY == kFourccGrey && V4L2_PIX_FMT_YUYV == kFourccYuyv &&
              V4L2_PIX_FMT_MJPEG == kFourccMjpeg);
static_assert(V4L2_FIELD_NONE == kV4l2FieldNone);

namespace {

class LinuxV4l2Device final : public V4l2Device {
public:
    explicit LinuxV4l2Device(std::string path) : path_(std::move(path)) {}
    ~LinuxV4l2Device() override { close(); }

    Status open() override {
        close();
        fd_ = ::open(path_.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
        if (fd_ < 0) return fail(StatusCode::kNotFound, "open");
        return Status::ok();
    }
    void close() override {
        if (fd_ >= 0) ::close(fd_);
        fd_ = -1;
    }

    Result<V4l2Capability> queryCapability() override {
        v4l2_capability c{};
        if (xioctl(VIDIOC_QUERYCAP, &c) < 0)
            return fail(StatusCode::kDeviceError, "VIDIOC_QUERYCAP");
        V4l2Capability out;
        out.driver = reinterpret_cast<const char*>(c.driver);
        out.card = reinterpret_cast<const char*>(c.card);
        out.bus_info = reinterpret_cast<const char*>(c.bus_info);
        out.capabilities = c.capabilities;
        out.device_caps = c.device_caps;
        return out;
    }

    Result<V4l2PixFormat> setFormat(const V4l2PixFormat& f) override {
        v4l2_format fmt{};
        fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        fmt.fmt.pix.width = f.width;
        fmt.fmt.pix.height = f.height;
        fmt.fmt.pix.pixelformat = f.pixelformat;
        fmt.fmt.pix.field = f.field;
        if (xioctl(VIDIOC_S_FMT, &fmt) < 0) return fail(StatusCode::kDeviceError, "VIDIOC_S_FMT");
        return V4l2PixFormat{fmt.fmt.pix.width, fmt.fmt.pix.height,       fmt.fmt.pix.pixelformat,
                             fmt.fmt.pix.field, fmt.fmt.pix.bytesperline, fmt.fmt.pix.sizeimage};
    }

    Result<V4l2Fraction> setFrameInterval(V4l2Fraction t) override {
        v4l2_streamparm p{};
        p.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        p.parm.capture.timeperframe.numerator = t.numerator;
        p.parm.capture.timeperframe.denominator = t.denominator;
        if (xioctl(VIDIOC_S_PARM, &p) < 0) return fail(StatusCode::kDeviceError, "VIDIOC_S_PARM");
        return V4l2Fraction{p.parm.capture.timeperframe.numerator,
                            p.parm.capture.timeperframe.denominator};
    }

    Result<std::uint32_t> requestBuffers(std::uint32_t count) override {
        v4l2_requestbuffers r{};
        r.count = count;
        r.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        r.memory = V4L2_MEMORY_MMAP;
        if (xioctl(VIDIOC_REQBUFS, &r) < 0) return fail(StatusCode::kDeviceError, "VIDIOC_REQBUFS");
        return r.count;
    }

    Result<V4l2Buffer> queryBuffer(std::uint32_t index) override {
        v4l2_buffer b{};
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = index;
        if (xioctl(VIDIOC_QUERYBUF, &b) < 0)
            return fail(StatusCode::kDeviceError, "VIDIOC_QUERYBUF");
        return convert(b);
    }

    Result<std::span<std::uint8_t>> map(std::uint32_t offset, std::uint32_t length) override {
        void* p = ::mmap(nullptr, length, PROT_READ | PROT_WRITE, MAP_SHARED, fd_, offset);
        if (p == MAP_FAILED) return fail(StatusCode::kNoSpace, "mmap");
        return std::span<std::uint8_t>(static_cast<std::uint8_t*>(p), length);
    }
    void unmap(std::span<std::uint8_t> m) override { ::munmap(m.data(), m.size()); }

    Status queueBuffer(std::uint32_t index) override {
        v4l2_buffer b{};
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        b.index = index;
        if (xioctl(VIDIOC_QBUF, &b) < 0) return fail(StatusCode::kDeviceError, "VIDIOC_QBUF");
        return Status::ok();
    }

    Result<V4l2Buffer> dequeueBuffer() override {
        v4l2_buffer b{};
        b.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        b.memory = V4L2_MEMORY_MMAP;
        if (xioctl(VIDIOC_DQBUF, &b) < 0) {
            if (errno == EAGAIN) return Status(StatusCode::kTimeout, "no buffer ready");
            return fail(errno == ENODEV ? StatusCode::kDisconnected : StatusCode::kIoError,
                        "VIDIOC_DQBUF");
        }
        return convert(b);
    }

    Status streamOn() override { return stream(VIDIOC_STREAMON, "VIDIOC_STREAMON"); }
    Status streamOff() override { return stream(VIDIOC_STREAMOFF, "VIDIOC_STREAMOFF"); }

    Result<bool> waitReadable(TimeNs timeout) override {
        pollfd p{fd_, POLLIN, 0};
        const int ms = timeout <= 0 ? 0 : static_cast<int>((timeout + kNsPerMs - 1) / kNsPerMs);
        const int n = ::poll(&p, 1, ms);
        if (n < 0 && errno != EINTR) return fail(StatusCode::kIoError, "poll");
        if (n > 0 && (p.revents & (POLLERR | POLLHUP | POLLNVAL))) {
            return Status(StatusCode::kDisconnected,
                          describe() + ": device error or unplugged (poll revents " +
                              std::to_string(p.revents) + ")");
        }
        return n > 0;
    }

    Status setControl(std::uint32_t id, std::int32_t value) override {
        v4l2_control c{};
        c.id = id;
        c.value = value;
        if (xioctl(VIDIOC_S_CTRL, &c) < 0)
            return fail(StatusCode::kDeviceError, "VIDIOC_S_CTRL " + std::to_string(id));
        return Status::ok();
    }
    Result<std::int32_t> getControl(std::uint32_t id) override {
        v4l2_control c{};
        c.id = id;
        if (xioctl(VIDIOC_G_CTRL, &c) < 0)
            return fail(StatusCode::kDeviceError, "VIDIOC_G_CTRL " + std::to_string(id));
        return c.value;
    }

    std::string describe() const override { return "v4l2 " + path_; }

private:
    int xioctl(unsigned long request, void* arg) {
        int r;
        do {
            r = ::ioctl(fd_, request, arg);
        } while (r < 0 && errno == EINTR);
        return r;
    }
    Status fail(StatusCode code, const std::string& what) const {
        return {code, describe() + ": " + what + " failed: " + std::strerror(errno)};
    }
    Status stream(unsigned long request, const char* name) {
        int type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
        if (xioctl(request, &type) < 0) return fail(StatusCode::kDeviceError, name);
        return Status::ok();
    }
    static V4l2Buffer convert(const v4l2_buffer& b) {
        V4l2Buffer o;
        o.index = b.index;
        o.bytesused = b.bytesused;
        o.flags = b.flags;
        o.field = b.field;
        o.sequence = b.sequence;
        o.timestamp_ns = static_cast<TimeNs>(b.timestamp.tv_sec) * kNsPerSec +
                         static_cast<TimeNs>(b.timestamp.tv_usec) * kNsPerUs;
        o.offset = b.m.offset;
        o.length = b.length;
        return o;
    }

    std::string path_;
    int fd_ = -1;
};

}  // namespace

std::unique_ptr<V4l2Device> makeLinuxV4l2Device(std::string path) {
    return std::make_unique<LinuxV4l2Device>(std::move(path));
}

}  // namespace handscan::transport
