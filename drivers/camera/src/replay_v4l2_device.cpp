#include "handscan/camera/replay_v4l2_device.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "handscan/camera/timed_frame_file.hpp"

namespace handscan::camera {

using transport::V4l2Buffer;
using transport::V4l2Fraction;
using transport::V4l2PixFormat;

ReplayV4l2Device::ReplayV4l2Device(ReplayDeviceConfig config) : cfg_(std::move(config)) {
    if (!cfg_.formats.empty()) format_ = cfg_.formats.front();
    if (cfg_.controls) {
        controls_[transport::kV4l2CidExposureAuto] = transport::kV4l2ExposureAperturePriority;
        controls_[transport::kV4l2CidExposureAbsolute] = 100;
    }
}

void ReplayV4l2Device::addFrame(const FrameRecordHeader& header, std::vector<std::uint8_t> payload,
                                TimeNs due) {
    frames_.push_back({header, std::move(payload), due});
}

Result<const ReplayFrame*> ReplayV4l2Device::next() {
    while (true) {
        if (frames_.empty() && feed_) {
            auto f = feed_();
            if (!f) return f.status();
            if (*f) frames_.push_back(std::move(**f));
        }
        if (frames_.empty()) return static_cast<const ReplayFrame*>(nullptr);
        // A paced camera exposes only while streaming: earlier frames were never captured.
        if (!cfg_.clock || frames_.front().due >= stream_on_) return &frames_.front();
        frames_.pop_front();
    }
}

Result<std::size_t> ReplayV4l2Device::addRecords(std::span<const std::uint8_t> records) {
    std::size_t n = 0;
    while (!records.empty()) {
        auto r = decodeFrameRecord(records);
        if (!r) return r.status();
        addFrame(r->header, std::vector<std::uint8_t>(r->payload.begin(), r->payload.end()));
        records = records.subspan(r->record_size);
        ++n;
    }
    return n;
}

std::int32_t ReplayV4l2Device::control(std::uint32_t id) const {
    auto it = controls_.find(id);
    return it == controls_.end() ? 0 : it->second;
}

// mmap cookies are page-aligned, one region per buffer (a page even for an empty buffer).
std::uint32_t ReplayV4l2Device::cookieStride() const {
    return std::max<std::uint32_t>(kPageSize,
                                   (format_.sizeimage + kPageSize - 1) / kPageSize * kPageSize);
}

Status ReplayV4l2Device::violation(const std::string& what) {
    violations_.push_back(what);
    return {StatusCode::kDeviceError, describe() + ": " + what};
}

Status ReplayV4l2Device::open() {
    calls_.push_back("open");
    if (!cfg_.open_error.empty()) return {StatusCode::kNotFound, cfg_.open_error};
    if (open_) return violation("open twice");
    open_ = true;
    return Status::ok();
}

void ReplayV4l2Device::close() {
    calls_.push_back("close");
    if (std::any_of(mapped_.begin(), mapped_.end(), [](bool m) { return m; }))
        violations_.push_back("close with buffers still mapped");
    open_ = false;
    streaming_ = false;
}

Result<transport::V4l2Capability> ReplayV4l2Device::queryCapability() {
    calls_.push_back("QUERYCAP");
    if (!open_) return violation("QUERYCAP on a closed device");
    transport::V4l2Capability c;
    c.driver = "replay";
    c.card = cfg_.card;
    c.bus_info = "platform:replay";
    c.capabilities = cfg_.capabilities | transport::kV4l2CapDeviceCaps;
    c.device_caps = cfg_.capabilities;
    return c;
}

Result<V4l2PixFormat> ReplayV4l2Device::setFormat(const V4l2PixFormat& f) {
    calls_.push_back("S_FMT " + std::to_string(f.width) + "x" + std::to_string(f.height) + " " +
                     transport::fourccName(f.pixelformat));
    if (!open_) return violation("S_FMT on a closed device");
    if (!buffers_.empty()) return violation("S_FMT while buffers are allocated (EBUSY)");
    if (cfg_.formats.empty()) return violation("no formats configured");
    // Like a driver: the closest supported size in the requested format, else the first format.
    const V4l2PixFormat* best = nullptr;
    for (const auto& s : cfg_.formats) {
        if (s.pixelformat != f.pixelformat) continue;
        const auto cost = [&](const V4l2PixFormat& c) {
            return std::abs(static_cast<long>(c.width) - static_cast<long>(f.width)) +
                   std::abs(static_cast<long>(c.height) - static_cast<long>(f.height));
        };
        if (best == nullptr || cost(s) < cost(*best)) best = &s;
    }
    format_ = best != nullptr ? *best : cfg_.formats.front();
    return format_;
}

Result<V4l2Fraction> ReplayV4l2Device::setFrameInterval(V4l2Fraction t) {
    calls_.push_back("S_PARM " + std::to_string(t.numerator) + "/" + std::to_string(t.denominator));
    if (!open_) return violation("S_PARM on a closed device");
    if (t.numerator == 0 || t.denominator == 0) return cfg_.frame_intervals.front();
    const double want = static_cast<double>(t.numerator) / t.denominator;
    V4l2Fraction best = cfg_.frame_intervals.front();
    for (const auto& c : cfg_.frame_intervals) {
        if (std::abs(static_cast<double>(c.numerator) / c.denominator - want) <
            std::abs(static_cast<double>(best.numerator) / best.denominator - want)) {
            best = c;
        }
    }
    return best;
}

Result<std::uint32_t> ReplayV4l2Device::requestBuffers(std::uint32_t count) {
    calls_.push_back("REQBUFS " + std::to_string(count));
    if (!open_) return violation("REQBUFS on a closed device");
    if (streaming_) return violation("REQBUFS while streaming (EBUSY)");
    if (std::any_of(mapped_.begin(), mapped_.end(), [](bool m) { return m; }))
        return violation("REQBUFS while buffers are mapped (EBUSY)");
    if (count == 0) {
        buffers_.clear();
        queued_.clear();
        mapped_.clear();
        queue_.clear();
        return 0u;
    }
    const std::uint32_t n = std::clamp(count, cfg_.min_buffers, cfg_.max_buffers);
    const std::uint32_t size = format_.sizeimage;
    buffers_.assign(n, std::vector<std::uint8_t>(size));
    queued_.assign(n, false);
    mapped_.assign(n, false);
    queue_.clear();
    return n;
}

Result<V4l2Buffer> ReplayV4l2Device::queryBuffer(std::uint32_t index) {
    calls_.push_back("QUERYBUF " + std::to_string(index));
    if (index >= buffers_.size())
        return violation("QUERYBUF index " + std::to_string(index) + " out of range (EINVAL)");
    V4l2Buffer b;
    b.index = index;
    const std::uint32_t stride = cookieStride();
    b.offset = index * stride;
    b.length = static_cast<std::uint32_t>(buffers_[index].size());
    return b;
}

Result<std::span<std::uint8_t>> ReplayV4l2Device::map(std::uint32_t offset, std::uint32_t length) {
    calls_.push_back("mmap " + std::to_string(offset) + " " + std::to_string(length));
    const std::uint32_t stride = cookieStride();
    const std::uint32_t index = offset / stride;
    if (offset % stride != 0 || index >= buffers_.size())
        return violation("mmap of unknown offset " + std::to_string(offset));
    if (length != buffers_[index].size())
        return violation("mmap length " + std::to_string(length) + " != buffer length");
    mapped_[index] = true;
    return std::span<std::uint8_t>(buffers_[index]);
}

void ReplayV4l2Device::unmap(std::span<std::uint8_t> m) {
    calls_.push_back("munmap");
    // Match a mapped buffer (empty buffers all share a null address).
    for (std::size_t i = 0; i < buffers_.size(); ++i) {
        if (buffers_[i].data() == m.data() && mapped_[i]) {
            mapped_[i] = false;
            return;
        }
    }
    violations_.push_back("munmap of memory that is not a mapped buffer");
}

Status ReplayV4l2Device::queueBuffer(std::uint32_t index) {
    calls_.push_back("QBUF " + std::to_string(index));
    if (index >= buffers_.size())
        return violation("QBUF index " + std::to_string(index) + " out of range (EINVAL)");
    if (queued_[index])
        return violation("QBUF of buffer " + std::to_string(index) + " already queued (EINVAL)");
    if (!mapped_[index]) return violation("QBUF of unmapped buffer " + std::to_string(index));
    queued_[index] = true;
    queue_.push_back(index);
    return Status::ok();
}

Status ReplayV4l2Device::streamOn() {
    calls_.push_back("STREAMON");
    if (buffers_.empty()) return violation("STREAMON without buffers (EINVAL)");
    if (queue_.empty())
        violations_.push_back("STREAMON with no buffer queued (the driver would starve)");
    streaming_ = true;
    if (cfg_.clock) stream_on_ = cfg_.clock();
    return Status::ok();
}

Status ReplayV4l2Device::streamOff() {
    calls_.push_back("STREAMOFF");
    streaming_ = false;
    // STREAMOFF returns every buffer to the application.
    std::fill(queued_.begin(), queued_.end(), false);
    queue_.clear();
    return Status::ok();
}

Result<bool> ReplayV4l2Device::waitReadable(TimeNs timeout) {
    calls_.push_back("poll");
    if (!streaming_) return violation("poll while not streaming");
    auto f = next();
    if (!f) return f.status();
    if (*f == nullptr && cfg_.disconnect_at_end)
        return Status(StatusCode::kDisconnected, describe() + ": device unplugged (POLLERR)");
    if (cfg_.clock) {
        // poll() blocks until the next buffer is done or the timeout passes.
        const TimeNs now = cfg_.clock();
        const TimeNs until = *f != nullptr ? std::min((*f)->due, now + timeout) : now + timeout;
        if (until > now) std::this_thread::sleep_for(std::chrono::nanoseconds(until - now));
    }
    return *f != nullptr && due(**f) && !queue_.empty();
}

Result<V4l2Buffer> ReplayV4l2Device::dequeueBuffer() {
    calls_.push_back("DQBUF");
    if (!streaming_) return violation("DQBUF while not streaming (EINVAL)");
    auto next_frame = next();
    if (!next_frame) return next_frame.status();
    if (*next_frame == nullptr) {
        if (cfg_.disconnect_at_end)
            return Status(StatusCode::kDisconnected,
                          describe() + ": VIDIOC_DQBUF failed: No such device");
        return Status(StatusCode::kTimeout, "no buffer ready");
    }
    if (!due(**next_frame)) return Status(StatusCode::kTimeout, "no buffer ready");
    if (queue_.empty()) return Status(StatusCode::kTimeout, "no buffer queued");
    ReplayFrame f = std::move(frames_.front());
    frames_.pop_front();
    const std::uint32_t index = queue_.front();
    queue_.pop_front();
    queued_[index] = false;
    auto& mem = buffers_[index];
    V4l2Buffer b;
    b.index = index;
    b.sequence = f.header.sequence;
    b.flags = f.header.flags;
    b.timestamp_ns = f.header.timestamp_ns;
    b.length = static_cast<std::uint32_t>(mem.size());
    const std::size_t n = std::min(mem.size(), f.payload.size());
    if (n > 0) std::memcpy(mem.data(), f.payload.data(), n);
    b.bytesused = static_cast<std::uint32_t>(n);
    if (n < f.payload.size() || f.header.fourcc != format_.pixelformat ||
        f.header.width != format_.width || f.header.height != format_.height) {
        b.flags |= transport::kV4l2BufFlagError;  // a recorded frame that does not fit this format
    }
    if (cfg_.controls && f.header.exposure_us > 0 &&
        control(transport::kV4l2CidExposureAuto) != transport::kV4l2ExposureManual) {
        controls_[transport::kV4l2CidExposureAbsolute] =
            static_cast<std::int32_t>(f.header.exposure_us / 100);
    }
    return b;
}

Status ReplayV4l2Device::setControl(std::uint32_t id, std::int32_t value) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "S_CTRL 0x%08X %d", static_cast<unsigned>(id),
                  static_cast<int>(value));
    calls_.push_back(buf);
    if (!open_) return violation("S_CTRL on a closed device");
    if (!controls_.count(id))
        return {StatusCode::kUnsupported, describe() + ": control not supported (EINVAL)"};
    controls_[id] = value;
    return Status::ok();
}

