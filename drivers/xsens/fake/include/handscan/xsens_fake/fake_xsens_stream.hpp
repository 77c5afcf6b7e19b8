// An in-memory ByteStream with a FakeXsens behind it and a virtual clock: reads advance virtual
// time to the next 200 Hz (or configured rate) packet, so device-state-machine tests run in
// microseconds and are deterministic. Chunks can be cut small to exercise reassembly, and the
// link can be made to drop.
#pragma once

#include <cstddef>
#include <optional>

#include "handscan/transport/byte_stream.hpp"
#include "handscan/xsens_fake/fake_xsens.hpp"

namespace handscan::xsens {

struct VirtualClock {
    TimeNs now = 1000 * kNsPerSec;
};

class FakeXsensStream : public transport::ByteStream {
public:
    FakeXsensStream(FakeXsens& device, VirtualClock& clock) : device_(device), clock_(clock) {}

    Status open() override;
    void close() override { open_ = false; }
    bool isOpen() const override { return open_; }
    Result<std::size_t> read(std::span<std::uint8_t> buffer, TimeNs timeout) override;
    Status writeAll(std::span<const std::uint8_t> data, TimeNs timeout) override;
    std::string describe() const override { return "fake-xsens (in memory)"; }

    // Largest chunk one read() returns (a serial driver hands out arbitrary pieces).
    void setMaxChunk(std::size_t n) { max_chunk_ = n; }
    // After this many more bytes the link drops once (kDisconnected) until open() is called again.
    void disconnectAfter(std::size_t bytes) { disconnect_after_ = bytes; }
    // The host side's line rate (what SerialStream::setBaudrate would set); a mismatch with the
    // device's rate garbles the link.
    Status setLinkBaudrate(int baud) {
        link_baud_ = baud;
        return Status::ok();
    }
    int linkBaudrate() const { return link_baud_; }
    // Constant delay between a packet's sample instant and its arrival at the host.
    void setLatency(TimeNs latency) { latency_ = latency; }

private:
    FakeXsens& device_;
    VirtualClock& clock_;
    std::vector<std::uint8_t> pending_;
    std::size_t max_chunk_ = 4096;
    std::optional<std::size_t> disconnect_after_;
    TimeNs next_packet_ = 0;
    TimeNs latency_ = 2 * kNsPerMs;
    bool open_ = false;
    int link_baud_ = 921600;
};

}  // namespace handscan::xsens
