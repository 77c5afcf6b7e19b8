// The recording tap: a driver hands every raw byte chunk it receives from its device (TCP payload,
// serial bytes, CAN frame, image buffer) to a RawTap with the host receive time, before decoding,
// so that recordings hold exactly what the device sent. The recorder implements it; drivers only
// see this interface. Implementations must be cheap and non-blocking (called on driver threads).
#pragma once

#include <cstdint>
#include <span>

#include "handscan/core/time.hpp"

namespace handscan {

class RawTap {
public:
    virtual ~RawTap() = default;
    virtual void onRaw(TimeNs t_host_rx, std::span<const std::uint8_t> bytes) = 0;
};

}  // namespace handscan
