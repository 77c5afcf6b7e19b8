#include "handscan/pipeline_daemon/export_job.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>

#include "handscan/core/log.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon {

ExportJob::~ExportJob() {
    if (thread_.joinable()) thread_.join();
}

Status ExportJob::start(const std::string& source, const std::string& target) {
    std::lock_guard lock(mutex_);
    if (running_) return Status(StatusCode::kInvalidArgument, "an export is running already");
    if (thread_.joinable()) thread_.join();  // the previous one has ended
    running_ = true;
    result_.reset();
    status_ = {};
    status_.state = static_cast<std::uint8_t>(shm::ExportState::kRunning);
    shm::setText(status_.target, target.empty() || target == "usb" ? "USB stick" : target);
    stage_ = "starting";
    thread_ = std::thread([this, source, target] { run(source, target); });
    return Status::ok();
}

void ExportJob::run(std::string source, std::string target) {
    exporter::ExportOptions options;
    options.progress = [this](double fraction, const std::string& stage) {
        std::lock_guard lock(mutex_);
        status_.progress = static_cast<float>(fraction);
        stage_ = stage;
    };
    const bool usb = target.empty() || target == "usb";
    options.preview_png = preview_png_;
    log().info("export of {} to {}", source, usb ? "the USB stick" : target);
    auto report = usb ? exporter::exportToUsb(source, options, usb_paths_)
                      : exporter::exportScan(source, target, options);
    std::lock_guard lock(mutex_);
    running_ = false;
    if (!report.isOk()) {
        status_.state = static_cast<std::uint8_t>(shm::ExportState::kFailed);
        shm::setText(status_.message, report.status().message());
        result_ = report.status();
        log().error("export failed: {}", report.status().message());
        return;
    }
    // The exporter wrote to temporary names, fsynced, verified by reading back, renamed and
    // synced the file system: pulling the stick now loses nothing.
    status_.state = static_cast<std::uint8_t>(shm::ExportState::kDone);
    status_.safe_to_remove = 1;
    status_.progress = 1.0f;
    status_.bytes_written = report->bytes;
    shm::setText(status_.target, report->directory);
    std::string msg = "exported " + std::to_string(report->points) + " points to " +
                      report->directory + (usb ? "; safe to remove the USB stick" : "");
    for (const std::string& note : report->notes) {
        log().warn("export: {}", note);
        msg += "; " + note;
    }
    shm::setText(status_.message, msg);
    result_ = msg;
    log().info("{}", msg);
    if (usb) requestEject(report->directory);
}

void ExportJob::requestEject(const std::string& directory) const {
    if (eject_request_.empty()) return;
    // The sandboxed daemon may not unmount; systemd does it for it (handscan-usb-eject.path).
    std::ofstream out(eject_request_, std::ios::trunc);
    out << directory << "\n";
    if (!out.flush())
        log().warn(
            "cannot write the USB eject request {} ({}): the stick stays mounted; it was "
            "synced, so pulling it is safe",
            eject_request_, std::strerror(errno));
}

bool ExportJob::running() const {
    std::lock_guard lock(mutex_);
    return running_;
}

shm::ExportStatus ExportJob::status() const {
    std::lock_guard lock(mutex_);
    return status_;
}

std::optional<Result<std::string>> ExportJob::takeResult() {
    std::lock_guard lock(mutex_);
    auto r = std::move(result_);
    result_.reset();
    return r;
}

std::pair<std::string, float> ExportJob::progress() const {
    std::lock_guard lock(mutex_);
    return {stage_, status_.progress};
}

}  // namespace handscan::pipeline_daemon
