#include "handscan/pipeline_daemon/pipeline_daemon.hpp"

#include <chrono>
#include <filesystem>
#include <thread>

#include "handscan/core/json.hpp"
#include "handscan/core/log.hpp"
#include "handscan/core/realtime.hpp"
#include "handscan/live_output/live_publisher.hpp"
#include "handscan/pipeline_daemon/calibrate_job.hpp"
#include "handscan/pipeline_daemon/command_handler.hpp"
#include "handscan/pipeline_daemon/export_job.hpp"
#include "handscan/pipeline_daemon/pipeline_thread.hpp"
#include "handscan/pipeline_daemon/systemd_notifier.hpp"
#include "handscan/prior_map/prior_map_loader.hpp"
#include "handscan/shm/export_preview.hpp"

namespace handscan::pipeline_daemon {

struct PipelineDaemon::Parts {
    std::unique_ptr<ScanRecorder> recorder;  // outlives the sources (their taps) and the worker
    std::unique_ptr<CalibrateJob> calibration;
    std::vector<std::unique_ptr<SensorSource>> sources;
    ExportJob exports;
    std::unique_ptr<PipelineThread> worker;
    std::unique_ptr<CommandHandler> commands;
    SystemdNotifier notifier;
    Parts(exporter::SystemPaths usb, std::string eject_request)
        : exports(std::move(usb), std::move(eject_request)) {}
};

PipelineDaemon::PipelineDaemon(DaemonOptions options, std::unique_ptr<DeviceLinks> links)
    : options_(std::move(options)), links_(std::move(links)) {}

PipelineDaemon::~PipelineDaemon() {
    if (!parts_) return;
    // The last export's picture goes with the live-map region it was named after.
    std::error_code ec;
    std::filesystem::remove(shm::exportPreviewPath(options_.shm_name), ec);
    for (auto& s : parts_->sources) s->stop();
    if (parts_->worker) parts_->worker->stop();
}

Status PipelineDaemon::open() {
    // The logger is created on first use; create it here, before the device threads all log.
    log().debug("handscan-pipeline: opening");
    const std::string config_dir = defaultConfigDir();
    const std::string device_yaml =
        options_.device_config.empty() ? config_dir + "/device.yaml" : options_.device_config;
    const std::string factory_calibration =
        options_.calibration.empty() ? config_dir + "/calibration.yaml" : options_.calibration;
    const std::string calibration_yaml =
        calibrationInUse(factory_calibration, options_.field_calibration);
    log().info("calibration: {}", calibration_yaml);
    RealtimeConfig realtime;
    try {
        calibration_ = loadCalibration(calibration_yaml);
        // The latencies calibration.yaml measured (`handscan calibrate`) replace device.yaml's,
        // as in replay.
        device_ = withCalibratedLatencies(loadDeviceConfig(device_yaml), calibration_);
        realtime = loadRealtimeConfig(device_yaml);
    } catch (const std::exception& e) {  // ConfigError: file, line, key, expected and found
        return Status(StatusCode::kInvalidArgument, e.what());
    }
    if (realtime.lock_memory) (void)lockProcessMemory();  // warns once if denied
    const std::string journal_dir =
        options_.journal_dir.empty() ? device_.storage.journal_dir : options_.journal_dir;
    std::error_code ec;
    std::filesystem::create_directories(journal_dir, ec);  // its free space is shown from the start
    if (ec)
        log().error("journal directory {}: {} (scans cannot start until it is writable)",
                    journal_dir, ec.message());
    shm::WriterOptions wo;
    wo.name = options_.shm_name;
    wo.map_capacity_points = options_.map_capacity_points;
    auto publisher = live_output::LivePublisher::create(wo, journal_dir);
    if (!publisher.isOk()) return publisher.status();

    parts_ = std::make_unique<Parts>(options_.usb_paths, options_.usb_eject_request);
    parts_->exports.setPreviewPath(shm::exportPreviewPath(options_.shm_name));
    const std::string metadata =
        jsonText({{"source", "handscan-pipeline"}, {"device_config", device_.source_file}});
    auto session = std::make_unique<ScanSession>(journal_dir, options_.journal, metadata);
    parts_->recorder = std::make_unique<ScanRecorder>(ScanRecorderOptions{
        device_.storage.record_scans,
        options_.journal.reserve_bytes +
            static_cast<std::uint64_t>(device_.storage.min_free_gib * double(1ull << 30))});
    session->setRecorder(parts_->recorder.get());
    parts_->calibration = std::make_unique<CalibrateJob>(
        device_yaml, factory_calibration,
        options_.field_calibration.empty() ? factory_calibration : options_.field_calibration);
    // A scan cut short by a crash or power cut is taken back, so the UI can still export it.
    if (auto recovered = session->recoverUnfinished(); !recovered.isOk())
        log().error("{}", recovered.status().message());
    WorkerInputs inputs;
    inputs.sensors = [this] {
        std::vector<live_output::LiveSensor> out;
        const TimeNs now = monotonicNow();
        for (auto& s : parts_->sources) out.push_back(s->health().snapshot(now));
        return out;
    };
    inputs.export_status = [this] { return parts_->exports.status(); };
    inputs.calibration_status = [this] { return parts_->calibration->status(); };
    inputs.new_calibration = [this] { return parts_->calibration->takeInstalled(); };
    if (!options_.prior_map_dir.empty()) {
        auto prior = prior_map::loadPriorMap(options_.prior_map_dir);
        if (!prior.isOk()) return prior.status();
        inputs.prior_map = *prior;
        if (!options_.initial_pose.empty()) {
            auto pose = prior_map::parsePose(options_.initial_pose);
            if (!pose.isOk())
                return Status(pose.status().code(), "--initial-pose: " + pose.status().message());
            inputs.initial_pose = *pose;
        }
    }
    parts_->worker =
        std::make_unique<PipelineThread>(device_, calibration_, std::move(*publisher),
                                         std::move(session), queues_, std::move(inputs));
    parts_->commands = std::make_unique<CommandHandler>(
        *parts_->worker, parts_->exports, parts_->worker->commands(), parts_->calibration.get());

    const SourceContext c{device_, *links_, queues_,
                          RawTaps{parts_->recorder->hokuyoTap(), parts_->recorder->xsensTap(),
                                  parts_->recorder->motorTap()}};
    parts_->sources.push_back(makeHokuyoSource(c));
    parts_->sources.push_back(makeXsensSource(c));
    parts_->sources.push_back(makeMotorSource(c));
    if (device_.tracking_camera.enabled) parts_->sources.push_back(makeCameraSource(c, false));
    if (device_.colour_camera.enabled) parts_->sources.push_back(makeCameraSource(c, true));
    parts_->sources.push_back(makeGpioSource(c, leds_, [this](ButtonAction a) {
        std::lock_guard lock(buttons_mutex_);
        buttons_.push_back(a);
    }));
    parts_->worker->start(realtime.pipeline_priority);
    for (auto& s : parts_->sources) s->start(realtime.device_priority);
    log().info("handscan-pipeline: {} devices, journal in {}, live map /dev/shm{}",
               parts_->sources.size(), journal_dir, options_.shm_name);
    return Status::ok();
}

bool PipelineDaemon::allAttempted() const {
    for (const auto& s : parts_->sources) {
        if (!s->health().attempted()) return false;
    }
    return true;
}

std::string PipelineDaemon::statusLine() {
    const auto state = parts_->worker->scanState();
    std::string line = state == shm::ScanState::kScanning  ? "scanning"
                       : state == shm::ScanState::kStopped ? "stopped"
                                                           : "idle";
    const TimeNs now = monotonicNow();
    for (auto& s : parts_->sources) {
        const live_output::LiveSensor h = s->health().snapshot(now);
        line += "; " + h.name + (h.connected ? " ok" : " LOST");
    }
    if (parts_->exports.running()) line += "; exporting";
    return line;
}

void PipelineDaemon::updateLeds() {
    using gpio::LedPattern;
    const bool scanning = parts_->worker->scanState() == shm::ScanState::kScanning;
    bool fault = false;
    const TimeNs now = monotonicNow();
    for (auto& s : parts_->sources) {
        if (s->health().name() != "buttons" && !s->health().snapshot(now).connected) fault = true;
    }
    leds_.ready.store(scanning ? LedPattern::kOff : LedPattern::kDoubleFlash);
    leds_.scanning.store(scanning ? LedPattern::kOn : LedPattern::kOff);
    leds_.fault.store(fault ? LedPattern::kBlinkFast : LedPattern::kOff);
    leds_.exporting.store(parts_->exports.running() ? LedPattern::kBlinkSlow : LedPattern::kOff);
}

Status PipelineDaemon::run(const std::atomic<bool>& stop) {
    if (!parts_)
        return Status(StatusCode::kInvalidArgument,
                      "handscan-pipeline: run() before a successful open()");
    Parts& p = *parts_;
    const TimeNs started = monotonicNow();
    bool ready = false;
    while (!stop.load(std::memory_order_acquire) && !p.commands->shutdownRequested()) {
        const TimeNs now = monotonicNow();
        if (!ready && (allAttempted() || now - started >= options_.ready_timeout)) {
            ready = true;
            p.notifier.ready(statusLine());
            log().info("ready: {}", statusLine());
        }
        p.commands->pollChannel();
        std::vector<ButtonAction> pressed;
        {
            std::lock_guard lock(buttons_mutex_);
            pressed.swap(buttons_);
        }
        for (ButtonAction a : pressed) p.commands->onButton(a);
        p.commands->tick();
        updateLeds();
        // Feed the watchdog only while the pipeline thread is alive: a hung pipeline must be
        // restarted by systemd even though this loop still runs.
        if (now - p.worker->lastLoop() < 2 * kNsPerSec) p.notifier.watchdog(now);
        if (ready) p.notifier.status(statusLine());
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    // Clean shutdown: the scan's last samples processed and journaled, the journal finished.
    p.notifier.stopping("stopping: saving the scan");
    for (auto& s : p.sources) s->stop();
    auto finished = p.worker->control(ScanControl::kFinish);
    p.worker->stop();
    while (p.exports.running())
        std::this_thread::sleep_for(std::chrono::milliseconds(50));  // never cut a write short
    if (p.calibration->running())
        log().info(
            "waiting for the calibration to finish (the old calibration.yaml stays until "
            "it does)");
    while (p.calibration->running()) std::this_thread::sleep_for(std::chrono::milliseconds(50));
    p.commands->tick();
    if (!finished.isOk()) return finished.status();
    log().info("handscan-pipeline: stopped cleanly ({})", *finished);
    return Status::ok();
}

}  // namespace handscan::pipeline_daemon
