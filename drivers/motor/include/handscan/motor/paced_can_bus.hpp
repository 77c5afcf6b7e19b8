// PacedCanBus: runs a bus that lives on a virtual clock (EmulatedCanBus, CandumpLogBus) at wall-
// clock pace on the host's CLOCK_MONOTONIC, so the live daemon can take its encoder from an
// emulated CiA 406 node or from a recorded candump log exactly as from SocketCAN: frames arrive
// when they are due and carry host receive times. The virtual clock is anchored to the host
// clock at the first receive().
#pragma once

#include <functional>

#include "handscan/transport/can_bus.hpp"

namespace handscan::motor {

class PacedCanBus final : public transport::CanBus {
public:
    // `inner` must outlive this; `inner_now` reads its virtual clock.
    PacedCanBus(transport::CanBus& inner, std::function<TimeNs()> inner_now)
        : inner_(inner), inner_now_(std::move(inner_now)) {}

    // The paced clock (host monotonic once anchored); the MotorDevice's clock.
    TimeNs now() const;
    // Fixes the anchor instead of taking it at the first receive(): host time = virtual time +
    // `host_minus_virtual` (0 for a log whose times are host CLOCK_MONOTONIC already, as
    // `handscan hil` writes them: each frame arrives at its own time, frames already due at once).
    void setOffset(TimeNs host_minus_virtual) {
        offset_ = host_minus_virtual;
        anchored_ = true;
    }

    Status open() override { return inner_.open(); }
    void close() override { inner_.close(); }
    bool isOpen() const override { return inner_.isOpen(); }
    Status setFilters(std::span<const CanFilter> filters) override {
        return inner_.setFilters(filters);
    }
    Result<TimedCanFrame> receive(TimeNs timeout) override;
    Status send(const CanFrame& frame) override { return inner_.send(frame); }
    std::string describe() const override { return inner_.describe() + " (paced)"; }

private:
    void anchor();

    transport::CanBus& inner_;
    std::function<TimeNs()> inner_now_;
    bool anchored_ = false;
    TimeNs offset_ = 0;  // host time - virtual time
};

}  // namespace handscan::motor
