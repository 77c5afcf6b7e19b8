#include "daemon_rig.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <numbers>
#include <thread>

namespace handscan::pipeline_daemon::test {
namespace {

using namespace handscan::hokuyo;

// 45 s of UTM-30LX-EW scans (ME, 1081 steps, 25 ms apart) from the middle of a 6 x 4 m room.
std::vector<SourceScanFrame> roomScans() {
    const ScanRequest me{'M', ScanEncoding::kThreeCharWithIntensity, 0, 1080, 1, 0, 0, ""};
    const FakeHokuyoIdentity id;
    std::string raw = encodeReply("SCIP2.0", "0E") + encodeKeyValueReply("VV", "00", id.vv) +
                      encodeKeyValueReply("PP", "00", id.pp) + encodeReply("BM", "00") +
                      encodeScanAck(me);
    ScanPayload p;
    for (int i = 0; i <= 1080; ++i) {
        const double a = (i - 540) * 2.0 * std::numbers::pi / 1440.0;
        const double r = std::min(3.0 / std::max(1e-6, std::abs(std::cos(a))),
                                  2.0 / std::max(1e-6, std::abs(std::sin(a))));
        p.ranges.push_back(static_cast<std::uint32_t>(std::lround(std::min(r, 30.0) * 1000.0)));
        p.intensities.push_back(static_cast<std::uint32_t>(1000 + (i % 7) * 300));
    }
    for (int k = 0; k < 45 * 40; ++k) {
        p.timestamp_ms = (1'000'000u + static_cast<std::uint32_t>(k) * 25u) & 0xFFFFFFu;
        raw += encodeScanFrame(me, p);
    }
    return splitScanFrames(raw);
}

}  // namespace

DaemonRig::DaemonRig(const std::string& name, RigDevices devices) {
    const std::string tag = name + "-" + std::to_string(::getpid());
    dir_ = fs::temp_directory_path() / ("handscan-daemon-" + tag);
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "journal");
    shm_name_ = "/handscan-test-" + tag;

    int hokuyo_port = 1;  // nothing listens there
    if (devices.hokuyo) {
        FakeServerOptions o;
        o.real_pace = true;
        hokuyo_ = std::make_unique<FakeHokuyoServer>(roomScans(), o);
        if (Status s = hokuyo_->start(); !s.isOk()) throw std::runtime_error(s.message());
        hokuyo_port = hokuyo_->port();
    }
    std::string xsens_path = (dir_ / "no-such-tty").string();
    if (devices.xsens) {
        xsens::FakeXsensConfig xc;
        xc.streaming_at_start = true;
        xc.stationary = true;
        xsens_ = std::make_unique<xsens::FakeXsens>(xc);
        pty_ = std::make_unique<xsens::PtyXsens>(*xsens_);
        xsens_path = pty_->slavePath();
    }
    const auto camera = [](const std::string& device, int w, int h, const char* format) {
        return "  enabled: " + std::string(device.empty() ? "false" : "true") +
               "\n  device: " + (device.empty() ? "/dev/null" : device) +
               "\n  width: " + std::to_string(w) + "\n  height: " + std::to_string(h) +
               "\n  fps: 10\n  format: " + format + "\n  exposure_ms: 5.0\n";
    };
    device_yaml_ = (dir_ / "device.yaml").string();
    std::ofstream y(device_yaml_);
    y << "hokuyo:\n  host: 127.0.0.1\n  port: " << hokuyo_port
      << "\n  connect_timeout_s: 0.5\n  reconnect_max_backoff_s: 0.5\n  frame_latency_ms: 1.2\n"
      << "xsens:\n  transport: serial\n  serial_path: " << xsens_path
      << "\n  baud: 921600\n  rate_hz: 200\n  delta_q_v: false\n"
      << "motor:\n  can_interface: " << devices.can_interface
      << "\n  encoder_node_id: 1\n  drive_node_id: 2\n  encoder_counts_per_rev: 16384\n  "
         "tpdo_period_ms: 5\n"
      << "  heartbeat_timeout_s: 0.5\n  target_speed_rev_s: 1.0\n  sweep_boundary: half\n"
      << "tracking_camera:\n"
      << camera(devices.tracking_camera, 640, 512, "GREY") << "colour_camera:\n"
      << camera(devices.colour_camera, 1600, 1200, "YUYV")
      << "gpio:\n  chip: handscan-test-no-such-chip\n  start_button_line: 17\n  "
         "export_button_line: 27\n  led_ready_line: 5\n"
      << "  led_scanning_line: 6\n  led_fault_line: 13\n  led_exporting_line: 19\n  debounce_ms: "
         "20\n"
      << "storage:\n  journal_dir: " << journalDir().string()
      << "\n  recording_dir: " << (dir_ / "rec").string() << "\n  min_free_gib: 0.0\n";
    shm::ReaderOptions ro;
    ro.name = shm_name_;
    reader_ = std::make_unique<shm::LiveMapReader>(ro);
}

DaemonRig::~DaemonRig() {
    reader_.reset();
    pty_.reset();
    if (hokuyo_) hokuyo_->stop();
    std::error_code ec;
    fs::remove_all(dir_, ec);
}

std::string DaemonRig::calibrationYaml() {
    return std::string(HANDSCAN_SOURCE_DIR) + "/config/calibration.yaml";
}

void DaemonRig::killHokuyo() {
    if (hokuyo_) hokuyo_->stop();
}

shm::CommandAck DaemonRig::command(shm::CommandType type, const std::string& argument,
                                   std::vector<shm::CommandState>* seen) {
    return hil::sendCommand(*reader_, type, argument, 20.0, seen);
}

std::optional<shm::StatusBlock> DaemonRig::waitStatus(
    const std::function<bool(const shm::StatusBlock&)>& pred, double timeout_s) {
    return hil::waitForStatus(*reader_, pred, timeout_s);
}

std::vector<fs::path> DaemonRig::scanDirs() const {
    std::vector<fs::path> out;
    for (const auto& e : fs::directory_iterator(journalDir())) {
        if (e.is_directory()) out.push_back(e.path());
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace handscan::pipeline_daemon::test
