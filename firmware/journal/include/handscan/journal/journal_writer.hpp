// Appends the scan's full-resolution points and trajectory to internal storage while scanning.
// Points are buffered and written as one checksummed chunk at most every `flush_interval_s`,
// each followed by fdatasync: a power cut or kill -9 loses at most the last interval. Free space
// is checked before every chunk: when it would fall below the reserve the writer stops cleanly
// (kNoSpace) with everything written so far intact, instead of corrupting anything.
// Not thread-safe: the daemon owns one writer on its journal thread.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"

namespace handscan::journal {

struct JournalOptions {
    double flush_interval_s = 0.5;              // at most this much is lost on a power cut
    std::uint64_t reserve_bytes = 64ull << 20;  // never fill the disk beyond this reserve
    std::uint64_t warn_bytes = 1ull << 30;    // lowSpace() (UI warning) when free < reserve + this
    std::size_t max_chunk_points = 1u << 18;  // a chunk is written early when this many wait
};

class JournalWriter {
public:
    // Starts a new journal file (fails if it exists). `metadata_json` is stored first.
    static Result<std::unique_ptr<JournalWriter>> create(const std::string& path,
                                                         const std::string& metadata_json,
                                                         JournalOptions options = {});
    // Continues a recovered journal: cuts any damaged tail and appends after the last good chunk.
    static Result<std::unique_ptr<JournalWriter>> resume(const std::string& path,
                                                         JournalOptions options = {});
    ~JournalWriter();
    JournalWriter(const JournalWriter&) = delete;
    JournalWriter& operator=(const JournalWriter&) = delete;

    Status appendPoints(std::span<const MapPoint> points);
    Status appendPose(const TrajectoryPose& pose);
    // A registered sweep's statistics (written with the next chunk of poses, before its points).
    Status appendSweep(const SweepRecord& sweep);
    // Writes pending data if the flush interval has passed (call it often, e.g. per sweep).
    Status flushIfDue();
    // Writes everything pending now.
    Status flush();
    // Flushes and marks the scan complete.
    Status finish();

    bool stopped() const { return !stop_reason_.isOk(); }
    const Status& stopReason() const { return stop_reason_; }
    bool lowSpace() const { return free_bytes_ < options_.reserve_bytes + options_.warn_bytes; }
    std::uint64_t freeBytes() const { return free_bytes_; }
    std::uint64_t committedPoints() const { return committed_points_; }
    std::uint64_t committedChunks() const { return sequence_; }
    const std::string& path() const { return path_; }

private:
    JournalWriter(std::string path, int fd, JournalOptions options);
    Status writeChunk(int kind, std::uint32_t records, double t_last,
                      const std::vector<std::uint8_t>& payload);
    Status stop(Status reason);
    void refreshFreeSpace();

    std::string path_;
    int fd_ = -1;
    JournalOptions options_;
    std::uint64_t end_offset_ = 0;
    std::uint64_t sequence_ = 0;
    std::uint64_t committed_points_ = 0;
    std::uint64_t free_bytes_ = ~0ull;
    std::int64_t last_flush_ns_ = 0;
    std::vector<MapPoint> pending_points_;
    std::vector<TrajectoryPose> pending_poses_;
    std::vector<SweepRecord> pending_sweeps_;
    Status stop_reason_;
};

}  // namespace handscan::journal