Result<std::int32_t> ReplayV4l2Device::getControl(std::uint32_t id) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "G_CTRL 0x%08X", static_cast<unsigned>(id));
    calls_.push_back(buf);
    if (!controls_.count(id))
        return Status(StatusCode::kUnsupported, describe() + ": control not supported (EINVAL)");
    return controls_[id];
}

namespace {

// A frame of the file as the device delivers it (payload decoded, PNG or not).
Result<ReplayFrame> replayFrame(const TimedFrameRecord& e, const std::string& path) {
    auto view = decodeFrameRecord(e.record);
    if (!view) return Status(view.status().code(), path + ": " + view.status().message());
    return ReplayFrame{
        view->header, std::vector<std::uint8_t>(view->payload.begin(), view->payload.end()), e.due};
}

}  // namespace

std::unique_ptr<transport::V4l2Device> openHostClockReplay(const std::string& path,
                                                           transport::V4l2Fraction interval) {
    ReplayDeviceConfig c;
    c.path = path;
    c.card = "handscan hil camera";
    c.clock = monotonicNow;
    if (interval.numerator != 0 && interval.denominator != 0) c.frame_intervals = {interval};
    auto reader = TimedFrameFileReader::open(path);
    Result<std::optional<TimedFrameRecord>> first =
        reader ? reader->next() : Result<std::optional<TimedFrameRecord>>(reader.status());
    std::optional<ReplayFrame> frame;
    if (first && *first) {
        auto f = replayFrame(**first, path);
        if (f)
            frame = std::move(*f);
        else
            first = f.status();
    }
    if (!first) {
        c.open_error = first.status().message();
    } else if (!frame) {
        c.open_error = path + ": no camera frames to play";
    } else {
        // The recorded camera's one format, as its driver offered it (MJPEG buffers sized as
        // UVC sizes them: two bytes a pixel).
        const FrameRecordHeader& h = frame->header;
        const std::uint32_t size = h.stride != 0 ? h.stride * h.height : 2 * h.width * h.height;
        c.formats = {{h.width, h.height, h.fourcc, transport::kV4l2FieldNone, h.stride,
                      std::max(size, h.bytesused)}};
    }
    auto device = std::make_unique<ReplayV4l2Device>(std::move(c));
    if (!frame) return device;
    device->addFrame(frame->header, std::move(frame->payload), frame->due);
    auto shared = std::make_shared<TimedFrameFileReader>(std::move(*reader));
    device->setFeed([shared]() -> Result<std::optional<ReplayFrame>> {
        auto e = shared->next();
        if (!e) return e.status();
        if (!*e) return std::optional<ReplayFrame>();
        auto f = replayFrame(**e, shared->path());
        if (!f) return f.status();
        return std::optional<ReplayFrame>(std::move(*f));
    });
    return device;
}

}  // namespace handscan::camera
