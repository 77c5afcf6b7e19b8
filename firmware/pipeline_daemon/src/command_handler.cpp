#include "handscan/pipeline_daemon/command_handler.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "handscan/core/log.hpp"
#include "handscan/pipeline_daemon/scan_recorder.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon {

using shm::CommandState;
using shm::CommandType;

void CommandHandler::pollChannel() {
    while (auto cmd = channel_.pollCommand()) {
        log().info("command #{} {} '{}'", cmd->seq, shm::toString(cmd->type), cmd->argument);
        channel_.ack(cmd->seq, CommandState::kAccepted, "");
        const Outcome o = execute(cmd->type, cmd->argument, cmd->seq);
        channel_.ack(cmd->seq, o.state, o.message,
                     o.state == CommandState::kInProgress ? 0.0f : 1.0f);
    }
}

void CommandHandler::onButton(ButtonAction action) {
    CommandType type = CommandType::kExport;
    if (action == ButtonAction::kToggleScan) {
        type = worker_.scanState() == shm::ScanState::kScanning ? CommandType::kStopScan
                                                                : CommandType::kStartScan;
    }
    const Outcome o = execute(type, "usb", 0);
    log().info("button: {}: {} {}", shm::toString(type), shm::toString(o.state), o.message);
}

CommandHandler::Outcome CommandHandler::execute(CommandType type, const std::string& argument,
                                                std::uint64_t seq) {
    const auto fromResult = [](const Result<std::string>& r) {
        if (r.isOk()) return Outcome{CommandState::kDone, *r};
        return Outcome{r.status().code() == StatusCode::kInvalidArgument ? CommandState::kRejected
                                                                         : CommandState::kFailed,
                       r.status().message()};
    };
    switch (type) {
        case CommandType::kStartScan:
            if (exports_.running())
                return {CommandState::kRejected, "an export is running; wait for it to finish"};
            return fromResult(worker_.control(ScanControl::kStart));
        case CommandType::kStopScan:
            return fromResult(worker_.control(ScanControl::kStop));
        case CommandType::kNewScan:
            if (exports_.running())
                return {CommandState::kRejected, "an export is running; wait for it to finish"};
            return fromResult(worker_.control(ScanControl::kNewScan));
        case CommandType::kExport: {
            if (worker_.scanState() == shm::ScanState::kScanning)
                return {CommandState::kRejected, "stop the scan before exporting"};
            const std::string journal = worker_.journalPath();
            if (journal.empty()) return {CommandState::kRejected, "no scan to export: scan first"};
            if (Status s = exports_.start(journal, argument); !s.isOk())
                return {CommandState::kRejected, s.message()};
            export_seq_ = seq;
            return {CommandState::kInProgress, "exporting"};
        }
        case CommandType::kContinueScan:
            if (exports_.running())
                return {CommandState::kRejected, "an export is running; wait for it to finish"};
            // While a continued scan searches for its place, a pose places the operator again.
            if (worker_.scanState() == shm::ScanState::kScanning)
                return fromResult(placeAgain(argument));
            if (auto loading = continueScan(argument, seq); !loading.isOk())
                return fromResult(loading);
            else
                return {CommandState::kInProgress, *loading};
        case CommandType::kCalibrate:
            return calibrate(argument, seq);
        case CommandType::kShutdown:
            shutdown_ = true;
            return {CommandState::kDone, "shutting down: the scan is saved"};
        case CommandType::kNone:
            break;
    }
    return {CommandState::kRejected, "unknown command " + std::to_string(static_cast<int>(type))};
}

Result<std::string> CommandHandler::continueScan(const std::string& argument, std::uint64_t seq) {
    if (continuing_) return Status(StatusCode::kInvalidArgument, "already continuing a scan");
    if (worker_.scanState() == shm::ScanState::kScanning)
        return Status(StatusCode::kInvalidArgument, "stop the scan before continuing another");
    auto request = parseContinueArgument(argument);
    if (!request.isOk()) return request.status();
    // Which scan: the one named, else the one just stopped, else the newest on the device.
    std::string dir;
    if (!request->scan.empty()) {
        dir = (std::filesystem::path(worker_.journalRoot()) / request->scan).string();
    } else if (worker_.scanState() == shm::ScanState::kStopped && !worker_.journalPath().empty()) {
        dir = std::filesystem::path(worker_.journalPath()).parent_path().string();
    } else {
        auto newest = newestContinuableScan(worker_.journalRoot());
        if (!newest.isOk()) return Status(StatusCode::kInvalidArgument, newest.status().message());
        dir = *newest;
    }
    if (!canContinue(dir))
        return Status(StatusCode::kInvalidArgument,
                      dir + " cannot be continued: it has no journal.hsj");
    continuing_ = Continuing{seq, request->initial_pose,
                             std::async(std::launch::async, loadEarlierScan, dir)};
    return "loading " + std::filesystem::path(dir).filename().string();
}

