#include "handscan/pipeline_daemon/scan_session.hpp"

#include <algorithm>
#include <ctime>
#include <filesystem>

#include "handscan/core/json.hpp"
#include "handscan/core/log.hpp"
#include "handscan/journal/journal_reader.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

// scan-YYYYmmdd-HHMMSS from the wall clock (UTC), with -2, -3 ... if taken.
fs::path freshScanDir(const fs::path& root) {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char name[32];
    std::strftime(name, sizeof(name), "scan-%Y%m%d-%H%M%S", &tm);
    fs::path dir = root / name;
    for (int i = 2; fs::exists(dir); ++i)
        dir = root / (std::string(name) + "-" + std::to_string(i));
    return dir;
}

}  // namespace

ScanSession::~ScanSession() { (void)finish(); }

void ScanSession::startRecording() {
    if (recorder_ == nullptr || path_.empty()) return;
    log().info("{}", recorder_->start(fs::path(path_).parent_path().string()));
}

void ScanSession::stopRecording() {
    if (recorder_ == nullptr || !recorder_->recording()) return;
    auto r = recorder_->stop();
    if (r.isOk())
        log().info("raw recording finished: {}", *r);
    else
        log().error("{}", r.status().message());
}

Result<std::string> ScanSession::start() {
    if (state_ == shm::ScanState::kScanning)
        return Status(StatusCode::kInvalidArgument, "already scanning");
    if (canResume()) {
        state_ = shm::ScanState::kScanning;
        startRecording();
        return std::string("scanning (resumed)");
    }
    if (journal_) (void)finish();  // a recovered scan, or the journal failed: start a fresh one
    return begin(metadata_);
}

Result<std::string> ScanSession::continueFrom(const std::string& prior_dir) {
    if (state_ == shm::ScanState::kScanning)
        return Status(StatusCode::kInvalidArgument, "stop the scan first");
    if (Status s = finish(); !s.isOk()) return s;
    Json meta = Json::parse(metadata_, nullptr, false);
    if (!meta.is_object()) meta = Json::object();
    meta["prior_map"] = prior_dir;
    auto out = begin(jsonText(meta));
    if (!out.isOk()) return out;
    return *out + ", continuing " + fs::path(prior_dir).filename().string();
}

Result<std::string> ScanSession::begin(const std::string& metadata) {
    std::error_code ec;
    const fs::path dir = freshScanDir(dir_);
    fs::create_directories(dir, ec);
    if (ec) {
        return Status(StatusCode::kIoError,
                      "journal: cannot create " + dir.string() + ": " + ec.message() +
                          " (is storage.journal_dir writable by the handscan user?)");
    }
    auto j = journal::JournalWriter::create((dir / "journal.hsj").string(), metadata, options_);
    if (!j.isOk()) return j.status();
    journal_ = std::move(*j);
    path_ = journal_->path();
    points_ = 0;
    problem_.clear();
    resumable_ = true;
    state_ = shm::ScanState::kScanning;
    log().info("scan started: {}", path_);
    startRecording();
    return "scanning into " + dir.filename().string();
}

Result<std::string> ScanSession::stop() {
    if (state_ != shm::ScanState::kScanning)
        return Status(StatusCode::kInvalidArgument, "not scanning");
    state_ = shm::ScanState::kStopped;
    stopRecording();
    if (Status s = journal_->flush(); !s.isOk()) onJournalError(s);
    log().info("scan stopped: {} points in {}", points_, path_);
    return "scan stopped: " + std::to_string(points_) + " points";
}

Result<std::string> ScanSession::newScan() {
    if (state_ == shm::ScanState::kScanning)
        return Status(StatusCode::kInvalidArgument, "stop the scan first");
    if (Status s = finish(); !s.isOk()) return s;
    state_ = shm::ScanState::kIdle;
    path_.clear();
    points_ = 0;
    problem_.clear();
    return std::string("new scan ready");
}

Status ScanSession::finish() {
    stopRecording();
    if (!journal_) return Status::ok();
    if (state_ == shm::ScanState::kScanning) state_ = shm::ScanState::kStopped;
    Status s = journal_->stopped() ? Status::ok() : journal_->finish();
    journal_.reset();
    if (!s.isOk()) log().error("journal {}: {}", path_, s.message());
    return s;
}

Result<std::string> ScanSession::recoverUnfinished() {
    std::error_code ec;
    std::vector<fs::path> journals;
    for (const auto& e : fs::directory_iterator(dir_, ec)) {
        if (e.is_regular_file(ec) || !fs::exists(e.path() / "journal.hsj", ec)) continue;
        journals.push_back(e.path() / "journal.hsj");
    }
    std::sort(journals.begin(), journals.end());  // scan-<UTC time>: the newest last
    for (auto it = journals.rbegin(); it != journals.rend(); ++it) {
        auto summary = journal::recoverJournal(it->string());
        if (!summary.isOk()) {
            log().warn("journal {}: {}", it->string(), summary.status().message());
            continue;
        }
        if (summary->finished) return std::string();  // the newest scan ended normally
        auto writer = journal::JournalWriter::resume(it->string(), options_);
        if (!writer.isOk()) return writer.status();
        journal_ = std::move(*writer);
        path_ = journal_->path();
        points_ = journal_->committedPoints();
        state_ = shm::ScanState::kStopped;
        resumable_ = false;
        problem_ = "recovered the scan cut short at the last shutdown (" + std::to_string(points_) +
                   " points): export it or start a new scan";
        log().warn("{}: {}{}", path_, problem_,
                   summary->damage.empty() ? "" : "; cut: " + summary->damage);
        return problem_;
    }
    return std::string();
}

void ScanSession::appendPose(const journal::TrajectoryPose& pose) {
    if (state_ != shm::ScanState::kScanning) return;
    if (Status s = journal_->appendPose(pose); !s.isOk()) onJournalError(s);
}

void ScanSession::appendPoints(std::span<const journal::MapPoint> points) {
    if (state_ != shm::ScanState::kScanning) return;
    if (Status s = journal_->appendPoints(points); !s.isOk()) return onJournalError(s);
    points_ += points.size();
}

void ScanSession::appendSweep(const journal::SweepRecord& sweep) {
    if (state_ != shm::ScanState::kScanning) return;
    if (Status s = journal_->appendSweep(sweep); !s.isOk()) onJournalError(s);
}

void ScanSession::flushIfDue() {
    if (state_ != shm::ScanState::kScanning) return;
    if (recorder_ != nullptr) recorder_->checkSpace();
    if (Status s = journal_->flushIfDue(); !s.isOk()) onJournalError(s);
}

void ScanSession::onJournalError(const Status& s) {
    // Everything written so far stays intact; the scan stops rather than losing data silently.
    stopRecording();
    problem_ = "scan stopped: " + s.message();
    log().error("journal {}: {}", path_, s.message());
    state_ = shm::ScanState::kStopped;
}

}  // namespace handscan::pipeline_daemon
