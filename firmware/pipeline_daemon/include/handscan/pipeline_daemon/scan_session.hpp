// ScanSession: the scan state machine and its journal on internal storage.
//   idle --start--> scanning (new journal DIR/scan-YYYYmmdd-HHMMSS/journal.hsj)
//   scanning --stop--> stopped (journal flushed: exportable, and start resumes the same scan)
//   stopped --new scan--> idle (journal finished); finish() (shutdown, SIGTERM) finishes it too.
//   idle or stopped --continue--> scanning a new journal whose metadata names the earlier scan
//   it continues (prior_map: `handscan merge` takes it as in that scan's frame).
// While scanning, poses, full-resolution points and per-sweep statistics are appended; the journal
// writer flushes a checksummed chunk at least every 0.5 s. When the journal stops (disk full) the
// scan stops cleanly with everything written so far intact, and problem() says why. After a crash
// or power cut, recoverUnfinished() takes the newest unfinished journal back (its torn tail cut) as
// a stopped scan, so the operator can still export it; starting scanning then begins a new scan
// (the recovered points are in another run's world frame). With a ScanRecorder, each scanning
// stretch's raw device streams go beside the journal (raw.mcap, ...).
#pragma once

#include <memory>
#include <span>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/journal/journal_writer.hpp"
#include "handscan/pipeline_daemon/scan_recorder.hpp"
#include "handscan/shm/layout.hpp"

namespace handscan::pipeline_daemon {

class ScanSession {
public:
    explicit ScanSession(std::string journal_dir, journal::JournalOptions options = {},
                         std::string metadata_json = "{}")
        : dir_(std::move(journal_dir)), options_(options), metadata_(std::move(metadata_json)) {}
    ~ScanSession();
    // Records each scanning stretch's raw streams into the scan's directory (null: none).
    void setRecorder(ScanRecorder* recorder) { recorder_ = recorder; }

    // Each returns the message for the operator, or why it was refused (kInvalidArgument) or
    // failed (I/O).
    Result<std::string> start();
    Result<std::string> stop();
    Result<std::string> newScan();
    // A new scan continuing the one in `prior_dir` (the stopped one's journal is finished).
    Result<std::string> continueFrom(const std::string& prior_dir);
    // Ends the scan for good (shutdown): flushed and marked finished.
    Status finish();
    // At start-up: adopts the newest unfinished journal of the directory, if any, as a stopped
    // scan; the message says what was recovered (empty when there was nothing to recover).
    Result<std::string> recoverUnfinished();
    // start() would continue the current scan rather than begin a new one.
    bool canResume() const {
        return state_ == shm::ScanState::kStopped && journal_ && !journal_->stopped() && resumable_;
    }

    void appendPose(const journal::TrajectoryPose& pose);
    void appendPoints(std::span<const journal::MapPoint> points);
    // A sweep's statistics (the report's module timeline and device rates).
    void appendSweep(const journal::SweepRecord& sweep);
    void flushIfDue();

    shm::ScanState state() const { return state_; }
    bool scanning() const { return state_ == shm::ScanState::kScanning; }
    const std::string& journalPath() const { return path_; }
    const std::string& root() const { return dir_; }
    std::uint64_t points() const { return points_; }
    const std::string& problem() const { return problem_; }
    bool lowSpace() const { return journal_ && journal_->lowSpace(); }

private:
    void onJournalError(const Status& s);
    Result<std::string> begin(const std::string& metadata);
    void startRecording();
    void stopRecording();

    std::string dir_;
    journal::JournalOptions options_;
    std::string metadata_;
    shm::ScanState state_ = shm::ScanState::kIdle;
    std::unique_ptr<journal::JournalWriter> journal_;
    std::string path_;
    std::uint64_t points_ = 0;
    std::string problem_;
    bool resumable_ = true;
    ScanRecorder* recorder_ = nullptr;
};

}  // namespace handscan::pipeline_daemon
