// The fake MTi-20 behind a real pseudo-terminal: the driver opens slavePath() with the real
// SerialStream exactly as it would /dev/ttyUSB0, and a thread plays the device on the master side
// (answers the handshake, streams MTData2 at the configured rate in real time or as fast as the
// host reads). The master is put in raw mode so the line discipline never alters the device's
// bytes, as a UART would not.
//
// Time: deviceNow() is the clock the host under test must use. In real time it is CLOCK_MONOTONIC.
// As fast as the host reads it is the device's own time: one output period per packet while
// measuring, real time otherwise. A fast stream stamped with the real clock would look to the
// host's ClockMapper like a device running ten times too fast, and a machine under load would
// stretch that unevenly into what looks like device restarts. In that mode the host must read
// through a PtyXsensHostStream: the fake never runs more than kFastLeadBytes ahead of what the
// host has taken (nothing is read, nothing more is produced), so the receive latency in device
// time stays below a few packets, and a device streaming since power-up sends only a few packets
// before the host's GoToConfig, however the threads are scheduled.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/transport/byte_stream.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"
#include "handscan/xsens_fake/recorded_byte_stream.hpp"

namespace handscan::xsens {

struct PtyXsensOptions {
    // Pace packets at the output rate; false: as fast as the host reads through a
    // PtyXsensHostStream.
    bool real_time = true;
    // When not empty: while measuring, the device sends these bytes instead of its synthetic
    // MTData2 packets, each chunk at its host CLOCK_MONOTONIC time (a recording's bytes after
    // the GoToMeasurement ack, shifted to now: `handscan hil`). Chunks that fall due while the
    // device is in config mode are lost, as a measuring MTi's would be. Needs real_time.
    std::vector<RecordedChunk> recorded_measurement;
};

// Bytes the fake may have on their way to a PtyXsensHostStream reader in the as-fast-as-read mode:
// about five 200 Hz MTData2 packets (54 bytes each), i.e. at most ~30 ms of receive latency in
// device time, below ClockMapper's 50 ms outlier threshold.
inline constexpr std::size_t kFastLeadBytes = 256;

class PtyXsens {
public:
    // Throws std::runtime_error when no pty can be allocated (tests skip then).
    PtyXsens(FakeXsens& device, PtyXsensOptions options = {});
    ~PtyXsens();
    PtyXsens(const PtyXsens&) = delete;
    PtyXsens& operator=(const PtyXsens&) = delete;

    const std::string& slavePath() const { return slave_path_; }
    // Stops the device thread and closes the master: the host sees a hang-up.
    void hangUp();
    // Stops producing packets (replies still flow) so a test can drain what is in flight.
    void pauseStreaming() { paused_ = true; }
    // Paused and every byte handed to the pty.
    bool drained() const { return paused_ && pending_bytes_ == 0; }
    // Runs `f(device)` under the device thread's lock (the device must not be touched otherwise
    // while the pty runs).
    template <typename F>
    auto inspect(F&& f) {
        std::lock_guard lock(mutex_);
        return f(static_cast<const FakeXsens&>(device_));
    }
    // A copy of what the device streamed so far (thread-safe).
    std::vector<StreamedPacket> streamed();
    std::uint64_t bytesWritten() const { return bytes_written_; }
    // Recorded chunks (PtyXsensOptions::recorded_measurement) handed out and lost so far.
    std::size_t recordedChunksSent() const { return recorded_sent_; }
    std::size_t recordedChunksLost() const { return recorded_lost_; }
    bool recordingPlayed() const {
        return recorded_sent_ + recorded_lost_ >= options_.recorded_measurement.size();
    }

    // The time the host should stamp what it receives with (see the header comment); thread-safe.
    TimeNs deviceNow();
    // Called by PtyXsensHostStream around the host's open() (which flushes what is in flight),
    // and when the host took `n` more bytes and came back for more.
    void hostOpening();
    void hostOpened();
    void hostTook(std::size_t n);

private:
    void run();
    // Device time: frozen while the fake produces as fast as read (packets advance it), running
    // with the real clock otherwise. Called with mutex_ held.
    void updateDeviceClock(bool producing_fast);
    // Moves the recorded chunks that fell due into `pending` (measuring) or drops them.
    void playRecorded(bool measuring, std::vector<std::uint8_t>& pending);

    FakeXsens& device_;
    PtyXsensOptions options_;
    int master_ = -1;
    std::string slave_path_;
    std::mutex mutex_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> bytes_written_{0};
    std::atomic<std::size_t> recorded_sent_{0};
    std::atomic<std::size_t> recorded_lost_{0};
    std::atomic<bool> paused_{false};
    std::atomic<std::size_t> pending_bytes_{0};
    // Flow control of the as-fast-as-read mode (guarded by mutex_).
    bool writes_held_ = false;       // the host is opening (and flushing) its end
    std::uint64_t host_took_ = 0;    // bytes the host has taken (comparable with bytes_written_)
    TimeNs device_time_ = 0;         // see updateDeviceClock()
    TimeNs device_time_anchor_ = 0;  // real time at which device_time_ was last set, when running
    bool device_time_runs_ = true;
    std::size_t next_recorded_ = 0;  // into options_.recorded_measurement (device thread only)
    int wake_fd_ = -1;               // eventfd: the host took bytes, the fake may produce more
    std::thread thread_;
};

// The host's end of the pty as the driver under test sees it: the real SerialStream (termios,
// poll, read) with receipts. Each read() first tells the fake that the host took the previous
// chunk, so while the host processes a chunk the fake cannot run further ahead.
class PtyXsensHostStream : public transport::ByteStream {
public:
    PtyXsensHostStream(transport::ByteStream& link, PtyXsens& pty) : link_(link), pty_(pty) {}
    Status open() override;
    void close() override { link_.close(); }
    bool isOpen() const override { return link_.isOpen(); }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override {
        return link_.writeAll(data, timeout);
    }
    std::string describe() const override { return link_.describe(); }

private:
    transport::ByteStream& link_;
    PtyXsens& pty_;
    std::size_t unreported_ = 0;
};

}  // namespace handscan::xsens
