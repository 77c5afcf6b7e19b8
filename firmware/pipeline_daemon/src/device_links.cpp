#include "handscan/pipeline_daemon/device_links.hpp"

#include <numbers>

#include "handscan/motor/paced_can_bus.hpp"
#include "handscan/motor/virtual_can_buses.hpp"
#include "handscan/transport/socketcan.hpp"
#include "handscan/transport/tcp_stream.hpp"

namespace handscan::pipeline_daemon {
namespace {

constexpr const char* kCandumpPrefix = "candump:";

// A virtual bus with its emulated nodes, paced to the wall clock; owns everything it uses.
class EmulatedMotorBus {
public:
    explicit EmulatedMotorBus(const MotorConfig& c)
        : encoder_(encoderConfig(c)),
          drive_(driveConfig(c)),
          paced_(bus_, [this] { return bus_.now(); }) {
        bus_.addNode(&encoder_);
        if (c.drive_node_id > 0) bus_.addNode(&drive_);
    }
    motor::PacedCanBus& paced() { return paced_; }

private:
    static motor::EncoderEmulatorConfig encoderConfig(const MotorConfig& c) {
        motor::EncoderEmulatorConfig e;
        e.node = static_cast<std::uint8_t>(c.encoder_node_id);
        e.units_per_revolution = static_cast<std::uint32_t>(c.encoder_counts_per_rev);
        e.total_range = e.units_per_revolution;  // single-turn, as ours
        e.speed_radps = 2.0 * std::numbers::pi * c.target_speed_rev_s;
        return e;
    }
    static motor::DriveEmulatorConfig driveConfig(const MotorConfig& c) {
        motor::DriveEmulatorConfig d;
        d.node = static_cast<std::uint8_t>(c.drive_node_id > 0 ? c.drive_node_id : 2);
        return d;
    }

    motor::EmulatedCanBus bus_;
    motor::Cia406EncoderEmulator encoder_;
    motor::Cia402DriveEmulator drive_;
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
        if (c.can_interface.rfind(kCandumpPrefix, 0) == 0) {
            auto log = motor::CandumpLogBus::openFile(
                c.can_interface.substr(std::string(kCandumpPrefix).size()));
            if (!log.isOk()) return log.status();
            struct Replay {
                std::unique_ptr<motor::CandumpLogBus> log;
                std::unique_ptr<motor::PacedCanBus> paced;
            };
            auto owner = std::make_shared<Replay>();
            owner->log = std::move(*log);
            owner->paced = std::make_unique<motor::PacedCanBus>(
                *owner->log, [l = owner->log.get()] { return l->now(); });
            std::shared_ptr<transport::CanBus> bus(owner, owner->paced.get());
            return CanLink{bus, [owner] { return owner->paced->now(); }};
        }
        return CanLink{std::make_shared<transport::SocketCanBus>(c.can_interface), monotonicNow};
    }
    std::unique_ptr<transport::V4l2Device> camera(const CameraConfig& c) override {
        return transport::makeLinuxV4l2Device(c.device);
    }
    Result<std::unique_ptr<gpio::GpioChip>> gpioChip(const GpioConfig& c) override {
        return gpio::openGpiodChip(c.chip, "handscan-pipeline");
    }
};

}  // namespace

std::unique_ptr<DeviceLinks> makeLinuxDeviceLinks() { return std::make_unique<LinuxDeviceLinks>(); }

}  // namespace handscan::pipeline_daemon
