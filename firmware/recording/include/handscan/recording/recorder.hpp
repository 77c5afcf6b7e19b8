// Recorder: records the raw device streams while the scanner runs. Each driver gets a RawTap per
// channel and calls onRaw(t_host_rx, bytes) on its own thread; the tap copies the bytes into a
// lock-free SPSC queue and returns at once. One writer thread drains every queue, writes the
// messages in host-time order into an McapWriter and closes chunks as they fill.
//
// A driver is never blocked: when a channel's queue is full (the disk stalls, a camera floods),
// the message is dropped and counted; counters() reports per channel what was written and what
// was dropped. stop() drains what is queued and finishes the file.
//
// When every driver goes quiet, the open chunk is written out after mcap.chunk_duration_ns, so
// the last messages before a stall are on disk too.
//
// One producer thread per tap (the SpscQueue's contract). Call stop() once the drivers have
// stopped; bytes offered after stop() are counted as dropped.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "handscan/core/raw_tap.hpp"
#include "handscan/core/status.hpp"
#include "handscan/recording/channels.hpp"
#include "handscan/recording/mcap_writer.hpp"

namespace handscan::recording {

// The recorder syncs every closed chunk to the storage device (done on the writer thread, never
// on a driver's): a power cut then loses at most the open chunk, not the page cache's ~30 s.
inline McapWriterOptions recorderWriterDefaults() {
    McapWriterOptions o;
    o.sync_each_chunk = true;
    return o;
}

struct RecorderOptions {
    McapWriterOptions mcap = recorderWriterDefaults();
    std::size_t queue_messages = 2048;    // per channel
    std::size_t queue_bytes = 64u << 20;  // per channel: bounds memory when images back up
    TimeNs idle_sleep_ns = 2 * kNsPerMs;  // writer thread's nap when every queue is empty
};

struct ChannelCounters {
    std::string topic;
    std::uint64_t written = 0;        // messages in the file
    std::uint64_t bytes_written = 0;  // payload bytes in the file
    std::uint64_t dropped = 0;        // messages lost (queue full, or after a write error)
};

class Recorder {
public:
    [[nodiscard]] static Result<std::unique_ptr<Recorder>> create(const std::string& path,
                                                                  RecorderOptions options = {});
    ~Recorder();  // stop()s if still running
    Recorder(const Recorder&) = delete;
    Recorder& operator=(const Recorder&) = delete;

    // Adds a channel before start() and returns the tap its driver writes to (owned by the
    // Recorder).
    [[nodiscard]] Result<RawTap*> addChannel(const ChannelSpec& spec);

    // Starts the writer thread.
    [[nodiscard]] Status start();
    // Stops accepting, drains every queue, finishes the file. Returns the first write error.
    [[nodiscard]] Status stop();

    // Thread-safe snapshot of the per-channel counts.
    std::vector<ChannelCounters> counters() const;
    // First write error so far (ok while all is well). Thread-safe.
    Status status() const;

private:
    class Tap;
    Recorder(std::unique_ptr<McapWriter> writer, RecorderOptions options);
    void run();
    // Moves everything queued into the file; false when nothing was queued.
    bool drainOnce();
    // Records the first write error; from then on messages are dropped and counted.
    void fail(const Status& s);

    RecorderOptions options_;
    std::unique_ptr<McapWriter> writer_;
    std::vector<std::unique_ptr<Tap>> taps_;
    std::thread thread_;
    std::atomic<bool> running_{false};
    std::atomic<bool> write_failed_{false};
    bool started_ = false;
    bool stopped_ = false;
    mutable std::mutex status_mutex_;
    Status status_;
};

}  // namespace handscan::recording
