// The motor's device.yaml section (handscan::MotorConfig) turned into what the driver and its
// emulated nodes take: the MotorDevice configuration the daemon runs, and the CiA 406 encoder /
// CiA 402 drive emulators that answer it without hardware ("emulated" bus, `handscan hil`).
#pragma once

#include "handscan/core/config.hpp"
#include "handscan/motor/motor_device.hpp"
#include "handscan/motor/node_emulators.hpp"
#include "handscan/motor/virtual_can_buses.hpp"

namespace handscan::motor {

MotorConfig motorDeviceConfig(const handscan::MotorConfig& c);

// An emulated bus with the encoder (spinning at target_speed_rev_s) and, when configured, the
// drive on it; on a virtual clock starting at `start`.
class EmulatedMotorNodes {
public:
    explicit EmulatedMotorNodes(const handscan::MotorConfig& c, TimeNs start = 0);
    EmulatedMotorNodes(const EmulatedMotorNodes&) = delete;
    EmulatedMotorNodes& operator=(const EmulatedMotorNodes&) = delete;
    EmulatedCanBus& bus() { return bus_; }

private:
    EmulatedCanBus bus_;
    Cia406EncoderEmulator encoder_;
    Cia402DriveEmulator drive_;
};

}  // namespace handscan::motor
