#include "handscan/transport/socketcan.hpp"

#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace handscan::transport {
namespace {

static_assert(CAN_EFF_FLAG == kCanEffFlag && CAN_RTR_FLAG == kCanRtrFlag &&
              CAN_ERR_FLAG == kCanErrFlag);
static_assert(CAN_SFF_MASK == kCanSffMask && CAN_EFF_MASK == kCanEffMask &&
              CAN_RAW_FILTER_MAX == kCanMaxFilters);

std::string errnoText(int e) { return std::strerror(e); }

CanFrame fromKernel(const canfd_frame& k, bool fd) {
    CanFrame f;
    f.extended = (k.can_id & CAN_EFF_FLAG) != 0;
    f.remote = !fd && (k.can_id & CAN_RTR_FLAG) != 0;
    f.error = (k.can_id & CAN_ERR_FLAG) != 0;
    f.id = f.error      ? (k.can_id & CAN_ERR_MASK)
           : f.extended ? (k.can_id & CAN_EFF_MASK)
                        : (k.can_id & CAN_SFF_MASK);
    f.fd = fd;
    f.len = k.len;
    if (fd) {
        f.fd_flags = k.flags;
    } else {
        const auto* c = reinterpret_cast<const can_frame*>(&k);
        if (c->len == CAN_MAX_DLEN && c->len8_dlc > CAN_MAX_DLEN) f.len8_dlc = c->len8_dlc;
    }
    std::memcpy(f.data.data(), k.data, f.len);
    return f;
}

}  // namespace

SocketCanBus::SocketCanBus(std::string interface) : interface_(std::move(interface)) {}
SocketCanBus::~SocketCanBus() { close(); }

void SocketCanBus::close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

Status SocketCanBus::open() {
    close();
    const int fd = ::socket(PF_CAN, SOCK_RAW, CAN_RAW);
    if (fd < 0) {
        const int e = errno;
        return {StatusCode::kUnsupported,
                "socketcan: socket(PF_CAN, SOCK_RAW, CAN_RAW) failed: " + errnoText(e) +
                    " (kernel without CAN support? modprobe can-raw)"};
    }
    ifreq ifr{};
    if (interface_.size() >= IFNAMSIZ) {
        ::close(fd);
        return {StatusCode::kInvalidArgument,
                "socketcan: interface name '" + interface_ + "' longer than 15 characters"};
    }
    std::strncpy(ifr.ifr_name, interface_.c_str(), IFNAMSIZ - 1);
    if (::ioctl(fd, SIOCGIFINDEX, &ifr) < 0) {
        const int e = errno;
        ::close(fd);
        return {StatusCode::kNotFound, "socketcan: no CAN interface '" + interface_ +
                                           "': " + errnoText(e) + " (ip link set " + interface_ +
                                           " up type can bitrate 1000000)"};
    }
    sockaddr_can addr{};
    addr.can_family = AF_CAN;
    addr.can_ifindex = ifr.ifr_ifindex;
    if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) < 0) {
        const int e = errno;
        ::close(fd);
        return {StatusCode::kIoError,
                "socketcan: bind to " + interface_ + " failed: " + errnoText(e)};
    }
    const int on = 1;
    fd_frames_ = ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_FD_FRAMES, &on, sizeof on) == 0;
    const can_err_mask_t err_mask =
        CAN_ERR_TX_TIMEOUT | CAN_ERR_CRTL | CAN_ERR_BUSOFF | CAN_ERR_RESTARTED;
    (void)::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &err_mask,
                       sizeof err_mask);  // best effort
    fd_ = fd;
    if (Status s = applyFilters(); !s) {
        close();
        return s;
    }
    return Status::ok();
}

Status SocketCanBus::setReceiveOwnMessages(bool on) {
    if (fd_ < 0) return {StatusCode::kDisconnected, describe() + " is not open"};
    const int v = on ? 1 : 0;
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_RECV_OWN_MSGS, &v, sizeof v) < 0) {
        return {StatusCode::kIoError,
                describe() + ": CAN_RAW_RECV_OWN_MSGS failed: " + errnoText(errno)};
    }
    return Status::ok();
}

