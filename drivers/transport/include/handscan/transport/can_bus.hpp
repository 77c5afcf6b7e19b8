// A CAN link (SocketCAN raw socket, a candump log file, or a test double). The frame and filter
// types are the plain ones of handscan/core/can_frame.hpp (codecs use them without this header);
// only the SocketCAN transport converts them to and from the kernel structs.
#pragma once

#include <span>
#include <string>

#include "handscan/core/can_frame.hpp"
#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::transport {

// The frame types under their transport names, for the device code written against them.
using handscan::CanFilter;
using handscan::canFilterMatches;
using handscan::CanFrame;
using handscan::canIdWithFlags;
using handscan::exactSffFilter;
using handscan::kCanEffFlag;
using handscan::kCanEffMask;
using handscan::kCanErrFlag;
using handscan::kCanErrMask;
using handscan::kCanFdMaxDataLength;
using handscan::kCanMaxDataLength;
using handscan::kCanMaxFilters;
using handscan::kCanRtrFlag;
using handscan::kCanSffMask;
using handscan::makeCanFrame;
using handscan::TimedCanFrame;

class CanBus {
public:
    virtual ~CanBus() = default;
    virtual Status open() = 0;
    virtual void close() = 0;
    virtual bool isOpen() const = 0;
    // Replaces the receive filters (empty = receive everything).
    virtual Status setFilters(std::span<const CanFilter> filters) = 0;
    // Waits at most `timeout` for one frame. Returns nullopt-like kTimeout status when none
    // arrived, kDisconnected when the link went away (interface down, end of a log file).
    virtual Result<TimedCanFrame> receive(TimeNs timeout) = 0;
    virtual Status send(const CanFrame& frame) = 0;
    // For messages: "socketcan can0", "candump-log /path/file.log".
    virtual std::string describe() const = 0;
};

}  // namespace handscan::transport
