#include "handscan/pipeline_daemon/device_links.hpp"

#include <cmath>
#include <string_view>

#include "handscan/camera/replay_v4l2_device.hpp"
#include "handscan/motor/motor_setup.hpp"
#include "handscan/motor/paced_can_bus.hpp"
#include "handscan/motor/virtual_can_buses.hpp"
#include "handscan/transport/socketcan.hpp"
#include "handscan/transport/tcp_stream.hpp"

namespace handscan::pipeline_daemon {
namespace {

constexpr std::string_view kCandumpPrefix = "candump:";
constexpr std::string_view kCandumpHostClockPrefix = "candump-host-clock:";
// Recorded camera frames on the host clock (camera/timed_frame_file.hpp), as `handscan hil`
// plays them: the camera's real start-up and buffer handling over a V4L2 device without a kernel.
constexpr std::string_view kV4l2ReplayHostClockPrefix = "v4l2-replay-host-clock:";

// A candump log played at its pace: from its first frame on (`host_clock` false) or at the host
// CLOCK_MONOTONIC times its lines carry (`host_clock` true).
Result<CanLink> candumpLink(const std::string& path, bool host_clock) {
    auto log = motor::CandumpLogBus::openFile(path);
    if (!log.isOk()) return log.status();
    struct Replay {
        std::unique_ptr<motor::CandumpLogBus> log;
        std::unique_ptr<motor::PacedCanBus> paced;
    };
    auto owner = std::make_shared<Replay>();
    owner->log = std::move(*log);
    owner->paced = std::make_unique<motor::PacedCanBus>(
        *owner->log, [l = owner->log.get()] { return l->now(); });
    if (host_clock) {
        // A frame is received when it is sent: those logged before this (re)connection are gone,
        // as on a bus (a restart after the end of the log plays nothing again).
        owner->log->skipBefore(monotonicNow() - 100 * kNsPerMs);
        owner->paced->setOffset(0);
    }
    std::shared_ptr<transport::CanBus> bus(owner, owner->paced.get());
    return CanLink{bus, [owner] { return owner->paced->now(); }};
}

// A virtual bus with its emulated nodes, paced to the wall clock; owns everything it uses.
class EmulatedMotorBus {
public:
    explicit EmulatedMotorBus(const MotorConfig& c)
        : nodes_(c), paced_(nodes_.bus(), [this] { return nodes_.bus().now(); }) {}
    motor::PacedCanBus& paced() { return paced_; }

private:
    motor::EmulatedMotorNodes nodes_;
    motor::PacedCanBus paced_;
};

class LinuxDeviceLinks final : public DeviceLinks {
public:
    std::unique_ptr<transport::ByteStream> hokuyo(const HokuyoConfig& c) override {
        return std::make_unique<transport::TcpStream>(c.host, c.port,
                                                      fromSeconds(c.connect_timeout_s));
    }
    Result<xsens::XsensLink> xsens(const XsensConfig& c) override {
        return xsens::makeXsensLink(c);
    }
    Result<CanLink> can(const MotorConfig& c) override {
        if (c.can_interface == "emulated") {
            auto owner = std::make_shared<EmulatedMotorBus>(c);
            std::shared_ptr<transport::CanBus> bus(owner, &owner->paced());
            return CanLink{bus, [owner] { return owner->paced().now(); }};
        }
        const std::string_view name = c.can_interface;
        if (name.starts_with(kCandumpHostClockPrefix))
            return candumpLink(std::string(name.substr(kCandumpHostClockPrefix.size())), true);
        if (name.starts_with(kCandumpPrefix))
            return candumpLink(std::string(name.substr(kCandumpPrefix.size())), false);
        return CanLink{std::make_shared<transport::SocketCanBus>(c.can_interface), monotonicNow};
    }
    std::unique_ptr<transport::V4l2Device> camera(const CameraConfig& c) override {
        const std::string_view name = c.device;
        if (name.starts_with(kV4l2ReplayHostClockPrefix)) {
            const transport::V4l2Fraction interval{
                1000, static_cast<std::uint32_t>(std::lround(c.fps * 1000.0))};
            return camera::openHostClockReplay(
                std::string(name.substr(kV4l2ReplayHostClockPrefix.size())), interval);
        }
        return transport::makeLinuxV4l2Device(c.device);
    }
    Result<std::unique_ptr<gpio::GpioChip>> gpioChip(const GpioConfig& c) override {
        return gpio::openGpiodChip(c.chip, "handscan-pipeline");
    }
};

}  // namespace

std::unique_ptr<DeviceLinks> makeLinuxDeviceLinks() { return std::make_unique<LinuxDeviceLinks>(); }

}  // namespace handscan::pipeline_daemon
