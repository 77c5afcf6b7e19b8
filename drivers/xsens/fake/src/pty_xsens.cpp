#include "handscan/xsens_fake/pty_xsens.hpp"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>  // posix_openpt, grantpt, unlockpt, ptsname_r
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace handscan::xsens {

PtyXsens::PtyXsens(FakeXsens& device, PtyXsensOptions options) : device_(device), options_(options) {
    master_ = ::posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (master_ < 0) throw std::runtime_error(std::string("posix_openpt: ") + std::strerror(errno));
    char name[128];
    if (::grantpt(master_) != 0 || ::unlockpt(master_) != 0 || ::ptsname_r(master_, name, sizeof name) != 0) {
        const std::string err = std::strerror(errno);
        ::close(master_);
        throw std::runtime_error("pty setup: " + err);
    }
    slave_path_ = name;
    termios tio{};
    if (::tcgetattr(master_, &tio) == 0) {
        ::cfmakeraw(&tio);
        ::tcsetattr(master_, TCSANOW, &tio);
    }
    thread_ = std::thread([this] { run(); });
}

PtyXsens::~PtyXsens() { hangUp(); }

namespace {

// The host's line rate as its SerialStream set it (pty termios are shared by both ends).
int hostBaudrate(int master) {
    termios tio{};
    if (::tcgetattr(master, &tio) != 0) return 0;
    switch (::cfgetospeed(&tio)) {
        case B9600: return 9600;
        case B19200: return 19200;
        case B38400: return 38400;
        case B57600: return 57600;
        case B115200: return 115200;
        case B230400: return 230400;
        case B460800: return 460800;
        case B921600: return 921600;
        default: return 0;
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

void PtyXsens::run() {
    std::vector<std::uint8_t> pending;
    std::uint8_t buf[1024];
    TimeNs next_packet = monotonicNow();
    while (!stop_) {
        // 1. Host bytes -> device.
        pollfd p{master_, POLLIN, 0};
        const TimeNs now = monotonicNow();
        int wait_ms = 1;
        if (options_.real_time && next_packet > now) wait_ms = static_cast<int>(std::min<TimeNs>((next_packet - now) / kNsPerMs, 5));
        if (!pending.empty()) wait_ms = std::min(wait_ms, 1);
        if (::poll(&p, 1, wait_ms) > 0 && (p.revents & POLLIN) != 0) {
            const ssize_t n = ::read(master_, buf, sizeof buf);
            std::lock_guard lock(mutex_);
            if (n > 0 && hostBaudrate(master_) == device_.baudrate()) {  // else the device hears noise
                device_.receive(std::span<const std::uint8_t>(buf, static_cast<std::size_t>(n)));
            }
        } else if ((p.revents & POLLHUP) != 0) {
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
            if (device_.measuring() && !paused_) {
                const TimeNs t = monotonicNow();
                const TimeNs period = kNsPerSec / device_.rateHz();
                if (options_.real_time) {
                    if (t - next_packet > 10 * period) next_packet = t;  // do not burst after a pause
                    while (next_packet <= t) {
                        device_.emitPacket();
                        next_packet += period;
                    }
                    out = device_.takeOutput();
                    if (mismatched) FakeXsens::garble(out);
                    pending.insert(pending.end(), out.begin(), out.end());
                } else {
                    // As fast as the host reads: keep about one pty buffer's worth in flight.
                    while (pending.size() < 4096) {
                        device_.emitPacket();
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
            const ssize_t n = ::write(master_, pending.data(), pending.size());
            if (n > 0) {
                pending.erase(pending.begin(), pending.begin() + n);
                bytes_written_ += static_cast<std::uint64_t>(n);
            }
        }
        // Nobody listening for long: a UART would lose these bytes too.
        constexpr std::size_t kMaxPending = 64 * 1024;
        if (pending.size() > kMaxPending) {
            pending.erase(pending.begin(), pending.end() - static_cast<std::ptrdiff_t>(kMaxPending));
        }
        pending_bytes_ = pending.size();
    }
}

}  // namespace handscan::xsens
