#include "handscan/camera/frame_record_tap.hpp"

namespace handscan::camera {

FrameRecordTap::FrameRecordTap(RawTap& tap, std::size_t max_queued_bytes)
    : tap_(tap), max_queued_bytes_(max_queued_bytes), worker_([this] { run(); }) {}

FrameRecordTap::~FrameRecordTap() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    worker_.join();
}

void FrameRecordTap::submit(TimeNs t_rx, const FrameRecordHeader& header,
                            std::vector<std::uint8_t> payload) {
    {
        std::lock_guard lock(mutex_);
        if (queued_bytes_ + payload.size() > max_queued_bytes_) {
            ++dropped_;
            return;
        }
        queued_bytes_ += payload.size();
        queue_.push_back(Frame{t_rx, header, std::move(payload)});
    }
    wake_.notify_one();
}

void FrameRecordTap::flush() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [this] { return queue_.empty() && !coding_; });
}

std::uint64_t FrameRecordTap::dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
}

std::uint64_t FrameRecordTap::recorded() const {
    std::lock_guard lock(mutex_);
    return recorded_;
}

void FrameRecordTap::run() {
    std::unique_lock lock(mutex_);
    for (;;) {
        wake_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return;  // stopping, and everything was handed on
        Frame f = std::move(queue_.front());
        queue_.pop_front();
        queued_bytes_ -= f.payload.size();
        coding_ = true;
        lock.unlock();
        const std::vector<std::uint8_t> record =
            encodeFrameRecord(f.header, f.payload, FrameCoding::kPng);
        tap_.onRaw(f.t_rx, record);
        lock.lock();
        coding_ = false;
        ++recorded_;
        if (queue_.empty()) idle_.notify_all();
    }
}

}  // namespace handscan::camera
