#include "handscan/xsens_fake/pty_xsens.hpp"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>  // posix_openpt, grantpt, unlockpt, ptsname_r
#include <sys/eventfd.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <utility>

namespace handscan::xsens {

PtyXsens::PtyXsens(FakeXsens& device, PtyXsensOptions options)
    : device_(device), options_(std::move(options)) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (master_ < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
    char name[128];
    if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0 ||
        ::ptsname_r(master_, name, sizeof name) != 0) {
        const std::string err = std::strerror(errno);
        ::close(master_);
        throw std::runtime_error("pty setup: " + err);
    }
    slave_path_ = name;
    wake_fd_ = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
    if (wake_fd_ < 0) {
        const std::string err = std::strerror(errno);
        ::close(master_);
        throw std::runtime_error("eventfd: " + err);
    }
    device_time_ = device_time_anchor_ = monotonicNow();
    termios tio{};
    if (::tcgetattr(master_, &tio) == 0) {
        ::cfmakeraw(&tio);
        ::tcsetattr(master_, TCSANOW, &tio);
    }
    thread_ = std::thread([this] { run(); });
}

PtyXsens::~PtyXsens() {
    hangUp();
    ::close(wake_fd_);
}

namespace {

// The host's line rate as its SerialStream set it (pty termios are shared by both ends).
int hostBaudrate(int master) {
    termios tio{};
    if (::tcgetattr(master, &tio) != 0) return 0;
    switch (::cfgetospeed(&tio)) {
        case B9600:
            return 9600;
        case B19200:
            return 19200;
        case B38400:
            return 38400;
        case B57600:
            return 57600;
        case B115200:
            return 115200;
        case B230400:
            return 230400;
        case B460800:
            return 460800;
        case B921600:
            return 921600;
        default:
            return 0;
    }
}

}  // namespace

void PtyXsens::hangUp() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (master_ >= 0) {
        ::close(master_);
        master_ = -1;
    }
}

std::vector<StreamedPacket> PtyXsens::streamed() {
    std::lock_guard lock(mutex_);
    return device_.streamed();
}

TimeNs PtyXsens::deviceNow() {
    if (options_.real_time) return monotonicNow();
    std::lock_guard lock(mutex_);
    return device_time_runs_ ? device_time_ + (monotonicNow() - device_time_anchor_) : device_time_;
}

void PtyXsens::updateDeviceClock(bool producing_fast) {
    if (device_time_runs_) {
        const TimeNs now = monotonicNow();
        device_time_ += now - device_time_anchor_;
        device_time_anchor_ = now;
    }
    device_time_runs_ = !producing_fast;
}

void PtyXsens::hostOpening() {
    std::lock_guard lock(mutex_);
    writes_held_ = true;
}

void PtyXsens::hostOpened() {
    std::lock_guard lock(mutex_);
    // Opening flushed the host's input, and nothing was written since: the count starts afresh.
    host_took_ = bytes_written_;
    writes_held_ = false;
}

void PtyXsens::hostTook(std::size_t n) {
    {
        std::lock_guard lock(mutex_);
        host_took_ += n;
    }
    const std::uint64_t one = 1;
    [[maybe_unused]] const ssize_t w = ::write(wake_fd_, &one, sizeof one);
}

Status PtyXsensHostStream::open() {
    // SerialStream::open() flushes what is in flight; the fake holds its writes meanwhile so that
    // it knows exactly which bytes the host can still read.
    pty_.hostOpening();
    Status s = link_.open();
    pty_.hostOpened();
    unreported_ = 0;
    return s;
}

Result<std::size_t> PtyXsensHostStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    // The previous chunk is processed: only now may the fake produce past it.
    if (unreported_ != 0) pty_.hostTook(unreported_);
    unreported_ = 0;
    auto n = link_.read(buffer, timeout);
    if (n.isOk()) unreported_ = *n;
    return n;
}

