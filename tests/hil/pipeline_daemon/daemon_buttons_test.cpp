// Every device absent (nothing on the laser's port, no serial port, no CAN interface, no video
// nodes): each one is reported in the status block with what failed and where, the daemon keeps
// running, and the panel's buttons (a fake GPIO line layer: the one device here) still start and
// stop a scan and export through the same commands as the touch screen, with the LEDs following.
#include <gtest/gtest.h>

#include <fstream>
#include <thread>

#include "daemon_rig.hpp"
#include "handscan/gpio/fake_gpio_chip.hpp"
#include "handscan/pipeline_daemon/pipeline_daemon.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon::test {
namespace {

// Hands the daemon a chip that forwards to the test's fake (which outlives the daemon's panel).
class ForwardingChip final : public gpio::GpioChip {
public:
    explicit ForwardingChip(gpio::FakeGpioChip& fake) : fake_(fake) {}
    Result<std::unique_ptr<gpio::GpioInput>> requestInput(unsigned offset,
                                                          const gpio::InputRequest& r) override {
        return fake_.requestInput(offset, r);
    }
    Result<std::unique_ptr<gpio::GpioOutput>> requestOutput(unsigned offset, bool active_low,
                                                            bool on) override {
        return fake_.requestOutput(offset, active_low, on);
    }
    Result<std::vector<std::size_t>> waitAny(std::span<gpio::GpioInput* const> inputs,
                                             TimeNs timeout) override {
        return fake_.waitAny(inputs, timeout);
    }
    TimeNs now() const override { return fake_.now(); }
    std::string describe() const override { return fake_.describe(); }

private:
    gpio::FakeGpioChip& fake_;
};

class LinksWithFakeGpio final : public DeviceLinks {
public:
    explicit LinksWithFakeGpio(gpio::FakeGpioChip& fake) : fake_(fake) {}
    std::unique_ptr<transport::ByteStream> hokuyo(const HokuyoConfig& c) override {
        return linux_->hokuyo(c);
    }
    Result<xsens::XsensLink> xsens(const XsensConfig& c) override { return linux_->xsens(c); }
    Result<CanLink> can(const MotorConfig& c) override { return linux_->can(c); }
    std::unique_ptr<transport::V4l2Device> camera(const CameraConfig& c) override {
        return linux_->camera(c);
    }
    Result<std::unique_ptr<gpio::GpioChip>> gpioChip(const GpioConfig&) override {
        return std::unique_ptr<gpio::GpioChip>(std::make_unique<ForwardingChip>(fake_));
    }

private:
    std::unique_ptr<DeviceLinks> linux_ = makeLinuxDeviceLinks();
    gpio::FakeGpioChip& fake_;
};

TEST(PipelineDaemonDevices, AbsentDevicesReportedButtonsStillScan) {
    RigDevices devices;
    devices.hokuyo = false;
    devices.xsens = false;
    devices.can_interface = "hscan-absent0";
    devices.tracking_camera = "/dev/handscan-no-such-video0";
    devices.colour_camera = "/dev/handscan-no-such-video1";
    DaemonRig rig("buttons", devices);

    // The scan button (line 17, active low: pressed = logical 1) pressed at 1.0 s and 3.0 s of
    // the chip's clock, which the panel thread advances at wall-clock pace.
    gpio::FakeGpioChip chip;
    for (TimeNs t : {1 * kNsPerSec, 3 * kNsPerSec}) {
        chip.inject(17, t, GpioEdgeType::kRising);
        chip.inject(17, t + 150 * kNsPerMs, GpioEdgeType::kFalling);
    }
    // The export button (line 27) at 4.5 s: to the USB stick, of which there is none.
    chip.inject(27, 4500 * kNsPerMs, GpioEdgeType::kRising);
    chip.inject(27, 4650 * kNsPerMs, GpioEdgeType::kFalling);
    std::ofstream(rig.dir() / "mountinfo") << "";
    DaemonOptions o;
    o.usb_paths.mountinfo = (rig.dir() / "mountinfo").string();
    o.device_config = rig.deviceYaml();
    o.calibration = DaemonRig::calibrationYaml();
    o.shm_name = rig.shmName();
    o.map_capacity_points = 1 << 16;
    PipelineDaemon daemon(o, std::make_unique<LinksWithFakeGpio>(chip));
    ASSERT_TRUE(daemon.open().isOk());
    DaemonThread running(daemon);

    // Each absent device: not connected, with an error naming it.
    const std::vector<std::pair<std::string, std::string>> expected = {
        {"hokuyo", "127.0.0.1"},
        {"xsens", "no-such-tty"},
        {"encoder", "hscan-absent0"},
        {"tracking-cam", "/dev/handscan-no-such-video0"},
        {"colour-cam", "/dev/handscan-no-such-video1"}};
    auto reported = rig.waitStatus(
        [&](const shm::StatusBlock& s) {
            for (const auto& [name, where] : expected) {
                const shm::SensorStatus* x = findSensor(s, name);
                if (!x || x->connected ||
                    std::string(shm::getText(x->last_error)).find(where) == std::string::npos)
                    return false;
            }
            return true;
        },
        8.0);
    std::optional<shm::StatusBlock> last;
    rig.ui().poll();
    last = rig.ui().readStatus();
    ASSERT_TRUE(reported) << "not every absent device is reported; last status: "
                          << (last ? [&] {
                                 std::string all;
                                 for (std::uint32_t i = 0; i < last->sensor_count; ++i) {
                                     all += std::string(shm::getText(last->sensors[i].name)) + ": " +
                                            std::string(shm::getText(last->sensors[i].last_error)) + "; ";
                                 }
                                 return all;
                             }()
                                : std::string("none"));
    EXPECT_TRUE(sensorConnected(*reported, "buttons"));

    // The button starts the scan, the second press stops it.
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kScanning);
        },
        6.0))
        << "the scan button did not start a scan";
    EXPECT_EQ(rig.scanDirs().size(), 1u);
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kStopped);
        },
        6.0))
        << "the second press did not stop the scan";

    // The export button takes the same path as the UI's export to USB: here, a clear failure.
    auto exported = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.export_status.state == static_cast<std::uint8_t>(shm::ExportState::kFailed);
        },
        6.0);
    ASSERT_TRUE(exported) << "the export button did not start an export";
    EXPECT_NE(std::string(shm::getText(exported->export_status.message)).find("no USB stick"),
              std::string::npos)
        << shm::getText(exported->export_status.message);

    // The daemon still answers the UI.
    EXPECT_EQ(rig.command(shm::CommandType::kNewScan).state,
              static_cast<std::uint32_t>(shm::CommandState::kDone));
    const Status result = running.stop();
    EXPECT_TRUE(result.isOk()) << result.message();

    // LEDs: scanning lit while scanning, fault blinking (devices missing).
    bool scanning_led = false, fault_led = false;
    for (const auto& w : chip.writes()) {
        if (w.line == 6 && w.on) scanning_led = true;
        if (w.line == 13 && w.on) fault_led = true;
    }
    EXPECT_TRUE(scanning_led);
    EXPECT_TRUE(fault_led);
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
