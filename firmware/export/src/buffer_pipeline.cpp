#include "buffer_pipeline.hpp"

namespace handscan::exporter {

BufferPipeline::BufferPipeline(std::size_t buffer_bytes, std::size_t buffers, Drain drain)
    : buffer_bytes_(buffer_bytes), drain_(std::move(drain)) {
    for (std::size_t i = 0; i < buffers; ++i) {
        buffers_.emplace_back(new (std::align_val_t{kAlignment}) std::uint8_t[buffer_bytes]);
        if (i > 0) free_.push_back(i);
    }
    worker_ = std::thread([this] { run(); });
}

BufferPipeline::~BufferPipeline() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    cv_.notify_all();
    worker_.join();
}

int BufferPipeline::submit(std::size_t bytes, std::uint64_t offset) {
    std::unique_lock lock(mutex_);
    if (error_ != 0) return error_;
    queue_.push_back({current_, bytes, offset});
    cv_.notify_all();
    cv_.wait(lock, [&] { return !free_.empty() || error_ != 0; });
    if (free_.empty()) return error_;  // the worker stopped; current_ stays queued and unused
    current_ = free_.back();
    free_.pop_back();
    return error_;
}

int BufferPipeline::finish() {
    std::unique_lock lock(mutex_);
    cv_.wait(lock, [&] { return (queue_.empty() && !draining_) || error_ != 0; });
    return error_;
}

void BufferPipeline::run() {
    std::unique_lock lock(mutex_);
    while (true) {
        cv_.wait(lock, [&] { return stop_ || !queue_.empty(); });
        if (stop_) return;  // queued buffers are abandoned: the file is being thrown away
        const Job job = queue_.front();
        queue_.pop_front();
        int err = error_;
        if (err == 0) {
            draining_ = true;
            lock.unlock();  // the write (or CRC) runs while the producer fills the next buffer
            err = drain_(std::span<const std::uint8_t>(buffers_[job.buffer].get(), job.bytes),
                         job.offset);
            lock.lock();
            draining_ = false;
            if (err != 0 && error_ == 0) error_ = err;
        }
        free_.push_back(job.buffer);
        cv_.notify_all();
    }
}

}  // namespace handscan::exporter
