// Camera frames to a recording tap as frame records, without holding up the capture thread.
// submit() (on the capture thread) only queues the buffer's bytes; a worker thread codes each frame
// as the simulator's recordings do (frame_record.hpp: PNG, version 2, for the uncompressed
// formats GREY and YUYV; as they are, version 1, for MJPEG) and hands the record to the tap with
// the frame's receive time, in capture order. PNG-coding a 640 x 480 frame takes milliseconds, a
// good part of a frame period, which the capture thread cannot spare. The queue is bounded in
// bytes: when the worker falls behind, frames beyond the bound are dropped and counted (as the
// recorder drops when its writer falls behind). The destructor hands on what is queued.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

#include "handscan/camera/frame_record.hpp"
#include "handscan/core/raw_tap.hpp"

namespace handscan::camera {

class FrameRecordTap {
public:
    explicit FrameRecordTap(RawTap& tap, std::size_t max_queued_bytes = std::size_t{64} << 20);
    ~FrameRecordTap();
    FrameRecordTap(const FrameRecordTap&) = delete;
    FrameRecordTap& operator=(const FrameRecordTap&) = delete;

    // Capture thread: queues the frame (header.bytesused is taken from the payload) or, when the
    // bound would be exceeded, drops it. Never waits for the coding.
    void submit(TimeNs t_rx, const FrameRecordHeader& header, std::vector<std::uint8_t> payload);
    // Waits until every frame submitted so far went to the tap.
    void flush();
    std::uint64_t dropped() const;
    std::uint64_t recorded() const;

private:
    struct Frame {
        TimeNs t_rx = 0;
        FrameRecordHeader header;
        std::vector<std::uint8_t> payload;
    };
    void run();

    RawTap& tap_;
    const std::size_t max_queued_bytes_;
    mutable std::mutex mutex_;
    std::condition_variable wake_;  // work queued, or stop
    std::condition_variable idle_;  // the queue ran empty and nothing is being coded
    std::deque<Frame> queue_;
    std::size_t queued_bytes_ = 0;
    bool coding_ = false;
    bool stop_ = false;
    std::uint64_t dropped_ = 0;
    std::uint64_t recorded_ = 0;
    std::thread worker_;
};

}  // namespace handscan::camera
