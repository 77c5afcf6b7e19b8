// Reads a map journal, recovering from a crash: every chunk up to the first truncated or damaged
// one is used; what follows is reported (offset, reason) and can be cut off with recover().
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"

namespace handscan::journal {

struct JournalSummary {
    std::string path;
    std::string metadata_json;
    std::uint64_t chunks = 0;
    std::uint64_t points = 0;
    std::vector<TrajectoryPose> trajectory;
    // Per-sweep statistics (ChunkKind::kSweepStats); none in a journal written before them.
    std::vector<SweepRecord> sweeps;
    // Statistics chunks (or records) that could not be read, each with where: they are left out
    // of `sweeps`, everything else of the journal is read on.
    std::vector<std::string> sweep_damage;
    std::uint64_t good_bytes = 0;  // the intact prefix
    std::uint64_t file_bytes = 0;
    bool finished = false;  // the scan was stopped normally (end-of-scan chunk present)
    std::string damage;     // empty when the file is intact, else what was cut and why
    double t_last_s = 0.0;  // newest time in the intact prefix
};

class JournalReader {
public:
    static Result<JournalReader> open(const std::string& path);
    const JournalSummary& summary() const { return summary_; }
    // Calls `sink` with each intact chunk of points, in order.
    Status forEachPoints(const std::function<void(std::span<const MapPoint>)>& sink) const;

private:
    struct ChunkRef {
        std::uint64_t offset;
        std::uint32_t bytes;
    };
    JournalSummary summary_;
    std::vector<ChunkRef> point_chunks_;
};

// Cuts a damaged tail off so the journal can be appended to or exported; returns the summary.
Result<JournalSummary> recoverJournal(const std::string& path);

}  // namespace handscan::journal
