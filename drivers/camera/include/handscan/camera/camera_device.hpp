// A V4L2 capture camera over an injected transport::V4l2Device (real, fake or replay):
//   start(): QUERYCAP (capture + streaming) -> S_FMT in order of preference (GREY, YUYV, MJPEG;
//            the driver answers with what it can do) -> S_PARM frame interval -> exposure
//            (manual: EXPOSURE_AUTO = manual + EXPOSURE_ABSOLUTE; else aperture priority) ->
//            REQBUFS (the driver may grant fewer) -> QUERYBUF + mmap each -> QBUF all -> STREAMON.
//   grab():  poll -> DQBUF -> copy the bytes out -> re-QBUF at once (the driver never starves),
//            mid-exposure host time (frame_timing.hpp), dropped frames from sequence gaps,
//            buffers flagged ERROR or too short skipped and counted; the buffer goes to the
//            recording tap as a frame record coded like the simulator's (PNG for GREY / YUYV),
//            the coding done on the FrameRecordTap's thread, never on the capture thread.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handscan/camera/frame_record_tap.hpp"
#include "handscan/camera/frame_timing.hpp"
#include "handscan/core/raw_tap.hpp"
#include "handscan/core/samples.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace handscan::camera {

struct CameraConfig {
    std::uint32_t width = 640;
    std::uint32_t height = 480;
    std::vector<PixelFormat> formats = {PixelFormat::kGrey8, PixelFormat::kYuyv,
                                        PixelFormat::kMjpeg};  // preference
    transport::V4l2Fraction frame_interval{1, 30};
    std::uint32_t buffer_count = 4;
    std::optional<TimeNs> exposure;  // manual exposure time; nullopt = automatic
    TimeNs readout = 0;              // end of exposure to end of frame, for EOF timestamps
};

struct CameraStats {
    std::uint64_t frames = 0;
    std::uint64_t dropped = 0;          // sequence gaps
    std::uint64_t error_buffers = 0;    // V4L2_BUF_FLAG_ERROR or short payload
    std::uint64_t host_timestamps = 0;  // frames timed by the host (no monotonic device stamp)
    std::uint64_t restarts = 0;         // sequence went backwards
    std::uint64_t unrecorded = 0;       // frames the recording tap dropped (its coder fell behind)
};

class CameraDevice {
public:
    using Clock = std::function<TimeNs()>;
    CameraDevice(transport::V4l2Device& device, CameraConfig config, RawTap* tap = nullptr,
                 Clock clock = monotonicNow);
    ~CameraDevice();
    CameraDevice(const CameraDevice&) = delete;
    CameraDevice& operator=(const CameraDevice&) = delete;

    [[nodiscard]] Status start();
    // One frame, nullopt when none arrived within `timeout` (or the buffer was bad and skipped).
    [[nodiscard]] Result<std::optional<Image>> grab(TimeNs timeout);
    [[nodiscard]] Status setExposure(TimeNs exposure);
    [[nodiscard]] Status stop();

    const transport::V4l2PixFormat& format() const { return format_; }
    transport::V4l2Fraction frameInterval() const { return interval_; }
    std::size_t bufferCount() const { return buffers_.size(); }
    const CameraStats& stats() const { return stats_; }
    TimestampSource lastTimestampSource() const { return last_source_; }

private:
    Status negotiateFormat();
    Status setupBuffers();
    void release();
    Status fail(Status s);

    transport::V4l2Device& dev_;
    CameraConfig cfg_;
    std::unique_ptr<FrameRecordTap> record_tap_;  // when constructed with a tap
    Clock clock_;
    transport::V4l2PixFormat format_;
    PixelFormat pixel_format_ = PixelFormat::kGrey8;
    transport::V4l2Fraction interval_;
    std::vector<std::span<std::uint8_t>> buffers_;
    bool streaming_ = false;
    bool open_ = false;
    bool auto_exposure_ = true;
    TimeNs exposure_ = 0;
    SequenceTracker sequence_;
    CameraStats stats_;
    TimestampSource last_source_ = TimestampSource::kEndOfFrame;
};

}  // namespace handscan::camera
