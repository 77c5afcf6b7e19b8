// A V4L2 device without a kernel: it answers the ioctl sequence like a capture driver (format
// substitution, buffer counts, mmap cookies, queue ownership, EAGAIN when empty) and fills its
// buffers from frame records (recorded /camera/* messages or synthetic frames). Used as the
// fake device layer in tests (every call is logged and checked against the V4L2 rules; misuse
// is an error the test sees in violations()) and as the replay source of recordings, so that
// replayed frames go through the driver's real buffer handling. Paced (a `clock` in the config),
// it delivers each frame only once the clock reaches the frame's due time, as a camera hands over
// a buffer when its readout ends, and frames due before STREAMON are never captured; unpaced,
// every frame is ready at once.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "handscan/camera/frame_record.hpp"
#include "handscan/transport/v4l2_device.hpp"

namespace handscan::camera {

struct ReplayDeviceConfig {
    std::string path = "/dev/video-replay";
    std::string card = "handscan replay";
    std::uint32_t capabilities = transport::kV4l2CapVideoCapture | transport::kV4l2CapStreaming;
    // Formats the "driver" supports; S_FMT of anything else answers with the first one.
    std::vector<transport::V4l2PixFormat> formats;
    std::uint32_t max_buffers = 8;
    std::uint32_t min_buffers = 2;
    std::vector<transport::V4l2Fraction> frame_intervals = {{1, 30}};
    bool controls = true;            // exposure controls exist
    bool disconnect_at_end = false;  // after the last frame: ENODEV (unplugged) instead of EAGAIN
    std::function<TimeNs()> clock;   // set: paced on this clock (see above)
    std::string open_error;          // set: open() fails with this (a source that cannot be read)
};

// One frame to deliver: the V4L2 buffer fields, the buffer's bytes, when it is due (paced).
struct ReplayFrame {
    FrameRecordHeader header;
    std::vector<std::uint8_t> payload;
    TimeNs due = 0;
};
// Frames pulled one at a time when the device runs out (a file read as it plays instead of held
// in memory); nullopt at the end, an error for a source that is not frames.
using ReplayFrameFeed = std::function<Result<std::optional<ReplayFrame>>()>;

class ReplayV4l2Device final : public transport::V4l2Device {
public:
    explicit ReplayV4l2Device(ReplayDeviceConfig config);

    // Frames to deliver, in order (header fields become the v4l2_buffer fields); `due` matters
    // only when paced.
    void addFrame(const FrameRecordHeader& header, std::vector<std::uint8_t> payload,
                  TimeNs due = 0);
    // Where frames come from after those added (read when the device has none left).
    void setFeed(ReplayFrameFeed feed) { feed_ = std::move(feed); }
    // Adds every record of a concatenation of frame records; returns the number added.
    [[nodiscard]] Result<std::size_t> addRecords(std::span<const std::uint8_t> records);

    const std::vector<std::string>& calls() const { return calls_; }
    const std::vector<std::string>& violations() const { return violations_; }
    std::int32_t control(std::uint32_t id) const;
    std::size_t framesLeft() const { return frames_.size(); }

    Status open() override;
    void close() override;
    Result<transport::V4l2Capability> queryCapability() override;
    Result<transport::V4l2PixFormat> setFormat(const transport::V4l2PixFormat& f) override;
    Result<transport::V4l2Fraction> setFrameInterval(transport::V4l2Fraction t) override;
    Result<std::uint32_t> requestBuffers(std::uint32_t count) override;
    Result<transport::V4l2Buffer> queryBuffer(std::uint32_t index) override;
    Result<std::span<std::uint8_t>> map(std::uint32_t offset, std::uint32_t length) override;
    void unmap(std::span<std::uint8_t> mapping) override;
    Status queueBuffer(std::uint32_t index) override;
    Result<transport::V4l2Buffer> dequeueBuffer() override;
    Status streamOn() override;
    Status streamOff() override;
    Result<bool> waitReadable(TimeNs timeout) override;
    Status setControl(std::uint32_t id, std::int32_t value) override;
    Result<std::int32_t> getControl(std::uint32_t id) override;
    std::string describe() const override { return "v4l2 " + cfg_.path; }

private:
    Status violation(const std::string& what);
    std::uint32_t cookieStride() const;
    // The next frame to deliver (pulled from the feed; frames due before STREAMON skipped when
    // paced), nullptr at the end; whether it is due yet.
    Result<const ReplayFrame*> next();
    bool due(const ReplayFrame& f) const { return !cfg_.clock || cfg_.clock() >= f.due; }
    static constexpr std::uint32_t kPageSize = 4096;

    ReplayDeviceConfig cfg_;
    std::deque<ReplayFrame> frames_;
    ReplayFrameFeed feed_;
    TimeNs stream_on_ = 0;
    std::vector<std::string> calls_;
    std::vector<std::string> violations_;
    std::map<std::uint32_t, std::int32_t> controls_;
    transport::V4l2PixFormat format_;
    std::vector<std::vector<std::uint8_t>> buffers_;
    std::vector<bool> queued_;
    std::vector<bool> mapped_;
    std::deque<std::uint32_t> queue_;  // driver-owned buffers in fill order
    bool open_ = false;
    bool streaming_ = false;
};

// A camera playing a timed frame file (timed_frame_file.hpp) on CLOCK_MONOTONIC: the device of a
// `v4l2-replay-host-clock:FILE` entry in device.yaml (`handscan hil`). It offers the format of the
// file's frames at `interval`, delivers each frame at its due time and skips those due before
// STREAMON (a restarted daemon sees the recording from then on). A file that cannot be read
// gives a device whose open() fails naming it.
std::unique_ptr<transport::V4l2Device> openHostClockReplay(const std::string& path,
                                                           transport::V4l2Fraction interval);

}  // namespace handscan::camera
