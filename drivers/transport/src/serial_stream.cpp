#include "handscan/transport/serial_stream.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace handscan::transport {
namespace {

std::optional<speed_t> speedOf(int baud) {
    switch (baud) {
        case 9600:
            return B9600;
        case 19200:
            return B19200;
        case 38400:
            return B38400;
        case 57600:
            return B57600;
        case 115200:
            return B115200;
        case 230400:
            return B230400;
        case 460800:
            return B460800;
        case 921600:
            return B921600;
        case 2000000:
            return B2000000;
        case 4000000:
            return B4000000;
        default:
            return std::nullopt;
    }
}

std::string errnoText() { return std::strerror(errno); }

int pollTimeoutMs(TimeNs timeout) {
    if (timeout <= 0) return 0;
    // Round up so a short positive timeout still waits.
    return static_cast<int>(std::min<TimeNs>((timeout + kNsPerMs - 1) / kNsPerMs, 1'000'000));
}

}  // namespace

SerialStream::~SerialStream() { close(); }

bool SerialStream::supportsBaudrate(int baud) { return speedOf(baud).has_value(); }

std::string SerialStream::describe() const {
    return "serial " + cfg_.path + " " + std::to_string(cfg_.baud);
}

Status SerialStream::applyTermios(int baud) {
    const auto speed = speedOf(baud);
    if (!speed) {
        return {StatusCode::kInvalidArgument,
                describe() + ": " + std::to_string(baud) +
                    " baud is not a standard rate; use 9600 ... 921600"};
    }
    termios tio{};
    if (::tcgetattr(fd_, &tio) != 0) {
        return {StatusCode::kIoError,
                describe() + ": tcgetattr: " + errnoText() + " (is it a tty?)"};
    }
    // Raw mode, spelled out (what cfmakeraw does, plus 8N1, no flow control, receiver on).
    tio.c_iflag &= ~static_cast<tcflag_t>(IGNBRK | BRKINT | PARMRK | ISTRIP | INLCR | IGNCR |
                                          ICRNL | IXON | IXOFF | IXANY | INPCK);
    tio.c_oflag &= ~static_cast<tcflag_t>(OPOST);
    tio.c_lflag &= ~static_cast<tcflag_t>(ECHO | ECHONL | ICANON | ISIG | IEXTEN);
    tio.c_cflag &= ~static_cast<tcflag_t>(CSIZE | PARENB | CSTOPB | CRTSCTS);
    tio.c_cflag |= CS8 | CREAD | CLOCAL;
    // read() returns at once with whatever is there; poll() does the waiting.
    tio.c_cc[VMIN] = 0;
    tio.c_cc[VTIME] = 0;
    ::cfsetispeed(&tio, *speed);
    ::cfsetospeed(&tio, *speed);
    if (::tcsetattr(fd_, TCSANOW, &tio) != 0) {
        return {StatusCode::kIoError, describe() + ": tcsetattr: " + errnoText()};
    }
    // tcsetattr succeeds if *any* change was applied: read back to be sure the rate took.
    termios check{};
    if (::tcgetattr(fd_, &check) != 0 || ::cfgetispeed(&check) != *speed ||
        ::cfgetospeed(&check) != *speed || (check.c_cflag & CSIZE) != CS8 ||
        (check.c_lflag & ICANON) != 0) {
        return {StatusCode::kIoError, describe() + ": the tty driver did not take raw 8N1 at " +
                                          std::to_string(baud) +
                                          " baud; does the adapter support this rate?"};
    }
    cfg_.baud = baud;
    return Status::ok();
}

Status SerialStream::open() {
    close();
    // O_NONBLOCK so that open() does not wait for carrier; cleared again below.
    fd_ = ::open(cfg_.path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
    if (fd_ < 0) {
        const int err = errno;
        const StatusCode code = err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError;
        std::string hint = err == EACCES
                               ? " (add the user to the dialout group or install the udev rule)"
                           : err == ENOENT ? " (is the device plugged in?)"
                                           : "";
        return {code, describe() + ": open: " + std::strerror(err) + hint};
    }
    if (cfg_.exclusive && ::ioctl(fd_, TIOCEXCL) != 0) {
        Status s{StatusCode::kIoError, describe() + ": TIOCEXCL: " + errnoText()};
        close();
        return s;
    }
    const int flags = ::fcntl(fd_, F_GETFL);
    if (flags < 0 || ::fcntl(fd_, F_SETFL, flags & ~O_NONBLOCK) != 0) {
        Status s{StatusCode::kIoError, describe() + ": fcntl: " + errnoText()};
        close();
        return s;
    }
    if (Status s = applyTermios(cfg_.baud); !s) {
        close();
        return s;
    }
    ::tcflush(fd_, TCIOFLUSH);  // stale bytes from before we owned the port
    return Status::ok();
}

void SerialStream::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

Status SerialStream::setBaudrate(int baud) {
    if (fd_ < 0) return {StatusCode::kDisconnected, describe() + ": not open"};
    ::tcdrain(fd_);
    return applyTermios(baud);
}

Result<std::size_t> SerialStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    if (fd_ < 0) return Status{StatusCode::kDisconnected, describe() + ": not open"};
    pollfd p{fd_, POLLIN, 0};
    int r = 0;
    do {
        r = ::poll(&p, 1, pollTimeoutMs(timeout));
    } while (r < 0 && errno == EINTR);
    if (r < 0) return Status{StatusCode::kIoError, describe() + ": poll: " + errnoText()};
    if (r == 0) return std::size_t{0};
    if ((p.revents & POLLIN) == 0 && (p.revents & (POLLHUP | POLLERR | POLLNVAL)) != 0) {
        return Status{StatusCode::kDisconnected, describe() + ": the device went away (hang-up)"};
    }
    ssize_t n = 0;
    do {
        n = ::read(fd_, buffer.data(), buffer.size());
    } while (n < 0 && errno == EINTR);
    if (n < 0) {
        if (errno == EAGAIN) return std::size_t{0};
        const StatusCode code = errno == EIO || errno == ENXIO || errno == ENODEV
                                    ? StatusCode::kDisconnected
                                    : StatusCode::kIoError;
        return Status{code, describe() + ": read: " + errnoText()};
    }
    if (n == 0) {
        // poll said readable but there is nothing: the line hung up (USB adapter unplugged).
        return Status{StatusCode::kDisconnected,
                      describe() + ": end of stream (device unplugged?)"};
    }
    return static_cast<std::size_t>(n);
}

Status SerialStream::writeAll(std::span<const std::uint8_t> data, TimeNs timeout) {
    if (fd_ < 0) return {StatusCode::kDisconnected, describe() + ": not open"};
    const TimeNs deadline = monotonicNow() + timeout;
    std::size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::write(fd_, data.data() + done, data.size() - done);
        if (n > 0) {
            done += static_cast<std::size_t>(n);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && errno != EAGAIN) {
            const StatusCode code =
                errno == EIO || errno == ENXIO ? StatusCode::kDisconnected : StatusCode::kIoError;
            return {code, describe() + ": write: " + errnoText()};
        }
        const TimeNs left = deadline - monotonicNow();
        if (left <= 0) {
            return {StatusCode::kTimeout, describe() + ": write timed out with " +
                                              std::to_string(data.size() - done) + " of " +
                                              std::to_string(data.size()) + " bytes unsent"};
        }
        pollfd p{fd_, POLLOUT, 0};
        (void)::poll(&p, 1, pollTimeoutMs(left));
    }
    return Status::ok();
}

}  // namespace handscan::transport
