// A fixed pool of large, page-aligned buffers passed from the thread that fills them to one worker
// thread that drains them, in order (triple buffering). The export uses it twice: encoding the
// next 4 MiB overlaps the write() of the previous ones, and reading back the next block overlaps
// the CRC of the previous one. The buffers are aligned for O_DIRECT. One producer thread only.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <new>
#include <span>
#include <thread>
#include <vector>

namespace handscan::exporter {

class BufferPipeline {
public:
    static constexpr std::size_t kAlignment = 4096;  // O_DIRECT: buffer, offset and length

    // Runs on the worker thread for each submitted buffer, in submission order. A non-zero return
    // (an errno) stops the pipeline: later buffers are skipped and every call reports that error.
    using Drain = std::function<int(std::span<const std::uint8_t> bytes, std::uint64_t offset)>;

    BufferPipeline(std::size_t buffer_bytes, std::size_t buffers, Drain drain);
    ~BufferPipeline();  // skips what is still queued and joins the worker
    BufferPipeline(const BufferPipeline&) = delete;
    BufferPipeline& operator=(const BufferPipeline&) = delete;

    // The buffer to fill next: buffer_bytes long, kAlignment-aligned.
    std::span<std::uint8_t> current() { return {buffers_[current_].get(), buffer_bytes_}; }
    // Queues the first `bytes` of current() to be drained at `offset`, then waits for a free
    // buffer to become current(). Returns the first drain error, 0 if none.
    int submit(std::size_t bytes, std::uint64_t offset);
    // Waits until everything queued has been drained. Returns the first drain error, 0 if none.
    int finish();

private:
    struct AlignedDelete {
        void operator()(std::uint8_t* p) const {
            ::operator delete[](p, std::align_val_t{kAlignment});
        }
    };
    struct Job {
        std::size_t buffer;
        std::size_t bytes;
        std::uint64_t offset;
    };
    void run();

    std::size_t buffer_bytes_;
    std::vector<std::unique_ptr<std::uint8_t, AlignedDelete>> buffers_;
    Drain drain_;
    std::mutex mutex_;
    std::condition_variable cv_;
    std::deque<Job> queue_;          // submitted, not yet drained
    std::vector<std::size_t> free_;  // neither current nor queued nor being drained
    std::size_t current_ = 0;
    bool draining_ = false;  // the worker holds a buffer outside the queue
    bool stop_ = false;
    int error_ = 0;
    std::thread worker_;
};

}  // namespace handscan::exporter
