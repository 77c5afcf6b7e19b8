#include "handscan/transport/tcp_stream.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace handscan::transport {

namespace {

std::string errnoText(int e) { return std::string(std::strerror(e)); }

// poll() timeout in ms, rounded up so that a 0.5 ms wait does not become a busy spin.
int pollMs(TimeNs timeout) {
    if (timeout <= 0) return 0;
    return static_cast<int>(std::min<TimeNs>((timeout + kNsPerMs - 1) / kNsPerMs, 1'000'000));
}

// Waits for `events` on fd; returns >0 ready, 0 timeout, <0 error (errno set). Retries EINTR.
int waitFor(int fd, short events, TimeNs timeout) {
    const TimeNs deadline = monotonicNow() + timeout;
    for (;;) {
        pollfd p{fd, events, 0};
        const int r = ::poll(&p, 1, pollMs(deadline - monotonicNow()));
        if (r < 0 && errno == EINTR) continue;
        return r;
    }
}

}  // namespace

TcpStream::TcpStream(std::string host, int port, TimeNs connect_timeout)
    : host_(std::move(host)), port_(port), connect_timeout_(connect_timeout) {}

TcpStream::~TcpStream() { close(); }

std::unique_ptr<TcpStream> TcpStream::adopt(int fd, std::string peer) {
    auto s = std::make_unique<TcpStream>(std::move(peer), 0, 0);
    s->fd_ = fd;
    s->adopted_ = true;
    return s;
}

std::string TcpStream::describe() const {
    return adopted_ ? "tcp peer " + host_ : "tcp " + host_ + ":" + std::to_string(port_);
}

void TcpStream::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

Status TcpStream::open() {
    close();
    if (adopted_) {
        return Status(StatusCode::kUnsupported,
                      describe() + ": an accepted connection cannot be reopened");
    }
    const std::string where = describe();
    if (port_ < 1 || port_ > 65535) {
        return Status(StatusCode::kInvalidArgument,
                      where + ": port must be 1..65535 (check hokuyo.port in device.yaml)");
    }
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    addrinfo* res = nullptr;
    const int gai = ::getaddrinfo(host_.c_str(), std::to_string(port_).c_str(), &hints, &res);
    if (gai != 0) {
        return Status(StatusCode::kNotFound, where + ": cannot resolve host: " + gai_strerror(gai));
    }
    Status last(StatusCode::kIoError, where + ": no address to connect to");
    for (addrinfo* ai = res; ai != nullptr; ai = ai->ai_next) {
        const int fd = ::socket(ai->ai_family, ai->ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC,
                                ai->ai_protocol);
        if (fd < 0) {
            last = Status(StatusCode::kIoError, where + ": socket(): " + errnoText(errno));
            continue;
        }
        int r = ::connect(fd, ai->ai_addr, ai->ai_addrlen);
        if (r < 0 && errno == EINPROGRESS) {
            const int w = waitFor(fd, POLLOUT, connect_timeout_);
            if (w == 0) {
                ::close(fd);
                last = Status(StatusCode::kTimeout,
                              where + ": no answer within " +
                                  std::to_string(toSeconds(connect_timeout_)) +
                                  " s; check the cable, the sensor's power and its IP address");
                continue;
            }
            int err = 0;
            socklen_t len = sizeof err;
            if (w < 0)
                err = errno;
            else
                ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &err, &len);
            r = err == 0 ? 0 : -1;
            errno = err;
        }
        if (r < 0) {
            const int e = errno;
            ::close(fd);
            last =
                Status(e == ECONNREFUSED ? StatusCode::kDisconnected : StatusCode::kIoError,
                       where + ": connect: " + errnoText(e) +
                           (e == ECONNREFUSED ? " (is another client connected, or the port wrong?)"
                                              : ""));
            continue;
        }
        const int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
        fd_ = fd;
        ::freeaddrinfo(res);
        return Status::ok();
    }
    ::freeaddrinfo(res);
    return last;
}

