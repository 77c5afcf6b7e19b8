// DeviceLinks: where the daemon gets each device's transport. The Linux implementation builds
// the real ones from device.yaml (TCP to the Hokuyo, serial/USB to the Xsens, SocketCAN, V4L2
// nodes, a gpiod chip); tests substitute what the kernel here cannot provide. The protocol code
// above is the same either way.
//
// motor.can_interface also takes two transports that need no CAN hardware:
//   "emulated"        a CiA 406 encoder (and CiA 402 drive) emulated on a virtual bus, spinning
//                     at motor.target_speed_rev_s, paced to the wall clock (desk demos, tests)
//   "candump:FILE"    a recorded candump -l log played back at its recorded pace
//   "candump-host-clock:FILE"  a candump log whose times are host CLOCK_MONOTONIC (written by
//                     `handscan hil`): each frame arrives at its own time, frames due at once
#pragma once

#include <functional>
#include <memory>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/gpio/gpio_lines.hpp"
#include "handscan/transport/byte_stream.hpp"
#include "handscan/transport/can_bus.hpp"
#include "handscan/transport/v4l2_device.hpp"
#include "handscan/xsens/xsens_driver.hpp"

namespace handscan::pipeline_daemon {

// A CAN link and the clock its frames are stamped on (host monotonic for real buses).
struct CanLink {
    std::shared_ptr<transport::CanBus> bus;
    std::function<TimeNs()> now;
};

class DeviceLinks {
public:
    virtual ~DeviceLinks() = default;
    virtual std::unique_ptr<transport::ByteStream> hokuyo(const HokuyoConfig& config) = 0;
    virtual Result<xsens::XsensLink> xsens(const XsensConfig& config) = 0;
    virtual Result<CanLink> can(const MotorConfig& config) = 0;
    virtual std::unique_ptr<transport::V4l2Device> camera(const CameraConfig& config) = 0;
    virtual Result<std::unique_ptr<gpio::GpioChip>> gpioChip(const GpioConfig& config) = 0;
};

std::unique_ptr<DeviceLinks> makeLinuxDeviceLinks();

}  // namespace handscan::pipeline_daemon
