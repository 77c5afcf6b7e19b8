// LiveMapReader: a UI's (or test's) side of the live-map region. Any number of readers; none of
// them can stall the writer. The reader finds the region by name, notices when the writer stops,
// hangs or is replaced by a new one (new object identity or writer nonce), and reconnects; a
// caller keeps a MapCursor and gets only what is new since its last call, plus a `reset` flag
// when it must drop what it has (new scan or new writer).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"
#include "handscan/shm/layout.hpp"
#include "handscan/shm/shared_region.hpp"

namespace handscan::shm {

struct ReaderOptions {
    std::string name = kDefaultRegionName;
    TimeNs stale_after_ns =
        2 * kNsPerSec;  // heartbeat age after which the writer is "not responding"
    TimeNs recheck_interval_ns = 250 * kNsPerMs;  // how often poll() looks for a replaced region
};

enum class Connection {
    kWaiting,       // no region (pipeline not started) or still initialising
    kIncompatible,  // a region of another layout version: message() says which
    kConnected,
    kStale,   // region there, but the writer has not published for stale_after_ns
    kClosed,  // the writer went away cleanly; last data still readable
};
const char* toString(Connection c);

// Where a reader is in the map. Default-constructed = nothing read yet.
struct MapCursor {
    std::uint64_t nonce = 0;
    std::uint64_t epoch = ~std::uint64_t{0};
    std::uint64_t points = 0;
    std::uint64_t track = 0;
};

// Which change report a reader holds (see LiveMapReader::readChanges).
struct ChangesCursor {
    std::uint64_t nonce = 0;  // the writer's
    std::uint64_t lock = 0;   // the report's seqlock counter when it was read
};

struct MapDelta {
    bool reset = false;  // drop everything read before (new scan or new writer)
    std::uint64_t epoch = 0;
    std::vector<DisplayPoint> points;  // new points, in append order
    std::vector<TrackPoint> track;     // new trajectory points
};

class LiveMapReader {
public:
    // Follows the named region, reconnecting as writers come and go.
    explicit LiveMapReader(ReaderOptions options);
    // Reads a fixed region (tests: anonymous mapping shared with a writer in this process).
    explicit LiveMapReader(std::shared_ptr<SharedRegion> region, ReaderOptions options = {});

    // Looks after the connection; cheap (a clock read, plus an fstat every recheck interval).
    Connection poll();
    Connection connection() const { return connection_; }
    const std::string& message() const { return message_; }  // why not connected
    std::uint64_t writerNonce() const;
    std::uint64_t writerPid() const;
    double heartbeatAgeSeconds() const;
    std::uint64_t mapCapacity() const;

    // Whole status block; nullopt without a region or if the writer kept rewriting it.
    std::optional<StatusBlock> readStatus() const;
    // Most recent pose.
    std::optional<PoseRecord> latestPose() const;
    // Poses from index `next` on (older ones already overwritten are skipped); advances `next`.
    std::size_t readPoses(std::uint64_t& next, std::vector<PoseRecord>& out) const;
    std::uint64_t poseCount() const;
    // New map points and trajectory since `cursor` (at most max_points points). False if nothing
    // could be read consistently right now (new scan being started): try again next frame.
    bool readMap(MapCursor& cursor, MapDelta& delta,
                 std::size_t max_points = ~std::size_t{0}) const;

    // The change report of a continued scan, when it is not the one `cursor` holds (a new
    // publication, or a new writer); false when unchanged or being rewritten (try next frame).
    // Its epoch says which scan it belongs to: one of an earlier epoch than the map's is stale.
    bool readChanges(ChangesCursor& cursor, ChangeReport& out) const;

    // The scans that can be continued (nullopt without a region or while being rewritten).
    std::optional<ScanList> readScanList() const;

    // Sends a command; returns its sequence number for commandResult().
    Result<std::uint64_t> sendCommand(CommandType type, std::string_view argument = {});
    // Latest answer to command `seq`: kPending until the pipeline answers; kNotFound if the slot
    // has since been reused or the writer was replaced.
    Result<CommandAck> commandResult(std::uint64_t seq) const;

private:
    RegionHeader* header() const;
    void connect();
    Status validate(const SharedRegion& region) const;

    ReaderOptions options_;
    bool follow_name_ = true;
    std::shared_ptr<SharedRegion> region_;
    Connection connection_ = Connection::kWaiting;
    std::string message_;
    TimeNs next_check_ns_ = 0;
    std::uint64_t sent_nonce_ = 0;  // writer nonce when our commands were sent
};

}  // namespace handscan::shm