void PtyXsens::run() {
    std::vector<std::uint8_t> pending;
    std::uint8_t buf[1024];
    TimeNs next_packet = monotonicNow();
    while (!stop_) {
        // 1. Host bytes -> device (or a receipt from the host: it took bytes).
        pollfd p[2]{{master_, POLLIN, 0}, {wake_fd_, POLLIN, 0}};
        const TimeNs now = monotonicNow();
        int wait_ms = 1;
        if (options_.real_time && next_packet > now)
            wait_ms = static_cast<int>(std::min<TimeNs>((next_packet - now) / kNsPerMs, 5));
        if (!pending.empty()) wait_ms = std::min(wait_ms, 1);
        const int ready = ::poll(p, 2, wait_ms);
        if (ready > 0 && (p[1].revents & POLLIN) != 0) {
            std::uint64_t receipts = 0;
            [[maybe_unused]] const ssize_t r = ::read(wake_fd_, &receipts, sizeof receipts);
        }
        if (ready > 0 && (p[0].revents & POLLIN) != 0) {
            const ssize_t n = ::read(master_, buf, sizeof buf);
            std::lock_guard lock(mutex_);
            if (n > 0 &&
                hostBaudrate(master_) == device_.baudrate()) {  // else the device hears noise
                device_.receive(std::span<const std::uint8_t>(buf, static_cast<std::size_t>(n)));
            }
        } else if ((p[0].revents & POLLHUP) != 0) {
            // No slave open yet (or it was closed): nothing to talk to.
            ::usleep(1000);
        }
        // 2. Device -> host: replies at once, packets when due.
        {
            std::lock_guard lock(mutex_);
            const bool mismatched = hostBaudrate(master_) != device_.baudrate();
            auto out = device_.takeOutput();
            if (mismatched) FakeXsens::garble(out);
            pending.insert(pending.end(), out.begin(), out.end());
            const bool producing = device_.measuring() && !paused_;
            updateDeviceClock(producing && !options_.real_time);
            if (!options_.recorded_measurement.empty()) {
                playRecorded(producing, pending);
            } else if (producing) {
                const TimeNs t = monotonicNow();
                const TimeNs period = kNsPerSec / device_.rateHz();
                if (options_.real_time) {
                    // The device's clock does not stop when this thread is held up: catch up with
                    // the packets that fell due meanwhile, as a UART FIFO would deliver them.
                    while (next_packet <= t) {
                        device_.emitPacket();
                        next_packet += period;
                    }
                    out = device_.takeOutput();
                    if (mismatched) FakeXsens::garble(out);
                    pending.insert(pending.end(), out.begin(), out.end());
                } else {
                    // As fast as the host reads: at most kFastLeadBytes ahead of what it took,
                    // each packet one period of device time.
                    const auto ahead = [&] {
                        const std::uint64_t written = bytes_written_;
                        return pending.size() + (written - std::min(host_took_, written));
                    };
                    while (ahead() < kFastLeadBytes) {
                        device_.emitPacket();
                        device_time_ += period;
                        out = device_.takeOutput();
                        if (mismatched) FakeXsens::garble(out);
                        pending.insert(pending.end(), out.begin(), out.end());
                    }
                }
            } else {
                next_packet = monotonicNow();
            }
        }
        if (!pending.empty()) {
            // Under the lock, so that hostOpening() knows no write is under way (non-blocking).
            std::lock_guard lock(mutex_);
            const ssize_t n = writes_held_ ? 0 : ::write(master_, pending.data(), pending.size());
            if (n > 0) {
                pending.erase(pending.begin(), pending.begin() + n);
                bytes_written_ += static_cast<std::uint64_t>(n);
            }
        }
        // Nobody listening for long: a UART would lose these bytes too.
        constexpr std::size_t kMaxPending = std::size_t{64} * 1024;
        if (pending.size() > kMaxPending) {
            pending.erase(pending.begin(),
                          pending.end() - static_cast<std::ptrdiff_t>(kMaxPending));
        }
        pending_bytes_ = pending.size();
    }
}

void PtyXsens::playRecorded(bool measuring, std::vector<std::uint8_t>& pending) {
    const auto& chunks = options_.recorded_measurement;
    const TimeNs now = monotonicNow();
    while (next_recorded_ < chunks.size() && chunks[next_recorded_].t_host_rx <= now) {
        const RecordedChunk& c = chunks[next_recorded_++];
        if (measuring) {
            pending.insert(pending.end(), c.bytes.begin(), c.bytes.end());
            ++recorded_sent_;
        } else {
            ++recorded_lost_;
        }
    }
}

}  // namespace handscan::xsens
