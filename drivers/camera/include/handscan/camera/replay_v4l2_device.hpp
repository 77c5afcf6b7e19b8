// A V4L2 device without a kernel: it answers the ioctl sequence like a capture driver (format
// substitution, buffer counts, mmap cookies, queue ownership, EAGAIN when empty) and fills its
// buffers from frame records (recorded /camera/* messages or synthetic frames). Used as the
// fake device layer in tests (every call is logged and checked against the V4L2 rules; misuse
// is an error the test sees in violations()) and as the replay source of recordings, so that
// replayed frames go through the driver's real buffer handling.
#pragma once

#include <cstdint>
#include <deque>
#include <map>
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
};

class ReplayV4l2Device final : public transport::V4l2Device {
public:
    explicit ReplayV4l2Device(ReplayDeviceConfig config);

    // Frames to deliver, in order (header fields become the v4l2_buffer fields).
    void addFrame(const FrameRecordHeader& header, std::vector<std::uint8_t> payload);
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
    static constexpr std::uint32_t kPageSize = 4096;

    struct Frame {
        FrameRecordHeader header;
        std::vector<std::uint8_t> payload;
    };
    ReplayDeviceConfig cfg_;
    std::deque<Frame> frames_;
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

}  // namespace handscan::camera
