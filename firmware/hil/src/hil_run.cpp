#include "handscan/hil/hil_run.hpp"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "handscan/core/config.hpp"
#include "handscan/hil/command_client.hpp"
#include "handscan/hil/daemon_process.hpp"
#include "handscan/hil/device_yaml.hpp"
#include "handscan/shm/text_field.hpp"
#include "handscan/viz/journal_viz.hpp"
#include "hil_outputs.hpp"

namespace handscan::hil {
namespace {

namespace fs = std::filesystem;

// After a kill -9: when the restarted daemon's encoder start-up is answered (it opens the bus
// within about a second; its boot-up wait lasts 2 s).
constexpr TimeNs kRestartCanStartup = 1500 * kNsPerMs;

// handscan-pipeline next to this program (installed: bin/), or in the build tree's
// firmware/pipeline_daemon/ beside firmware/cli/.
std::string defaultDaemon() {
    std::error_code ec;
    const fs::path self = fs::read_symlink("/proc/self/exe", ec);
    for (const fs::path& p :
         {self.parent_path() / "handscan-pipeline",
          self.parent_path().parent_path() / "pipeline_daemon" / "handscan-pipeline"}) {
        if (fs::exists(p, ec)) return p.string();
    }
    return "handscan-pipeline";
}

Result<std::string> readText(const std::string& path) {
    std::ifstream in(path);
    if (!in) return Status(StatusCode::kNotFound, path + ": cannot read");
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// device.yaml with each device's transport at its fake (or at nothing, when left out).
Result<std::string> hilDeviceYaml(const std::string& source, const RecordingFakes& fakes,
                                  const fs::path& out) {
    std::map<std::string, std::string> v;
    v["hokuyo.host"] = "127.0.0.1";
    v["hokuyo.port"] = std::to_string(fakes.hokuyoPort() > 0 ? fakes.hokuyoPort() : 1);
    v["hokuyo.connect_timeout_s"] = "0.5";
    v["hokuyo.reconnect_max_backoff_s"] = "1.0";
    v["xsens.transport"] = "serial";
    v["xsens.serial_path"] =
        fakes.xsensPath().empty() ? (out / "no-xsens-tty").string() : fakes.xsensPath();
    v["motor.can_interface"] = fakes.candumpPath().empty()
                                   ? "candump:" + (out / "no-can-log").string()
                                   : "candump-host-clock:" + fakes.candumpPath().string();
    // A camera not recorded (or left out) is not there.
    const auto camera = [&](const std::string& section, const std::string& frames) {
        v[section + ".enabled"] = frames.empty() ? "false" : "true";
        if (!frames.empty()) v[section + ".device"] = "v4l2-replay-host-clock:" + frames;
    };
    camera("tracking_camera", fakes.trackFramesPath());
    camera("colour_camera", fakes.colourFramesPath());
    v["gpio.chip"] = "handscan-hil-no-gpio-chip";
    v["storage.journal_dir"] = (out / "journal").string();
    v["storage.recording_dir"] = (out / "recordings").string();
    v["storage.min_free_gib"] = "0.0";
    return overrideYaml(source, v);
}

// The laser streams its pre-roll, so its status says connected. The IMU sends nothing before
// the recording plays, and a sensor without fresh samples is shown lost: its driver's log line
// says when it finished the handshake.
bool connected(const shm::StatusBlock& s, const FakesOptions& f, const fs::path& log) {
    if (f.hokuyo && !sensorConnected(s, "hokuyo")) return false;
    return !f.xsens || logTail(log, 1 << 20).find("xsens: connected") != std::string::npos;
}

void sleepUntil(TimeNs t) {
    const TimeNs left = t - monotonicNow();
    if (left > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(left));
}

// One daemon life: its rusage added to the report when it ends.
struct DaemonRuns {
    DaemonProcess process;
    std::vector<ProcessEnd> ends;
    Status reap(TimeNs timeout, const fs::path& log) {
        auto end = process.wait(timeout);
        if (!end) {
            process.signal(SIGKILL);
            end = process.wait(5 * kNsPerSec);
            if (end) ends.push_back(*end);
            return Status(StatusCode::kTimeout, "handscan-pipeline did not exit within " +
                                                    std::to_string(timeout / kNsPerSec) +
                                                    " s; killed. Log:\n" + logTail(log));
        }
        ends.push_back(*end);
        return Status::ok();
    }
};

}  // namespace

constexpr const char* kEarlierScan = "earlier-scan";  // sorts before the daemon's scan-*

Result<HilReport> runHil(const HilOptions& o) {
    const fs::path out = o.out_dir;
    std::error_code ec;
    fs::remove_all(out / "journal", ec);
    fs::remove_all(out / "export", ec);
    fs::remove_all(out / "export-recovered", ec);
    fs::remove_all(out / "cameras", ec);
    fs::create_directories(out / "journal", ec);
    fs::create_directories(out / "export", ec);
    if (o.kill_at_s) fs::create_directories(out / "export-recovered", ec);
    if (o.fakes.cameras) fs::create_directories(out / "cameras", ec);
    if (ec) return Status(StatusCode::kIoError, out.string() + ": cannot create: " + ec.message());
    if (!o.continue_scan.empty()) {
        // The earlier scan as the daemon keeps its scans: one directory of its journal root.
        const fs::path earlier = out / "journal" / kEarlierScan;
        fs::create_directories(earlier, ec);
        for (const char* f : {"journal.hsj", "feature_map.hsf"}) {
            fs::copy_file(fs::path(o.continue_scan) / f, earlier / f, ec);
            if (ec)
                return Status(StatusCode::kNotFound,
                              "--continue " + o.continue_scan + ": cannot copy " + f + ": " +
                                  ec.message() +
                                  " (give a scan directory of replay or the daemon)");
        }
    }
    auto rec = loadRecordedStreams(o.recording, o.fakes.cameras ? (out / "cameras").string() : "");
    if (!rec.isOk()) return rec.status();
    const std::string config_dir = defaultConfigDir();
    auto device_text =
        readText(o.device_config.empty() ? config_dir + "/device.yaml" : o.device_config);

    if (!device_text.isOk()) return device_text.status();
    const std::string calibration =
        o.calibration.empty() ? config_dir + "/calibration.yaml" : o.calibration;

    // 1. The fakes, holding the recording back until the daemon had time to come up.
    const TimeNs play_at = monotonicNow() + fromSeconds(o.startup_s);
    const TimeNs offset = play_at - rec->start;
    const std::string device_path =
        o.device_config.empty() ? config_dir + "/device.yaml" : o.device_config;
    DeviceConfig device;
    try {
        device = loadDeviceConfig(device_path);
    } catch (const std::exception& e) {
        return Status(StatusCode::kInvalidArgument, e.what());
    }
    FakesOptions fakes_options = o.fakes;
    fakes_options.hokuyo_preroll_s = o.startup_s + 1.0;
    std::unique_ptr<RecordingFakes> fakes;
    try {
        fakes = std::make_unique<RecordingFakes>(*rec, device.motor, offset, out, fakes_options);
    } catch (const std::exception& e) {
        return Status(StatusCode::kIoError, std::string("fake devices: ") + e.what());
    }
    auto yaml = hilDeviceYaml(*device_text, *fakes, out);
    if (!yaml.isOk()) return yaml.status();
    const fs::path device_yaml = out / "device.yaml";
    std::ofstream(device_yaml) << *yaml;

    // 2. The daemon, and the UI's end of its shared memory.
    const std::string shm_name = "/handscan-hil-" + std::to_string(::getpid());
    const fs::path log = out / "daemon.log";
    fs::remove(log, ec);
    std::vector<std::string> argv{o.daemon.empty() ? defaultDaemon() : o.daemon,
                                  "--config",
                                  device_yaml.string(),
                                  "--calibration",
                                  calibration,
                                  "--shm",
                                  shm_name};
    if (!o.field_calibration.empty()) {
        argv.push_back("--field-calibration");
        argv.push_back(o.field_calibration);
    }
    DaemonRuns daemon;
    if (Status s = daemon.process.start(argv, log); !s.isOk()) return s;
    shm::ReaderOptions ro;
    ro.name = shm_name;
    shm::LiveMapReader ui(ro);
    const auto fail = [&](const std::string& what) -> Status {
        daemon.process.signal(SIGKILL);
        (void)daemon.process.wait(5 * kNsPerSec);
        return Status(StatusCode::kDeviceError,
                      what + "\ndaemon log (" + log.string() + "):\n" + logTail(log));
    };

    // 3. Devices open, scan started - before the first recorded byte is due.
    if (!waitForStatus(
            ui, [&](const shm::StatusBlock& s) { return connected(s, o.fakes, log); },
            o.startup_s)) {
        return fail("the daemon did not open the fake devices within --startup " +
                    std::to_string(o.startup_s) + " s");
    }
    const bool continuing = !o.continue_scan.empty();
    const std::string continue_argument =
        std::string("scan=") + kEarlierScan +
        (o.initial_pose.empty() ? std::string() : " pose=" + o.initial_pose);
    const shm::CommandAck started =
        continuing ? sendCommand(ui, shm::CommandType::kContinueScan, continue_argument, 30.0)
                   : sendCommand(ui, shm::CommandType::kStartScan);
    if (started.state != static_cast<std::uint32_t>(shm::CommandState::kDone))
        return fail(std::string(continuing ? "continue scan: " : "start scan: ") +
                    std::string(shm::getText(started.message)));
    if (monotonicNow() > play_at) {
        return fail("the scan started " + std::to_string(toSeconds(monotonicNow() - play_at)) +
                    " s after the recording began to play; raise --startup");
    }

    // 4. The recording plays; a kill -9 on the way if asked for.
    HilReport report;
    report.recording_s = toSeconds(rec->end - rec->start);
    const TimeNs play_end = rec->end + offset;
    // "exported N points to DIR"; N of the export done, or the failure.
    const auto exportScan = [&](const fs::path& to) -> Result<std::uint64_t> {
        const shm::CommandAck exported =
            sendCommand(ui, shm::CommandType::kExport, to.string(), 300.0);
        const std::string message(shm::getText(exported.message));
        if (exported.state != static_cast<std::uint32_t>(shm::CommandState::kDone))
            return fail("export to " + to.string() + ": " + message);
        const auto at = message.find("exported ");
        return at == std::string::npos ? 0 : std::strtoull(message.c_str() + at + 9, nullptr, 10);
    };
    if (o.kill_at_s) {
        sleepUntil(play_at + fromSeconds(*o.kill_at_s));
        daemon.process.signal(SIGKILL);
        if (Status s = daemon.reap(5 * kNsPerSec, log); !s.isOk()) return s;
        // The new daemon's encoder start-up is answered as the first one's: a CAN log whose
        // exchange begins once the daemon had time to open the bus (its boot-up wait is 2 s).
        if (!fakes->candumpPath().empty()) {
            (void)fakes->restartCandump(monotonicNow() + kRestartCanStartup);
            auto again = hilDeviceYaml(*device_text, *fakes, out);
            if (!again.isOk()) return again.status();
            std::ofstream(device_yaml, std::ios::trunc) << *again;
        }
        if (Status s = daemon.process.start(argv, log); !s.isOk()) return s;
        auto back = waitForStatus(
            ui,
            [](const shm::StatusBlock& s) {
                return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kStopped);
            },
            15.0);
        if (!back) return fail("after kill -9 the restarted daemon did not take the scan back");
        report.recovered_after_kill =
            std::string(shm::getText(back->message)).find("recovered") != std::string::npos;
        // As an operator would: export the recovered scan, then scan on (a new scan: the new
        // daemon's map frame is not the recovered one's).
        auto recovered = exportScan(out / "export-recovered");
        if (!recovered.isOk()) return recovered.status();
        report.recovered_export_points = *recovered;
        const shm::CommandAck restarted = sendCommand(ui, shm::CommandType::kStartScan);
        if (restarted.state != static_cast<std::uint32_t>(shm::CommandState::kDone)) {
            return fail(std::string("start scan after the restart: ") +
                        std::string(shm::getText(restarted.message)));
        }
    }
    // + the pipeline's ordering window and a sweep; a continued scan's lock as the UI sees it.
    while (continuing && report.locked_after_s < 0 && monotonicNow() < play_end) {
        ui.poll();
        if (auto s = ui.readStatus();
            s && s->localization == static_cast<std::uint8_t>(shm::LocalizationState::kLocked))
            report.locked_after_s = toSeconds(monotonicNow() - play_at);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    sleepUntil(play_end + fromSeconds(1.0));

    // 5. Stop, export, shut down.
    const shm::CommandAck stopped = sendCommand(ui, shm::CommandType::kStopScan);
    if (stopped.state != static_cast<std::uint32_t>(shm::CommandState::kDone))
        return fail(std::string("stop scan: ") + std::string(shm::getText(stopped.message)));
    auto exported = exportScan(out / "export");
    if (!exported.isOk()) return exported.status();
    report.export_points = *exported;
    if (o.calibrate_rounds > 0) {
        // As the operator's "calibrate" on the stopped screen: on the scan just made.
        const shm::CommandAck calibrated =
            sendCommand(ui, shm::CommandType::kCalibrate,
                        "rounds=" + std::to_string(o.calibrate_rounds), 900.0);
        report.calibration = std::string(shm::getText(calibrated.message));
        if (calibrated.state != static_cast<std::uint32_t>(shm::CommandState::kDone))
            return fail("calibrate: " + report.calibration);
        // As the operator next: a new scan, which runs with the new calibration.
        const shm::CommandAck next = sendCommand(ui, shm::CommandType::kNewScan);
        if (next.state != static_cast<std::uint32_t>(shm::CommandState::kDone))
            return fail("new scan after the calibration: " +
                        std::string(shm::getText(next.message)));
    }
    daemon.process.signal(SIGTERM);
    if (Status s = daemon.reap(20 * kNsPerSec, log); !s.isOk()) return s;
    const ProcessEnd& last = daemon.ends.back();
    if (!last.exited || last.exit_code != 0) {
        return Status(StatusCode::kDeviceError, "handscan-pipeline " + last.describe() +
                                                    " after SIGTERM; log:\n" + logTail(log));
    }
    for (const ProcessEnd& e : daemon.ends) {
        report.daemon_user_cpu_s += e.user_cpu_s;
        report.daemon_system_cpu_s += e.system_cpu_s;
        report.daemon_peak_rss_mib = std::max(report.daemon_peak_rss_mib, e.peak_rss_mib);
    }

    // 6. What replay writes, from the daemon's journal and export.
    OutputsInputs in{*rec, offset, fakes->counts(), o, log, out};
    if (Status s = writeHilOutputs(in, report); !s.isOk()) return s;
    if (!o.viz_path.empty()) {
        viz::JournalVizOptions v;
        v.journal = report.journal;
        v.out = o.viz_path;
        v.recording = o.recording;
        v.journal_minus_recording_ns = offset;
        Calibration cal;
        try {
            cal = loadCalibration(calibration);
        } catch (const std::exception& e) {
            return Status(StatusCode::kInvalidArgument, std::string("--viz: ") + e.what());
        }
        auto written = viz::writeJournalViz(v, cal);
        if (!written.isOk()) return written.status();
        report.viz_bytes = written->bytes;
        report.summary += "viz: " + std::to_string(written->poses) + " poses, " +
                          std::to_string(written->points) + " points, " +
                          std::to_string(written->recorded_messages) +
                          " recorded frames and ground-truth poses, " +
                          std::to_string(written->bytes >> 20) + " MiB -> " + o.viz_path + "\n";
    }
    if (continuing) {
        char line[160];
        std::snprintf(
            line, sizeof line, "hil: continued %s: %s\n", o.continue_scan.c_str(),
            report.locked_after_s >= 0
                ? ("locked " + std::to_string(report.locked_after_s) + " s into the recording")
                      .c_str()
                : "NOT locked");
        report.summary += line;
    }
    fakes.reset();
    fs::remove_all(out / "cameras", ec);  // the played frames: the recording's, large
    return report;
}

}  // namespace handscan::hil