Result<std::size_t> TcpStream::read(std::span<std::uint8_t> buffer, TimeNs timeout) {
    if (fd_ < 0) return Status(StatusCode::kDisconnected, describe() + ": not connected");
    const int w = waitFor(fd_, POLLIN, timeout);
    if (w == 0) return std::size_t{0};
    if (w < 0) return Status(StatusCode::kIoError, describe() + ": poll: " + errnoText(errno));
    for (;;) {
        const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
        if (n > 0) return static_cast<std::size_t>(n);
        if (n == 0) {
            close();
            return Status(StatusCode::kDisconnected,
                          describe() + ": connection closed by the peer");
        }
        if (errno == EINTR) continue;
        if (errno == EAGAIN || errno == EWOULDBLOCK) return std::size_t{0};
        const int e = errno;
        close();
        return Status(StatusCode::kDisconnected, describe() + ": recv: " + errnoText(e));
    }
}

Status TcpStream::writeAll(std::span<const std::uint8_t> data, TimeNs timeout) {
    if (fd_ < 0) return Status(StatusCode::kDisconnected, describe() + ": not connected");
    const TimeNs deadline = monotonicNow() + timeout;
    std::size_t done = 0;
    while (done < data.size()) {
        const ssize_t n = ::send(fd_, data.data() + done, data.size() - done, MSG_NOSIGNAL);
        if (n > 0) {
            done += static_cast<std::size_t>(n);
            continue;
        }
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
            const TimeNs left = deadline - monotonicNow();
            if (left <= 0 || waitFor(fd_, POLLOUT, left) == 0) {
                return Status(StatusCode::kTimeout, describe() + ": peer did not take " +
                                                        std::to_string(data.size() - done) +
                                                        " bytes within the write timeout");
            }
            continue;
        }
        const int e = errno;
        close();
        return Status(StatusCode::kDisconnected, describe() + ": send: " + errnoText(e));
    }
    return Status::ok();
}

// --- listener ----------------------------------------------------------------------------------

TcpListener::~TcpListener() { close(); }

void TcpListener::close() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
}

std::string TcpListener::describe() const {
    return "tcp listener " + address_ + ":" + std::to_string(port_);
}

Status TcpListener::listen(const std::string& address, int port) {
    close();
    address_ = address;
    port_ = port;
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(static_cast<std::uint16_t>(port));
    if (::inet_pton(AF_INET, address.c_str(), &sa.sin_addr) != 1) {
        return Status(StatusCode::kInvalidArgument, describe() + ": not an IPv4 address");
    }
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) return Status(StatusCode::kIoError, describe() + ": socket(): " + errnoText(errno));
    const int one = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd, reinterpret_cast<sockaddr*>(&sa), sizeof sa) < 0 || ::listen(fd, 4) < 0) {
        const int e = errno;
        ::close(fd);
        return Status(StatusCode::kIoError, describe() + ": bind/listen: " + errnoText(e));
    }
    socklen_t len = sizeof sa;
    ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
    port_ = ntohs(sa.sin_port);
    fd_ = fd;
    return Status::ok();
}

Result<std::unique_ptr<TcpStream>> TcpListener::accept(TimeNs timeout) {
    if (fd_ < 0) return Status(StatusCode::kDisconnected, describe() + ": not listening");
    const int w = waitFor(fd_, POLLIN, timeout);
    if (w == 0) return std::unique_ptr<TcpStream>{};
    if (w < 0) return Status(StatusCode::kIoError, describe() + ": poll: " + errnoText(errno));
    sockaddr_in peer{};
    socklen_t len = sizeof peer;
    const int fd =
        ::accept4(fd_, reinterpret_cast<sockaddr*>(&peer), &len, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) {
        if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)
            return std::unique_ptr<TcpStream>{};
        return Status(StatusCode::kIoError, describe() + ": accept: " + errnoText(errno));
    }
    const int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    char ip[INET_ADDRSTRLEN] = {};
    ::inet_ntop(AF_INET, &peer.sin_addr, ip, sizeof ip);
    return TcpStream::adopt(fd, std::string(ip) + ":" + std::to_string(ntohs(peer.sin_port)));
}

}  // namespace handscan::transport
