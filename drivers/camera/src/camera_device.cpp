#include "handscan/camera/camera_device.hpp"

#include <cmath>
#include <cstdio>

#include "handscan/camera/frame_record.hpp"
#include "handscan/camera/image_convert.hpp"
#include "handscan/core/log.hpp"

namespace handscan::camera {
namespace {

constexpr TimeNs kExposureUnit = 100 * kNsPerUs;  // V4L2_CID_EXPOSURE_ABSOLUTE counts 100 us

int bytesPerPixel(PixelFormat f) {
    return f == PixelFormat::kYuyv ? 2 : f == PixelFormat::kGrey8 ? 1 : 0;
}

std::string hex32(std::uint32_t v) {
    char b[16];
    std::snprintf(b, sizeof b, "0x%08X", static_cast<unsigned>(v));
    return b;
}

}  // namespace

CameraDevice::CameraDevice(transport::V4l2Device& device, CameraConfig config, RawTap* tap,
                           Clock clock)
    : dev_(device),
      cfg_(std::move(config)),
      record_tap_(tap != nullptr ? std::make_unique<FrameRecordTap>(*tap) : nullptr),
      clock_(std::move(clock)) {}

CameraDevice::~CameraDevice() { release(); }

void CameraDevice::release() {
    if (streaming_) (void)dev_.streamOff();
    streaming_ = false;
    for (auto& b : buffers_) dev_.unmap(b);
    if (!buffers_.empty()) (void)dev_.requestBuffers(0);
    buffers_.clear();
    if (open_) dev_.close();
    open_ = false;
}

Status CameraDevice::fail(Status s) {
    release();
    return s;
}

Status CameraDevice::negotiateFormat() {
    std::string offered;
    for (PixelFormat want : cfg_.formats) {
        transport::V4l2PixFormat req;
        req.width = cfg_.width;
        req.height = cfg_.height;
        req.pixelformat = fourccFromPixelFormat(want);
        auto got = dev_.setFormat(req);
        if (!got) return got.status();
        if (got->pixelformat != req.pixelformat) {
            offered = transport::fourccName(got->pixelformat);
            continue;  // the driver substituted a format it has: try the next preference
        }
        if (got->width != cfg_.width || got->height != cfg_.height) {
            log().warn("camera {}: asked for {}x{}, the driver set {}x{}", dev_.describe(),
                       cfg_.width, cfg_.height, got->width, got->height);
        }
        const int bpp = bytesPerPixel(want);
        if (bpp > 0) {
            if (got->bytesperline == 0)
                got->bytesperline = got->width * static_cast<std::uint32_t>(bpp);
            if (got->bytesperline < got->width * static_cast<std::uint32_t>(bpp)) {
                return {StatusCode::kDeviceError,
                        dev_.describe() + ": driver reports " + std::to_string(got->bytesperline) +
                            " bytes per line for " + std::to_string(got->width) + " pixels"};
            }
        }
        format_ = *got;
        pixel_format_ = want;
        return Status::ok();
    }
    std::string wanted;
    for (PixelFormat f : cfg_.formats)
        wanted += std::string(wanted.empty() ? "" : ", ") + toString(f);
    return {StatusCode::kUnsupported,
            dev_.describe() + ": offers none of " + wanted + " at " + std::to_string(cfg_.width) +
                "x" + std::to_string(cfg_.height) + " (driver answered " + offered +
                "); check `v4l2-ctl --list-formats-ext` and camera.formats"};
}

Status CameraDevice::setupBuffers() {
    auto granted = dev_.requestBuffers(cfg_.buffer_count);
    if (!granted) return granted.status();
    if (*granted < 2) {
        return {StatusCode::kNoSpace, dev_.describe() + ": driver granted " +
                                          std::to_string(*granted) +
                                          " buffers, streaming needs at least 2 (out of memory?)"};
    }
    for (std::uint32_t i = 0; i < *granted; ++i) {
        auto b = dev_.queryBuffer(i);
        if (!b) return b.status();
        auto m = dev_.map(b->offset, b->length);
        if (!m) return m.status();
        buffers_.push_back(*m);
    }
    for (std::uint32_t i = 0; i < *granted; ++i) {
        if (Status s = dev_.queueBuffer(i); !s) return s;
    }
    return Status::ok();
}

Status CameraDevice::start() {
    release();
    stats_ = {};
    sequence_.reset();
    if (Status s = dev_.open(); !s) return s;
    open_ = true;
    auto cap = dev_.queryCapability();
    if (!cap) return fail(cap.status());
    const std::uint32_t caps = cap->nodeCaps();
    if (!(caps & transport::kV4l2CapVideoCapture) || !(caps & transport::kV4l2CapStreaming)) {
        return fail({StatusCode::kUnsupported,
                     dev_.describe() + " (" + cap->card + ", driver " + cap->driver +
                         "): not a video capture device with streaming I/O (caps " + hex32(caps) +
                         ")"});
    }
    if (Status s = negotiateFormat(); !s) return fail(s);
    auto interval = dev_.setFrameInterval(cfg_.frame_interval);
    if (!interval) return fail(interval.status());
    interval_ = *interval;
    if (interval_.numerator * cfg_.frame_interval.denominator !=
        cfg_.frame_interval.numerator * interval_.denominator) {
        log().warn("camera {}: asked for {}/{} s per frame, the driver set {}/{}", dev_.describe(),
                   cfg_.frame_interval.numerator, cfg_.frame_interval.denominator,
                   interval_.numerator, interval_.denominator);
    }
    if (cfg_.exposure) {
        if (Status s = setExposure(*cfg_.exposure); !s) return fail(s);
    } else {
        auto_exposure_ = true;
        if (Status s = dev_.setControl(transport::kV4l2CidExposureAuto,
                                       transport::kV4l2ExposureAperturePriority);
            !s) {
            log().warn("camera {}: automatic exposure not available ({})", dev_.describe(),
                       s.message());
        }
    }
    if (Status s = setupBuffers(); !s) return fail(s);
    if (Status s = dev_.streamOn(); !s) return fail(s);
    streaming_ = true;
    return Status::ok();
}

Status CameraDevice::setExposure(TimeNs exposure) {
    if (exposure <= 0) return {StatusCode::kInvalidArgument, "camera: exposure must be positive"};
    const auto units =
        static_cast<std::int32_t>(std::llround(static_cast<double>(exposure) / kExposureUnit));
    if (Status s = dev_.setControl(transport::kV4l2CidExposureAuto, transport::kV4l2ExposureManual);
        !s)
        return s;
    if (Status s = dev_.setControl(transport::kV4l2CidExposureAbsolute, units < 1 ? 1 : units); !s)
        return s;
    auto_exposure_ = false;
    exposure_ = static_cast<TimeNs>(units < 1 ? 1 : units) * kExposureUnit;
    return Status::ok();
}

Result<std::optional<Image>> CameraDevice::grab(TimeNs timeout) {
    if (!streaming_) return Status(StatusCode::kInvalidArgument, "camera: grab() before start()");
    auto ready = dev_.waitReadable(timeout);
    if (!ready) return ready.status();
    if (!*ready) return std::optional<Image>();
    auto buf = dev_.dequeueBuffer();
    if (!buf) {
        if (buf.status().code() == StatusCode::kTimeout) return std::optional<Image>();
        return buf.status();
    }
    const TimeNs t_dequeue = clock_();
    if (buf->index >= buffers_.size()) {
        return Status(StatusCode::kDeviceError, dev_.describe() + ": DQBUF returned buffer " +
                                                    std::to_string(buf->index) + " of " +
                                                    std::to_string(buffers_.size()));
    }
    const auto requeue = [&]() -> Status { return dev_.queueBuffer(buf->index); };
    sequence_.update(buf->sequence);
    stats_.dropped = sequence_.dropped();
    stats_.restarts = sequence_.restarts();

    const std::span<const std::uint8_t> mem = buffers_[buf->index];
    const int bpp = bytesPerPixel(pixel_format_);
    const std::uint64_t need =
        bpp > 0 ? static_cast<std::uint64_t>(format_.bytesperline) * (format_.height - 1) +
                      format_.width * static_cast<std::uint64_t>(bpp)
                : 1;
    if ((buf->flags & transport::kV4l2BufFlagError) || buf->bytesused > mem.size() ||
        buf->bytesused < need) {
        ++stats_.error_buffers;
        log().warn("camera {}: frame {} skipped ({}; {} bytes, need {})", dev_.describe(),
                   buf->sequence,
                   (buf->flags & transport::kV4l2BufFlagError) ? "driver flagged ERROR"
                                                               : "bad payload size",
                   buf->bytesused, need);
        if (Status s = requeue(); !s) return s;
        return std::optional<Image>();
    }
    if (auto_exposure_) {
        auto e = dev_.getControl(transport::kV4l2CidExposureAbsolute);
        if (e) exposure_ = static_cast<TimeNs>(*e) * kExposureUnit;
    }
    const FrameTime ft =
        midExposureTime(buf->flags, buf->timestamp_ns, exposure_, cfg_.readout, t_dequeue);
    last_source_ = ft.source;
    if (ft.source == TimestampSource::kHostDequeue) ++stats_.host_timestamps;

    Image img;
    img.t_host = ft.t_mid_exposure;
    img.sequence = buf->sequence;
    img.format = pixel_format_;
    img.width = static_cast<int>(format_.width);
    img.height = static_cast<int>(format_.height);
    img.stride_bytes = bpp > 0 ? static_cast<int>(format_.bytesperline) : 0;
    img.exposure_ns = exposure_;
    img.data.assign(mem.begin(), mem.begin() + buf->bytesused);
    if (Status s = requeue(); !s) return s;  // hand the buffer back before anything slow
    ++stats_.frames;

    if (record_tap_) {
        FrameRecordHeader h;
        h.sequence = buf->sequence;
        h.flags = buf->flags;
        h.timestamp_ns = buf->timestamp_ns;
        h.fourcc = format_.pixelformat;
        h.width = format_.width;
        h.height = format_.height;
        h.stride = bpp > 0 ? format_.bytesperline : 0;
        h.exposure_us = static_cast<std::uint32_t>(exposure_ / kNsPerUs);
        h.t_host_ns = img.t_host;
        record_tap_->submit(t_dequeue, h, img.data);  // queued: coded on the tap's thread
        stats_.unrecorded = record_tap_->dropped();
    }
    return std::optional<Image>(std::move(img));
}

Status CameraDevice::stop() {
    Status first;
    if (streaming_) first = dev_.streamOff();
    streaming_ = false;
    release();
    return first;
}

}  // namespace handscan::camera
