// The CANopen master side shared by the encoder and the drive: sends and receives frames over
// an injected transport::CanBus, hands every frame to the recording tap as a candump -l line,
// and runs expedited SDO transfers (request, wait for the matching response or abort, retry on
// timeout) while passing every other frame that arrives meanwhile to the owner's handler, so no
// TPDO is lost during configuration.
#pragma once

#include <functional>
#include <string>

#include "handscan/core/raw_tap.hpp"
#include "handscan/core/status.hpp"
#include "handscan/motor/canopen.hpp"
#include "handscan/transport/can_bus.hpp"

namespace handscan::motor {

using Clock = std::function<TimeNs()>;

class CanOpenMaster {
public:
    using FrameHandler = std::function<void(const TimedCanFrame&)>;

    CanOpenMaster(transport::CanBus& bus, Clock clock, RawTap* tap, std::string interface_name);

    void setFrameHandler(FrameHandler handler) { handler_ = std::move(handler); }
    TimeNs now() const { return clock_(); }
    transport::CanBus& bus() { return bus_; }

    [[nodiscard]] Status send(const CanFrame& frame);
    // One frame (tapped), or kTimeout / kDisconnected.
    [[nodiscard]] Result<TimedCanFrame> receive(TimeNs timeout);
    // Receives and dispatches frames to the handler until `done()` holds or `timeout` passed.
    [[nodiscard]] Status pumpUntil(const std::function<bool()>& done, TimeNs timeout,
                                   const std::string& what);

    // Expedited SDO write / read with `retries` extra attempts after a timeout. An abort is not
    // retried: its code is reported in plain words.
    [[nodiscard]] Status sdoWrite(std::uint8_t node, std::uint16_t index, std::uint8_t sub,
                                  std::uint32_t value, std::uint8_t size, TimeNs timeout,
                                  int retries);
    [[nodiscard]] Result<std::uint32_t> sdoRead(std::uint8_t node, std::uint16_t index,
                                                std::uint8_t sub, TimeNs timeout, int retries);

private:
    Result<SdoMessage> sdoTransfer(const CanFrame& request, SdoKind expect, TimeNs timeout,
                                   int retries);
    void tap(TimeNs t, const CanFrame& frame);

    transport::CanBus& bus_;
    Clock clock_;
    RawTap* tap_;
    std::string interface_;
    FrameHandler handler_;
};

}  // namespace handscan::motor
