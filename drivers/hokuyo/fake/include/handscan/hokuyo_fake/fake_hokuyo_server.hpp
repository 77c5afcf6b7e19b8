// FakeHokuyoServer: a FakeHokuyoSensor behind a real TCP listener on loopback, so tests run the
// real TcpStream and the real driver against it. Streams at the recording's pace (frame spacing
// from the sensor timestamps) or as fast as the client reads, one client at a time (as the sensor),
// and injects the faults a real link has: the socket closed mid-scan, a corrupted byte, a dropped
// byte - each at a given source frame and byte offset.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/hokuyo_fake/fake_hokuyo_sensor.hpp"
#include "handscan/transport/tcp_stream.hpp"

namespace handscan::hokuyo {

struct FakeLinkFault {
    enum class Kind { kCloseMidFrame, kCorruptByte, kDropByte };
    Kind kind = Kind::kCorruptByte;
    std::size_t frame_index = 0;  // index of the scan frame in the source
    std::size_t byte_offset = 0;  // byte of that frame (kCloseMidFrame: bytes sent before closing)
};

struct FakeServerOptions {
    bool real_pace = false;  // false: as fast as the client reads
    // When set (one entry per source frame): the host CLOCK_MONOTONIC time at which each frame is
    // sent, e.g. its recorded receive time shifted to now (`handscan hil`). Overrides real_pace.
    // Frames that fell due while no client streamed are lost, as the sensor does not buffer.
    std::vector<TimeNs> schedule;
    // framesSent() and framesSkipped() count source frames from this index on (a pre-roll before
    // it is not counted).
    std::size_t count_from = 0;
    std::vector<FakeLinkFault> faults;
};

class FakeHokuyoServer {
public:
    FakeHokuyoServer(std::vector<SourceScanFrame> source, FakeServerOptions options = {},
                     FakeHokuyoIdentity identity = {});
    ~FakeHokuyoServer();
    FakeHokuyoServer(const FakeHokuyoServer&) = delete;
    FakeHokuyoServer& operator=(const FakeHokuyoServer&) = delete;

    // Listens on 127.0.0.1 (an ephemeral port) and serves in a thread.
    Status start();
    void stop();
    int port() const { return port_; }

    std::size_t connections() const { return connections_.load(); }
    std::size_t framesSent() const { return frames_sent_.load(); }  // complete or damaged
    // Scheduled frames that fell due while no client was streaming (see FakeServerOptions).
    std::size_t framesSkipped() const { return frames_skipped_.load(); }
    bool sourceExhausted() const { return exhausted_.load(); }
    // Commands received from clients, in order (for tests of the handshake).
    std::vector<std::string> commandLog() const;

private:
    void serve();

    FakeHokuyoSensor sensor_;
    FakeServerOptions options_;
    int port_ = 0;
    std::thread thread_;
    std::atomic<bool> running_{false};
    std::atomic<std::size_t> connections_{0};
    std::atomic<std::size_t> frames_sent_{0};
    std::atomic<std::size_t> frames_skipped_{0};
    std::atomic<bool> exhausted_{false};
    mutable std::mutex log_mutex_;
    std::vector<std::string> command_log_;
    transport::TcpListener listener_;
};

}  // namespace handscan::hokuyo
