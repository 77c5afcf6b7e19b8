// SocketCAN raw socket (Linux): socket(PF_CAN, SOCK_RAW, CAN_RAW) bound to an interface, kernel
// receive filters (CAN_RAW_FILTER), CAN FD frames enabled when the interface supports them, error
// frames delivered. Frames are timestamped with CLOCK_MONOTONIC on reception.
// Kernels without CAN support make open() fail with kUnsupported (tests skip on that).
#pragma once

#include <string>
#include <vector>

#include "handscan/transport/can_bus.hpp"

namespace handscan::transport {

class SocketCanBus final : public CanBus {
public:
    explicit SocketCanBus(std::string interface);
    ~SocketCanBus() override;
    SocketCanBus(const SocketCanBus&) = delete;
    SocketCanBus& operator=(const SocketCanBus&) = delete;

    Status open() override;
    void close() override;
    bool isOpen() const override { return fd_ >= 0; }
    Status setFilters(std::span<const CanFilter> filters) override;
    Result<TimedCanFrame> receive(TimeNs timeout) override;
    Status send(const CanFrame& frame) override;
    std::string describe() const override { return "socketcan " + interface_; }
    // Also deliver the frames this socket sends (CAN_RAW_RECV_OWN_MSGS), for loopback tests.
    Status setReceiveOwnMessages(bool on);

private:
    Status applyFilters();

    std::string interface_;
    int fd_ = -1;
    bool fd_frames_ = false;
    std::vector<CanFilter> filters_;
};

}  // namespace handscan::transport
