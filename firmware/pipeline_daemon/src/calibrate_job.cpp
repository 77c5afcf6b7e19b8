#include "handscan/pipeline_daemon/calibrate_job.hpp"

#include <fcntl.h>
#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "handscan/calibrate/self_calibration.hpp"
#include "handscan/core/log.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

Status ioError(const std::string& what, const std::string& path) {
    return Status(StatusCode::kIoError, what + " " + path + ": " + std::strerror(errno));
}

// The calibration only gets CPU time nothing else wants (the pipeline and device threads are
// SCHED_FIFO on the device; a developer's shell runs them at normal priority, above idle too).
void idlePriority() {
    sched_param p{};
    if (::sched_setscheduler(0, SCHED_IDLE, &p) != 0)
        log().warn("calibration: cannot run at idle priority ({}); running at normal priority",
                   std::strerror(errno));
}

}  // namespace

std::string calibrationInUse(const std::string& factory, const std::string& field) {
    std::error_code ec;
    return !field.empty() && fs::is_regular_file(field, ec) ? field : factory;
}

Status installKeepingPrevious(const std::string& fresh, const std::string& target) {
    const std::string prev = target + ".prev", prev_tmp = target + ".prev.tmp";
    if (fs::exists(target)) {
        ::unlink(prev_tmp.c_str());
        if (::link(target.c_str(), prev_tmp.c_str()) != 0)
            return ioError("calibration: cannot keep the previous file as", prev_tmp);
        if (::rename(prev_tmp.c_str(), prev.c_str()) != 0)
            return ioError("calibration: cannot keep the previous file as", prev);
    }
    if (::rename(fresh.c_str(), target.c_str()) != 0)
        return ioError("calibration: cannot install the new file as", target);
    const std::string dir = fs::path(target).parent_path().string();
    if (int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
        fd >= 0) {
        ::fsync(fd);
        ::close(fd);
    }
    return Status::ok();
}

CalibrateJob::~CalibrateJob() {
    if (thread_.joinable()) thread_.join();
}

Status CalibrateJob::start(const std::string& recording, int rounds) {
    std::lock_guard lock(mutex_);
    if (running_) return Status(StatusCode::kInvalidArgument, "a calibration is running already");
    if (thread_.joinable()) thread_.join();  // the previous one has ended
    running_ = true;
    result_.reset();
    status_ = shm::CalibrationStatus{};
    status_.state = static_cast<std::uint8_t>(shm::CalibrationState::kRunning);
    shm::setText(status_.message, "starting on " + fs::path(recording).filename().string());
    shm::setText(status_.file, calibration_yaml_);
    thread_ = std::thread([this, recording, rounds] { run(recording, rounds); });
    return Status::ok();
}

void CalibrateJob::step(const std::string& line, int rounds) {
    std::lock_guard lock(mutex_);
    // "round N: ..." lines mark the rounds; one more replay follows the last (the "after").
    int round = 0;
    if (std::sscanf(line.c_str(), "round %d", &round) == 1)
        status_.progress =
            std::max(status_.progress, std::min(0.95f, static_cast<float>(round) / (rounds + 1)));
    shm::setText(status_.message, line);
}

void CalibrateJob::run(std::string recording, int rounds) {
    idlePriority();
    calibrate::SelfCalibrationOptions o;
    o.recording = recording;
    o.start_calibration = calibrationInUse(factory_yaml_, calibration_yaml_);
    o.device_config = device_yaml_;
    o.out = calibration_yaml_ + ".new";
    o.max_rounds = rounds;
    o.log = [this, rounds](const std::string& line) {
        log().info("calibration: {}", line);
        step(line, rounds);
    };
    log().info("calibration on {} (starting from {})", recording, o.start_calibration);
    std::error_code ec;
    fs::create_directories(fs::path(calibration_yaml_).parent_path(), ec);  // named if it fails
    Result<calibrate::SelfCalibrationReport> report =
        Status(StatusCode::kDeviceError, "calibration did not run");
    try {
        report = calibrate::selfCalibrate(o);
    } catch (const std::exception& e) {  // configuration loading reports by exception
        report = Status(StatusCode::kInvalidArgument, e.what());
    }
    Status installed = report.isOk() ? installKeepingPrevious(o.out, calibration_yaml_) : Status();
    std::lock_guard lock(mutex_);
    running_ = false;
    if (!report.isOk() || !installed.isOk()) {
        const Status& failure = report.isOk() ? installed : report.status();
        fs::remove(o.out, ec);
        status_.state = static_cast<std::uint8_t>(shm::CalibrationState::kFailed);
        shm::setText(status_.message, failure.message());
        result_ = failure;
        log().error("calibration failed: {} ({} unchanged)", failure.message(), calibration_yaml_);
        return;
    }
    installed_ = true;
    status_.state = static_cast<std::uint8_t>(shm::CalibrationState::kDone);
    status_.progress = 1.0f;
    status_.consistency_before_mm = static_cast<float>(report->consistency_before_m * 1e3);
    status_.consistency_after_mm = static_cast<float>(report->consistency_after_m * 1e3);
    status_.value_count = 0;
    int written = 0;
    for (const calibrate::ParameterEstimate& p : report->parameters) {
        if (status_.value_count == shm::kCalibrationValues) break;
        shm::CalibrationValue& v = status_.values[status_.value_count++];
        shm::setText(v.name, p.name);
        shm::setText(v.unit, p.unit);
        v.start = static_cast<float>(p.start);
        v.value = static_cast<float>(p.value);
        v.std = std::isfinite(p.std) ? static_cast<float>(p.std) : 0.0f;
        v.written = p.written ? 1 : 0;
        written += p.written;
    }
    // What replaced what: the first field calibration leaves the factory's as the previous one.
    const bool over_factory = o.start_calibration != calibration_yaml_;
    char msg[200];
    std::snprintf(msg, sizeof msg,
                  "calibrated: %d of %zu values written, consistency %.2f -> %.2f mm; %s; "
                  "in use from the next scan",
                  written, report->parameters.size(), status_.consistency_before_mm,
                  status_.consistency_after_mm,
                  over_factory ? "factory calibration kept" : "previous kept as .prev");
    // The camchain is Kalibr's, not calibrate's: a camera that no longer fits the laser is said
    // (first, so that the UI's line of kTextChars keeps it), not corrected.
    std::string text;
    for (const calibrate::CamchainCameraCheck& c : report->camchain.cameras) {
        if (!c.looks_wrong) continue;
        char camera[96];
        std::snprintf(camera, sizeof camera, "%s camera %.1f deg off the laser: check camchain; ",
                      c.camera.c_str(), c.best_turn_deg.norm());
        text += camera;
    }
    text += msg;
    shm::setText(status_.message, text);
    result_ = text;
    log().info("{} ({})", text, calibration_yaml_);
}

bool CalibrateJob::running() const {
    std::lock_guard lock(mutex_);
    return running_;
}

shm::CalibrationStatus CalibrateJob::status() const {
    std::lock_guard lock(mutex_);
    return status_;
}

std::optional<std::string> CalibrateJob::takeInstalled() {
    std::lock_guard lock(mutex_);
    if (!installed_) return std::nullopt;
    installed_ = false;
    return calibration_yaml_;
}

std::optional<Result<std::string>> CalibrateJob::takeResult() {
    std::lock_guard lock(mutex_);
    auto r = std::move(result_);
    result_.reset();
    return r;
}

}  // namespace handscan::pipeline_daemon
