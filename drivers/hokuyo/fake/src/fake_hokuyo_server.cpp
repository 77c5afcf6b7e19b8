#include "handscan/hokuyo_fake/fake_hokuyo_server.hpp"

#include <algorithm>
#include <array>
#include <chrono>

#include "handscan/core/log.hpp"

namespace handscan::hokuyo {

namespace {

std::span<const std::uint8_t> bytesOf(std::string_view s) {
    return {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()};
}

constexpr TimeNs kWriteTimeout = 2 * kNsPerSec;

}  // namespace

FakeHokuyoServer::FakeHokuyoServer(std::vector<SourceScanFrame> source, FakeServerOptions options,
                                   FakeHokuyoIdentity identity)
    : sensor_(std::move(source), std::move(identity)), options_(std::move(options)) {}

FakeHokuyoServer::~FakeHokuyoServer() { stop(); }

Status FakeHokuyoServer::start() {
    if (Status s = listener_.listen("127.0.0.1", 0); !s) return s;
    port_ = listener_.port();
    running_ = true;
    thread_ = std::thread([this] { serve(); });
    return Status::ok();
}

void FakeHokuyoServer::stop() {
    running_ = false;
    if (thread_.joinable()) thread_.join();
    listener_.close();
}

std::vector<std::string> FakeHokuyoServer::commandLog() const {
    std::lock_guard<std::mutex> lock(log_mutex_);
    return command_log_;
}

void FakeHokuyoServer::serve() {
    std::unique_ptr<transport::TcpStream> client;
    std::array<std::uint8_t, 4096> buf{};
    std::string pending_line;
    TimeNs next_due = 0;
    std::uint32_t last_ts = 0;
    bool have_ts = false;
    std::optional<std::string> frame;  // the next scan frame, waiting for its due time
    std::size_t index = 0;
    bool stream_restarted = true;  // scheduled frames already due are skipped, not sent late
    auto drop_client = [&] {
        client.reset();
        sensor_.onDisconnect();
        pending_line.clear();
        have_ts = false;
        frame.reset();  // lost with the connection, as on a real link
        stream_restarted = true;
    };
    while (running_) {
        if (!client) {
            auto accepted = listener_.accept(20 * kNsPerMs);
            if (!accepted) {
                log().warn("fake hokuyo: {}", accepted.status().message());
                continue;
            }
            if (!*accepted) continue;
            client = std::move(*accepted);
            ++connections_;
        }
        // Host commands (poll briefly; not at all when a frame is due).
        const bool frame_ready = frame || (sensor_.streaming() && !sensor_.sourceExhausted());
        const TimeNs wait =
            frame_ready ? std::max<TimeNs>(0, next_due - monotonicNow()) : 10 * kNsPerMs;
        auto n = client->read(buf, std::min<TimeNs>(wait, 10 * kNsPerMs));
        if (!n) {
            drop_client();
            continue;
        }
        if (*n > 0) {
            const std::string_view text(reinterpret_cast<const char*>(buf.data()), *n);
            {
                std::lock_guard<std::mutex> lock(log_mutex_);
                for (char c : text) {
                    if (c == '\n' || c == '\r') {
                        if (!pending_line.empty()) command_log_.push_back(pending_line);
                        pending_line.clear();
                    } else {
                        pending_line += c;
                    }
                }
            }
            sensor_.onHostBytes(text);
            const std::string replies = sensor_.takeReplies();
            if (!replies.empty() && !client->writeAll(bytesOf(replies), kWriteTimeout)) {
                drop_client();
                continue;
            }
        }
        if (frame && !sensor_.streaming()) frame.reset();  // QT / RS stopped the stream
        if (!frame) {
            if (!sensor_.streaming() || sensor_.sourceExhausted()) {
                exhausted_ = sensor_.sourceExhausted();
                continue;
            }
            std::uint32_t ts = 0;
            frame = sensor_.nextStreamFrame(&ts);
            if (!frame) continue;
            index = sensor_.lastFrameIndex();
            if (index < options_.schedule.size()) {
                next_due = options_.schedule[index];
                if (stream_restarted && next_due < monotonicNow()) {
                    frame.reset();
                    if (index >= options_.count_from) ++frames_skipped_;
                    continue;
                }
                stream_restarted = false;
            } else if (options_.real_pace) {
                // Keep the recording's spacing (24-bit ms clock; a gap over 1 s is not waited out).
                const std::uint32_t dt = have_ts ? ((ts - last_ts) & 0xFFFFFFu) : 0;
                const TimeNs spacing = dt < 1000 ? static_cast<TimeNs>(dt) * kNsPerMs : 0;
                next_due = std::max(next_due + spacing, have_ts ? next_due : monotonicNow());
                last_ts = ts;
                have_ts = true;
            }
        }
        const bool paced = options_.real_pace || !options_.schedule.empty();
        if (paced && monotonicNow() < next_due) continue;
        bool close_after = false;
        for (const FakeLinkFault& f : options_.faults) {
            if (f.frame_index != index || f.byte_offset >= frame->size()) continue;
            switch (f.kind) {
                case FakeLinkFault::Kind::kCorruptByte:
                    (*frame)[f.byte_offset] ^= 0x01;
                    break;
                case FakeLinkFault::Kind::kDropByte:
                    frame->erase(f.byte_offset, 1);
                    break;
                case FakeLinkFault::Kind::kCloseMidFrame:
                    frame->resize(f.byte_offset);
                    close_after = true;
                    break;
            }
        }
        if (index >= options_.count_from) ++frames_sent_;
        const Status w = client->writeAll(bytesOf(*frame), kWriteTimeout);
        frame.reset();
        if (!w || close_after) drop_client();
        exhausted_ = sensor_.sourceExhausted();
    }
}

}  // namespace handscan::hokuyo