Status SocketCanBus::setFilters(std::span<const CanFilter> filters) {
    if (filters.size() > kCanMaxFilters) {
        return {StatusCode::kInvalidArgument, describe() + ": " + std::to_string(filters.size()) +
                                                  " filters, the kernel takes at most 512"};
    }
    filters_.assign(filters.begin(), filters.end());
    return fd_ >= 0 ? applyFilters() : Status::ok();
}

Status SocketCanBus::applyFilters() {
    std::vector<can_filter> k;
    if (filters_.empty()) {
        k.push_back({0, 0});  // everything, as after socket()
    }
    for (const CanFilter& f : filters_) {
        k.push_back({f.id | (f.inverted ? CAN_INV_FILTER : 0u), f.mask});
    }
    if (::setsockopt(fd_, SOL_CAN_RAW, CAN_RAW_FILTER, k.data(),
                     static_cast<socklen_t>(k.size() * sizeof(can_filter))) < 0) {
        return {StatusCode::kIoError,
                describe() + ": setsockopt(CAN_RAW_FILTER) failed: " + errnoText(errno)};
    }
    return Status::ok();
}

Result<TimedCanFrame> SocketCanBus::receive(TimeNs timeout) {
    if (fd_ < 0) return Status(StatusCode::kDisconnected, describe() + " is not open");
    pollfd p{fd_, POLLIN, 0};
    const int ms = timeout <= 0 ? 0 : static_cast<int>((timeout + kNsPerMs - 1) / kNsPerMs);
    const int n = ::poll(&p, 1, ms);
    if (n == 0) return Status(StatusCode::kTimeout, "no frame");
    if (n < 0) {
        if (errno == EINTR) return Status(StatusCode::kTimeout, "interrupted");
        return Status(StatusCode::kIoError, describe() + ": poll failed: " + errnoText(errno));
    }
    if (p.revents & (POLLERR | POLLHUP | POLLNVAL)) {
        return Status(StatusCode::kDisconnected, describe() + ": interface went down");
    }
    canfd_frame k{};
    const ssize_t got = ::read(fd_, &k, sizeof k);
    const TimeNs t = monotonicNow();
    if (got < 0) {
        const int e = errno;
        if (e == ENETDOWN || e == ENODEV)
            return Status(StatusCode::kDisconnected, describe() + ": " + errnoText(e));
        return Status(StatusCode::kIoError, describe() + ": read failed: " + errnoText(e));
    }
    if (got != static_cast<ssize_t>(CAN_MTU) && got != static_cast<ssize_t>(CANFD_MTU)) {
        return Status(StatusCode::kProtocolError,
                      describe() + ": short read of " + std::to_string(got) + " bytes");
    }
    return TimedCanFrame{t, fromKernel(k, got == static_cast<ssize_t>(CANFD_MTU))};
}

Status SocketCanBus::send(const CanFrame& f) {
    if (fd_ < 0) return {StatusCode::kDisconnected, describe() + " is not open"};
    if (f.fd && !fd_frames_)
        return {StatusCode::kUnsupported, describe() + ": interface does not take CAN FD frames"};
    canfd_frame k{};
    k.can_id = canIdWithFlags(f);
    if (f.fd) k.can_id &= ~CAN_RTR_FLAG;
    k.len = f.len > (f.fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN) ? (f.fd ? CANFD_MAX_DLEN : CAN_MAX_DLEN)
                                                           : f.len;
    if (f.fd) {
        k.flags = f.fd_flags;
    } else if (f.len8_dlc > CAN_MAX_DLEN && k.len == CAN_MAX_DLEN) {
        reinterpret_cast<can_frame*>(&k)->len8_dlc = f.len8_dlc;
    }
    std::memcpy(k.data, f.data.data(), k.len);
    const std::size_t size = f.fd ? CANFD_MTU : CAN_MTU;
    const ssize_t put = ::write(fd_, &k, size);
    if (put != static_cast<ssize_t>(size)) {
        const int e = errno;
        if (e == ENOBUFS)
            return {StatusCode::kNoSpace,
                    describe() + ": transmit queue full (bus off or no ACK from any node?)"};
        return {StatusCode::kIoError, describe() + ": write failed: " + errnoText(e)};
    }
    return Status::ok();
}

}  // namespace handscan::transport
