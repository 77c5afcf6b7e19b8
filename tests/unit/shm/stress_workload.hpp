// A writer and a reader workload whose every record is derived from one counter, so a reader can
// tell a torn record (fields from two different writes) from a whole one. Shared by the fork()
// stress test (separate processes) and its thread variant (run under ThreadSanitizer).
#pragma once

#include <chrono>
#include <cstdint>
#include <memory>

#include "handscan/shm/live_map_reader.hpp"
#include "handscan/shm/live_map_writer.hpp"

namespace handscan::shm::stress {

struct ReaderStats {
    std::uint64_t status_reads = 0;
    std::uint64_t pose_reads = 0;
    std::uint64_t points_checked = 0;
    std::uint64_t resets = 0;
    std::uint64_t nonces_seen = 0;
    std::uint64_t commands_sent = 0;
    std::uint64_t commands_answered = 0;
    std::uint64_t commands_lost = 0;  // slot reused or writer replaced before the answer was read
    std::uint64_t torn = 0;           // records whose fields disagree: must stay 0
    std::uint64_t bad_points = 0;   // map points not where append-only order puts them: must stay 0
    std::uint64_t bad_answers = 0;  // acks with the wrong text for their command: must stay 0
};

// Writer: publishes poses, status and points as fast as it can for `duration`, starts a new scan
// every `points_per_scan` points, answers every command with its own sequence number as text.
void runWriter(LiveMapWriter& writer, std::chrono::milliseconds duration,
               std::uint64_t points_per_scan);

// Reader: checks everything it reads for `duration`, sending a command every few iterations.
ReaderStats runReader(LiveMapReader& reader, std::chrono::milliseconds duration);

}  // namespace handscan::shm::stress