Result<std::string> CommandHandler::placeAgain(const std::string& argument) {
    auto request = parseContinueArgument(argument);
    if (!request.isOk()) return request.status();
    if (!request->initial_pose || !request->scan.empty())
        return Status(StatusCode::kInvalidArgument, "stop the scan before continuing another");
    return worker_.placeAgain(*request->initial_pose);
}

void CommandHandler::finishContinue() {
    if (!continuing_ ||
        continuing_->loaded.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
        return;
    auto earlier = continuing_->loaded.get();
    Result<std::string> out = earlier.isOk()
                                  ? worker_.continueScan(*earlier, continuing_->initial_pose)
                                  : Result<std::string>(earlier.status());
    const CommandState state = out.isOk() ? CommandState::kDone
                               : out.status().code() == StatusCode::kInvalidArgument
                                   ? CommandState::kRejected
                                   : CommandState::kFailed;
    const std::string message = out.isOk() ? *out : out.status().message();
    log().info("command #{} continue-scan: {} {}", continuing_->seq, shm::toString(state), message);
    if (continuing_->seq != 0) channel_.ack(continuing_->seq, state, message, 1.0f);
    continuing_.reset();
}

CommandHandler::Outcome CommandHandler::calibrate(const std::string& argument, std::uint64_t seq) {
    if (calibration_ == nullptr) return {CommandState::kRejected, "calibration is not available"};
    if (worker_.scanState() == shm::ScanState::kScanning)
        return {CommandState::kRejected, "stop the scan before calibrating"};
    if (exports_.running())
        return {CommandState::kRejected, "an export is running; wait for it to finish"};
    int rounds = 4;
    if (!argument.empty() &&
        (std::sscanf(argument.c_str(), "rounds=%d", &rounds) != 1 || rounds < 1 || rounds > 10))
        return {CommandState::kRejected,
                "calibrate: argument '" + argument + "': expected rounds=1..10 or nothing"};
    const std::string journal = worker_.journalPath();
    if (journal.empty()) return {CommandState::kRejected, "no scan to calibrate on: scan first"};
    const std::string recording =
        scanRecording(std::filesystem::path(journal).parent_path().string());
    if (recording.empty())
        return {CommandState::kRejected,
                "the last scan has no raw recording (storage.record_scans off, or too little "
                "space when it started): scan again to calibrate"};
    if (Status s = calibration_->start(recording, rounds); !s.isOk())
        return {CommandState::kRejected, s.message()};
    calibrate_seq_ = seq;
    return {CommandState::kInProgress, "calibrating"};
}

void CommandHandler::tickCalibration() {
    if (calibration_ == nullptr) return;
    if (auto result = calibration_->takeResult()) {
        if (calibrate_seq_ != 0) {
            if (result->isOk())
                channel_.ack(calibrate_seq_, CommandState::kDone, **result, 1.0f);
            else
                channel_.ack(calibrate_seq_, CommandState::kFailed, result->status().message(),
                             1.0f);
        }
        calibrate_seq_ = 0;
        return;
    }
    const TimeNs now = monotonicNow();
    if (calibrate_seq_ != 0 && calibration_->running() &&
        now - last_calibration_ack_ >= 250 * kNsPerMs) {
        last_calibration_ack_ = now;
        const shm::CalibrationStatus s = calibration_->status();
        channel_.ack(calibrate_seq_, CommandState::kInProgress, shm::getText(s.message),
                     s.progress);
    }
}

void CommandHandler::tick() {
    finishContinue();
    tickCalibration();
    if (auto result = exports_.takeResult()) {
        if (export_seq_ != 0) {
            if (result->isOk())
                channel_.ack(export_seq_, CommandState::kDone, **result, 1.0f);
            else
                channel_.ack(export_seq_, CommandState::kFailed, result->status().message(), 1.0f);
        }
        export_seq_ = 0;
        return;
    }
    const TimeNs now = monotonicNow();
    if (export_seq_ != 0 && exports_.running() && now - last_progress_ack_ >= 100 * kNsPerMs) {
        last_progress_ack_ = now;
        const auto [stage, fraction] = exports_.progress();
        channel_.ack(export_seq_, CommandState::kInProgress, stage, fraction);
    }
}

}  // namespace handscan::pipeline_daemon
