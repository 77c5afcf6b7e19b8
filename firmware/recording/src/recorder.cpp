#include "handscan/recording/recorder.hpp"

#include <algorithm>
#include <chrono>

#include "handscan/core/log.hpp"
#include "handscan/core/spsc_queue.hpp"

namespace handscan::recording {

class Recorder::Tap final : public RawTap {
public:
    struct Packet {
        TimeNs t = 0;
        std::vector<std::uint8_t> bytes;
    };

    Tap(std::string topic, std::uint16_t channel_id, const RecorderOptions& o)
        : topic_(std::move(topic)),
          channel_id_(channel_id),
          byte_budget_(o.queue_bytes),
          queue_(o.queue_messages) {}

    // Driver thread. The copy is the only allocation; nothing here waits on the writer.
    void onRaw(TimeNs t_host_rx, std::span<const std::uint8_t> bytes) override {
        if (!accepting_.load(std::memory_order_acquire) ||
            queued_bytes_.load(std::memory_order_relaxed) + bytes.size() > byte_budget_) {
            dropped_.fetch_add(1, std::memory_order_relaxed);
            return;
        }
        Packet p{t_host_rx, std::vector<std::uint8_t>(bytes.begin(), bytes.end())};
        queued_bytes_.fetch_add(bytes.size(), std::memory_order_relaxed);
        if (!queue_.tryPush(std::move(p))) {
            queued_bytes_.fetch_sub(bytes.size(), std::memory_order_relaxed);
            dropped_.fetch_add(1, std::memory_order_relaxed);
        }
    }

    // Writer thread.
    bool pop(Packet& out) {
        auto p = queue_.tryPop();
        if (!p) return false;
        queued_bytes_.fetch_sub(p->bytes.size(), std::memory_order_relaxed);
        out = std::move(*p);
        return true;
    }

    const std::string topic_;
    const std::uint16_t channel_id_;
    const std::size_t byte_budget_;
    SpscQueue<Packet> queue_;
    std::atomic<bool> accepting_{true};
    std::atomic<std::size_t> queued_bytes_{0};
    std::atomic<std::uint64_t> dropped_{0};
    std::atomic<std::uint64_t> written_{0};
    std::atomic<std::uint64_t> bytes_written_{0};
};

Recorder::Recorder(std::unique_ptr<McapWriter> writer, RecorderOptions options)
    : options_(std::move(options)), writer_(std::move(writer)) {}

Recorder::~Recorder() {
    if (Status s = stop(); !s) log().error("recorder: {}", s.message());
}

Result<std::unique_ptr<Recorder>> Recorder::create(const std::string& path,
                                                   RecorderOptions options) {
    auto w = McapWriter::create(path, options.mcap);
    if (!w) return w.status();
    return std::unique_ptr<Recorder>(new Recorder(std::move(*w), std::move(options)));
}

Result<RawTap*> Recorder::addChannel(const ChannelSpec& spec) {
    if (started_) {
        return Status{
            StatusCode::kInvalidArgument,
            "Recorder::addChannel(" + std::string(spec.topic) + "): add channels before start()"};
    }
    auto id = recording::addChannel(*writer_, spec);
    if (!id) return id.status();
    taps_.push_back(std::make_unique<Tap>(std::string(spec.topic), *id, options_));
    return static_cast<RawTap*>(taps_.back().get());
}

Status Recorder::start() {
    if (started_) return {StatusCode::kInvalidArgument, "Recorder::start: already started"};
    started_ = true;
    running_.store(true, std::memory_order_release);
    thread_ = std::thread([this] { run(); });
    return Status::ok();
}

bool Recorder::drainOnce() {
    // Everything queued right now, written in host-time order so chunks cover tight time ranges.
    struct Item {
        Tap* tap;
        Tap::Packet packet;
    };
    std::vector<Item> batch;
    for (auto& tap : taps_) {
        Tap::Packet p;
        while (tap->pop(p)) batch.push_back({tap.get(), std::move(p)});
    }
    if (batch.empty()) return false;
    std::stable_sort(batch.begin(), batch.end(),
                     [](const Item& a, const Item& b) { return a.packet.t < b.packet.t; });
    for (auto& item : batch) {
        bool ok = !write_failed_.load(std::memory_order_relaxed);
        if (ok) {
            if (Status s = writer_->write(item.tap->channel_id_, item.packet.t, item.packet.bytes);
                !s) {
                fail(s);
                ok = false;
            }
        }
        if (ok) {
            item.tap->written_.fetch_add(1, std::memory_order_relaxed);
            item.tap->bytes_written_.fetch_add(item.packet.bytes.size(), std::memory_order_relaxed);
        } else {
            item.tap->dropped_.fetch_add(1, std::memory_order_relaxed);
        }
    }
    return true;
}

void Recorder::fail(const Status& s) {
    if (write_failed_.exchange(true)) return;  // the first error is the one to report
    log().error("recorder: {} (further messages are dropped)", s.message());
    std::lock_guard<std::mutex> lock(status_mutex_);
    status_ = s;
}

void Recorder::run() {
    TimeNs last_data = monotonicNow();
    bool unflushed = false;
    while (running_.load(std::memory_order_acquire)) {
        if (drainOnce()) {
            last_data = monotonicNow();
            unflushed = true;
            continue;
        }
        // Idle: close the open chunk once it has waited a chunk duration.
        if (unflushed && options_.mcap.chunk_duration_ns > 0 &&
            monotonicNow() - last_data >= options_.mcap.chunk_duration_ns) {
            unflushed = false;
            if (Status s = writer_->flush(); !s) fail(s);
        }
        std::this_thread::sleep_for(std::chrono::nanoseconds(options_.idle_sleep_ns));
    }
    while (drainOnce()) {
    }
}

Status Recorder::stop() {
    if (stopped_) return status();
    stopped_ = true;
    for (auto& tap : taps_) tap->accepting_.store(false, std::memory_order_release);
    if (started_) {
        running_.store(false, std::memory_order_release);
        thread_.join();
        // A driver that passed the accepting check just before stop() may have pushed since.
        while (drainOnce()) {
        }
    }
    Status s = writer_->close();
    std::lock_guard<std::mutex> lock(status_mutex_);
    if (status_ && !s) status_ = s;
    return status_;
}

std::vector<ChannelCounters> Recorder::counters() const {
    std::vector<ChannelCounters> out;
    for (const auto& tap : taps_) {
        out.push_back({tap->topic_, tap->written_.load(std::memory_order_relaxed),
                       tap->bytes_written_.load(std::memory_order_relaxed),
                       tap->dropped_.load(std::memory_order_relaxed)});
    }
    return out;
}

Status Recorder::status() const {
    std::lock_guard<std::mutex> lock(status_mutex_);
    return status_;
}

}  // namespace handscan::recording
