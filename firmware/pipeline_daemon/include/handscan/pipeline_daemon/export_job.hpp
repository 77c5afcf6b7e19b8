// ExportJob: one export at a time on its own thread, through the same code as `handscan export`
// (exporter::exportToUsb for the stick, exporter::exportScan for a named directory), so the
// daemon's main loop keeps answering commands and the watchdog while a slow stick is written.
// Progress and the final "safe to remove" are kept as the status block's ExportStatus.
#pragma once

#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "handscan/core/status.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::pipeline_daemon {

class ExportJob {
public:
    // `eject_request`: the file written after a verified export to the USB stick, which
    // handscan-usb-eject.path turns into an unmount ("" writes none).
    explicit ExportJob(exporter::SystemPaths usb_paths = {}, std::string eject_request = {})
        : usb_paths_(std::move(usb_paths)), eject_request_(std::move(eject_request)) {}
    ~ExportJob();
    ExportJob(const ExportJob&) = delete;
    ExportJob& operator=(const ExportJob&) = delete;

    // Where each export also leaves the map's picture for the UI (shm::exportPreviewPath of the
    // daemon's region; "" writes none). Call before the first start().
    void setPreviewPath(std::string path) { preview_png_ = std::move(path); }
    // Exports journal `source` to `target`: "" or "usb" = the removable stick, else a directory.
    // Refused (kInvalidArgument) while another export runs.
    Status start(const std::string& source, const std::string& target);
    bool running() const;
    // What the status bar shows (idle until the first export).
    shm::ExportStatus status() const;
    // The outcome of a finished export, once: the message for the operator, or the error.
    std::optional<Result<std::string>> takeResult();
    // Stage text and progress of the running export, for the command's ack.
    std::pair<std::string, float> progress() const;

private:
    void run(std::string source, std::string target);

    void requestEject(const std::string& mount_point) const;

    exporter::SystemPaths usb_paths_;
    std::string eject_request_;
    std::string preview_png_;
    mutable std::mutex mutex_;
    shm::ExportStatus status_{};
    std::string stage_;
    bool running_ = false;
    std::optional<Result<std::string>> result_;
    std::thread thread_;
};

}  // namespace handscan::pipeline_daemon
