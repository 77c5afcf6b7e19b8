// `handscan config check`: validates the device and calibration files before a scan.
#include <filesystem>
#include <iostream>

#include "command_registry.hpp"
#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"

namespace handscan::cli {
namespace {

const RegisterCommand kConfig{
    "config", "Check configuration and calibration files", [](CLI::App& sub) {
        auto device = std::make_shared<std::string>();
        auto calibration = std::make_shared<std::string>();
        CLI::App* check = sub.add_subcommand(
            "check", "Validate device.yaml and calibration.yaml (exit 2 on the first error)");
        sub.require_subcommand(1);
        check->add_option("--device", *device,
                          "device configuration (default: <config dir>/device.yaml)");
        check->add_option("--calibration", *calibration,
                          "calibration (default: <config dir>/calibration.yaml)");
        return std::function<int()>([device, calibration] {
            const std::string dir = defaultConfigDir();
            const std::string dev = device->empty() ? dir + "/device.yaml" : *device;
            const std::string cal = calibration->empty() ? dir + "/calibration.yaml" : *calibration;
            const DeviceConfig d = loadDeviceConfig(dev);
            const Calibration c = loadCalibration(cal);
            std::cout << dev << ": ok (hokuyo " << d.hokuyo.host << ":" << d.hokuyo.port
                      << ", xsens " << d.xsens.transport << " " << d.xsens.rate_hz << " Hz, CAN "
                      << d.motor.can_interface << ")\n";
            std::cout << cal << ": ok (tracking camera " << c.tracking.resolution[0] << "x"
                      << c.tracking.resolution[1] << " " << c.tracking.distortion_model << ")\n";
            return 0;
        });
    }};

}  // namespace
}  // namespace handscan::cli
