// The fake MTi-20 behind a real pseudo-terminal: the driver opens slavePath() with the real
// SerialStream exactly as it would /dev/ttyUSB0, and a thread plays the device on the master side
// (answers the handshake, streams MTData2 at the configured rate in real time or as fast as the
// host reads). The master is put in raw mode so the line discipline never alters the device's
// bytes, as a UART would not.
#pragma once

#include <atomic>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"

namespace handscan::xsens {

struct PtyXsensOptions {
    bool real_time = true;  // pace packets at the output rate; false: as fast as the host reads
};

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

private:
    void run();

    FakeXsens& device_;
    PtyXsensOptions options_;
    int master_ = -1;
    std::string slave_path_;
    std::mutex mutex_;
    std::atomic<bool> stop_{false};
    std::atomic<std::uint64_t> bytes_written_{0};
    std::atomic<bool> paused_{false};
    std::atomic<std::size_t> pending_bytes_{0};
    std::thread thread_;
};

}  // namespace handscan::xsens
