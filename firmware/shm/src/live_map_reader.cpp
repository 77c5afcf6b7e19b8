// A UI's side of the live-map region.
#include "handscan/shm/live_map_reader.hpp"

#include <algorithm>
#include <atomic>

#include "handscan/shm/seqlock.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::shm {

const char* toString(Connection c) {
    switch (c) {
        case Connection::kWaiting:
            return "waiting for pipeline";
        case Connection::kIncompatible:
            return "incompatible pipeline";
        case Connection::kConnected:
            return "connected";
        case Connection::kStale:
            return "pipeline not responding";
        case Connection::kClosed:
            return "pipeline stopped";
    }
    return "unknown";
}

LiveMapReader::LiveMapReader(ReaderOptions options) : options_(std::move(options)) {
    message_ = "waiting for pipeline (no shared memory " + options_.name + ")";
}

LiveMapReader::LiveMapReader(std::shared_ptr<SharedRegion> region, ReaderOptions options)
    : options_(std::move(options)), follow_name_(false) {
    if (Status s = validate(*region); s) {
        region_ = std::move(region);
        connection_ = Connection::kConnected;
    } else {
        message_ = s.message();
    }
}

RegionHeader* LiveMapReader::header() const {
    return region_ ? reinterpret_cast<RegionHeader*>(region_->data()) : nullptr;
}

Status LiveMapReader::validate(const SharedRegion& region) const {
    const std::string where =
        region.name().empty() ? std::string("live-map region") : "shared memory " + region.name();
    if (region.size() < sizeof(RegionHeader)) {
        return {StatusCode::kTruncated,
                where + ": " + std::to_string(region.size()) + " bytes, smaller than a header"};
    }
    auto& h = *reinterpret_cast<RegionHeader*>(region.data());
    if (atomicWord(h.magic).load(std::memory_order_acquire) != kMagic) {
        return {StatusCode::kNotFound, where + ": writer still initialising"};
    }
    if (h.version != kLayoutVersion || h.header_bytes != sizeof(RegionHeader)) {
        return {StatusCode::kUnsupported, where + ": layout version " + std::to_string(h.version) +
                                              ", this program understands " +
                                              std::to_string(kLayoutVersion) +
                                              ": install matching handscan and handscan-ui"};
    }
    const std::uint64_t cap = atomicWord(h.map_capacity_points).load(std::memory_order_relaxed);
    if (atomicWord(h.points_offset).load(std::memory_order_relaxed) != sizeof(RegionHeader) ||
        regionBytes(cap) > region.size()) {
        return {StatusCode::kTruncated, where + ": " + std::to_string(region.size()) +
                                            " bytes cannot hold " + std::to_string(cap) +
                                            " points (corrupt header?)"};
    }
    return Status::ok();
}

void LiveMapReader::connect() {
    auto opened = SharedRegion::open(options_.name);
    if (!opened) {
        region_.reset();
        connection_ = Connection::kWaiting;
        message_ = "waiting for pipeline (" + opened.status().message() + ")";
        return;
    }
    if (Status s = validate(**opened); !s) {
        region_.reset();
        connection_ =
            s.code() == StatusCode::kUnsupported ? Connection::kIncompatible : Connection::kWaiting;
        message_ = s.code() == StatusCode::kUnsupported
                       ? s.message()
                       : "waiting for pipeline (" + s.message() + ")";
        return;
    }
    region_ = std::move(*opened);
    connection_ = Connection::kConnected;
    message_.clear();
}

Connection LiveMapReader::poll() {
    const TimeNs now = monotonicNow();
    if (follow_name_ && now >= next_check_ns_) {
        next_check_ns_ = now + options_.recheck_interval_ns;
        if (!region_) {
            connect();
        } else {
            // A restarted writer made a new object under the same name: move over to it.
            auto id = SharedRegion::identityOf(options_.name);
            if (id && !(*id == region_->identity())) connect();
        }
    }
    RegionHeader* h = header();
    if (!h) return connection_;
    const auto state =
        static_cast<WriterState>(atomicWord(h->writer_state).load(std::memory_order_acquire));
    const double age = heartbeatAgeSeconds();
    if (state == WriterState::kClosed) {
        connection_ = Connection::kClosed;
        message_ =
            "pipeline stopped (pid " + std::to_string(writerPid()) + "); waiting for it to restart";
    } else if (age * 1e9 > static_cast<double>(options_.stale_after_ns)) {
        connection_ = Connection::kStale;
        message_ = "pipeline not responding for " + std::to_string(static_cast<int>(age)) +
                   " s (pid " + std::to_string(writerPid()) + ")";
    } else {
        connection_ = Connection::kConnected;
        message_.clear();
    }
    return connection_;
}

std::uint64_t LiveMapReader::writerNonce() const {
    RegionHeader* h = header();
    return h ? atomicWord(h->writer_nonce).load(std::memory_order_relaxed) : 0;
}
std::uint64_t LiveMapReader::writerPid() const {
    RegionHeader* h = header();
    return h ? atomicWord(h->writer_pid).load(std::memory_order_relaxed) : 0;
}
double LiveMapReader::heartbeatAgeSeconds() const {
    RegionHeader* h = header();
    if (!h) return 0.0;
    return toSeconds(monotonicNow() - atomicWord(h->heartbeat_ns).load(std::memory_order_acquire));
}
std::uint64_t LiveMapReader::mapCapacity() const {
    RegionHeader* h = header();
    return h ? atomicWord(h->map_capacity_points).load(std::memory_order_relaxed) : 0;
}

std::optional<StatusBlock> LiveMapReader::readStatus() const {
    RegionHeader* h = header();
    if (!h) return std::nullopt;
    StatusBlock s;
    if (!seqlockRead(h->status_lock, h->status, s)) return std::nullopt;
    return s;
}

std::uint64_t LiveMapReader::poseCount() const {
    RegionHeader* h = header();
    return h ? atomicWord(h->pose_count).load(std::memory_order_acquire) : 0;
}

namespace {

// How long a slot stays reserved for an answer its UI has not read (a UI that died meanwhile),
// and for a request the pipeline has not answered at all (a pipeline that is not taking
// commands). A long export keeps its slot: each progress answer renews it.
constexpr TimeNs kUnreadAnswerKeepNs = 2 * kNsPerSec;
constexpr TimeNs kUnansweredRequestKeepNs = 10 * kNsPerSec;

// True while `held` (the request in `slot`, read with the slot claimed) must not be overwritten.
bool slotInUse(CommandSlot& slot, const CommandRequest& held, TimeNs writer_started, TimeNs now) {
    if (held.seq == 0) return false;                  // never used
    if (held.sent_ns < writer_started) return false;  // sent to a previous pipeline
    if (atomicWord(slot.collected_seq).load(std::memory_order_acquire) == held.seq) return false;
    CommandAck ack;
    if (!seqlockRead(slot.ack_lock, slot.ack, ack, 16)) return true;  // being answered right now
    if (ack.seq != held.seq) return now - held.sent_ns < kUnansweredRequestKeepNs;
    if (!isFinal(static_cast<CommandState>(ack.state)))
        return now - ack.t_ns < kUnansweredRequestKeepNs;
    if (!SharedRegion::processExists(held.sender_pid))
        return false;  // its UI died: nobody will read it
    return now - ack.t_ns < kUnreadAnswerKeepNs;
}

// Pose n, if its slot still holds it and it was not being rewritten while we copied.
bool readPoseSlot(PoseSlot& slot, std::uint64_t n, PoseRecord& out) {
    auto seq = atomicWord(slot.seq);
    const std::uint64_t s1 = seq.load(std::memory_order_acquire);
    if (s1 != 2 * n + 2) return false;
    loadRelaxed(out, slot.pose);
    std::atomic_thread_fence(std::memory_order_acquire);
    return seq.load(std::memory_order_relaxed) == s1;
}

}  // namespace

std::optional<PoseRecord> LiveMapReader::latestPose() const {
    RegionHeader* h = header();
    if (!h) return std::nullopt;
    for (int attempt = 0; attempt < 100; ++attempt) {
        const std::uint64_t n = atomicWord(h->pose_count).load(std::memory_order_acquire);
        if (n == 0) return std::nullopt;
        PoseRecord p;
        if (readPoseSlot(h->poses[(n - 1) % kPoseRingCapacity], n - 1, p)) return p;
    }
    return std::nullopt;
}

std::size_t LiveMapReader::readPoses(std::uint64_t& next, std::vector<PoseRecord>& out) const {
    RegionHeader* h = header();
    if (!h) return 0;
    const std::uint64_t n = atomicWord(h->pose_count).load(std::memory_order_acquire);
    if (next > n) next = 0;  // a new writer started counting again
    // Leave a margin: the oldest slots may be overwritten while we read.
    const std::uint64_t oldest = n > kPoseRingCapacity - 8 ? n - (kPoseRingCapacity - 8) : 0;
    std::size_t added = 0;
    for (std::uint64_t i = std::max(next, oldest); i < n; ++i) {
        PoseRecord p;
        if (readPoseSlot(h->poses[i % kPoseRingCapacity], i, p)) {
            out.push_back(p);
            ++added;
        }
    }
    next = n;
    return added;
}

bool LiveMapReader::readMap(MapCursor& cursor, MapDelta& delta, std::size_t max_points) const {
    delta.reset = false;
    delta.points.clear();
    delta.track.clear();
    RegionHeader* h = header();
    if (!h) return false;
    auto lock = atomicWord(h->map_lock);
    const std::uint64_t l1 = lock.load(std::memory_order_acquire);
    if (l1 & 1u) return false;
    MapCursor c = cursor;
    const std::uint64_t nonce = atomicWord(h->writer_nonce).load(std::memory_order_relaxed);
    if (c.nonce != nonce || c.epoch != l1 / 2) {
        c = MapCursor{nonce, l1 / 2, 0, 0};
        delta.reset = true;
    }
    const std::uint64_t cap = atomicWord(h->map_capacity_points).load(std::memory_order_relaxed);
    const std::uint64_t np =
        std::min(atomicWord(h->map_points).load(std::memory_order_acquire), cap);
    const std::uint64_t nt = std::min<std::uint64_t>(
        atomicWord(h->track_points).load(std::memory_order_acquire), kTrackCapacity);
    const std::uint64_t from = std::min(c.points, np);
    const std::uint64_t to = from + std::min<std::uint64_t>(np - from, max_points);
    const auto* pts = reinterpret_cast<const DisplayPoint*>(region_->data() + sizeof(RegionHeader));
    delta.points.resize(to - from);
    loadWordsRelaxed(delta.points.data(), pts + from, (to - from) * sizeof(DisplayPoint));
    const std::uint64_t tfrom = std::min(c.track, nt);
    delta.track.resize(nt - tfrom);
    loadWordsRelaxed(delta.track.data(), h->track + tfrom, (nt - tfrom) * sizeof(TrackPoint));
    std::atomic_thread_fence(std::memory_order_acquire);
    if (lock.load(std::memory_order_relaxed) != l1) {  // a new scan started while we copied
        delta.reset = false;
        delta.points.clear();
        delta.track.clear();
        return false;
    }
    c.points = to;
    c.track = nt;
    delta.epoch = c.epoch;
    cursor = c;
    return true;
}

bool LiveMapReader::readChanges(ChangesCursor& cursor, ChangeReport& out) const {
    RegionHeader* h = header();
    if (!h) return false;
    const std::uint64_t nonce = atomicWord(h->writer_nonce).load(std::memory_order_relaxed);
    const std::uint64_t lock = atomicWord(h->changes_lock).load(std::memory_order_acquire);
    if (nonce == cursor.nonce && lock == cursor.lock) return false;
    if (!seqlockTryRead(h->changes_lock, h->changes, out) ||
        atomicWord(h->changes_lock).load(std::memory_order_relaxed) != lock)
        return false;
    out.count = std::min<std::uint32_t>(out.count, kMaxChangeCells);
    cursor = {nonce, lock};
    return true;
}

std::optional<ScanList> LiveMapReader::readScanList() const {
    RegionHeader* h = header();
    ScanList l;
    if (!h || !seqlockRead(h->scans_lock, h->scans, l)) return std::nullopt;
    l.count = std::min<std::uint32_t>(l.count, kMaxListedScans);
    return l;
}

Result<std::uint64_t> LiveMapReader::sendCommand(CommandType type, std::string_view argument) {
    RegionHeader* h = header();
    if (!h || connection_ == Connection::kClosed) {
        return Status{StatusCode::kDisconnected, std::string("cannot send ") + toString(type) +
                                                     ": " +
                                                     (message_.empty() ? "no pipeline" : message_)};
    }
    CommandRequest req;
    req.type = static_cast<std::uint32_t>(type);
    req.sent_ns = monotonicNow();
    req.sender_pid = static_cast<std::uint32_t>(SharedRegion::currentProcessId());
    setText(req.argument, argument);
    // Each try claims a fresh sequence number and its slot; a slot still held by another UI (or by
    // one that crashed mid-write) is skipped rather than waited for, and so is a slot whose command
    // is still in flight or whose answer its UI has not read yet: other UIs' traffic never loses a
    // command (the check runs with the slot claimed, so two UIs cannot both take it).
    const TimeNs writer_started = atomicWord(h->writer_started_ns).load(std::memory_order_relaxed);
    for (std::size_t attempt = 0; attempt < 2 * kCommandSlots; ++attempt) {
        const std::uint64_t seq =
            atomicWord(h->next_command_seq).fetch_add(1, std::memory_order_relaxed) + 1;
        CommandSlot& slot = h->commands[seq % kCommandSlots];
        auto lock = atomicWord(slot.request_lock);
        std::uint64_t s = lock.load(std::memory_order_relaxed);
        if ((s & 1u) || !lock.compare_exchange_strong(s, s + 1, std::memory_order_acquire,
                                                      std::memory_order_relaxed)) {
            continue;
        }
        CommandRequest held;
        loadRelaxed(held, slot.request);
        if (slotInUse(slot, held, writer_started, req.sent_ns)) {
            lock.store(s + 2, std::memory_order_release);  // unchanged: readers' copies stay valid
            continue;
        }
        std::atomic_thread_fence(std::memory_order_release);
        req.seq = seq;
        storeRelaxed(slot.request, req);
        lock.store(s + 2, std::memory_order_release);
        sent_nonce_ = writerNonce();
        return seq;
    }
    return Status{StatusCode::kTimeout,
                  std::string("cannot send ") + toString(type) +
                      ": every command slot is busy (pipeline not taking commands?)"};
}

Result<CommandAck> LiveMapReader::commandResult(std::uint64_t seq) const {
    RegionHeader* h = header();
    if (!h) return Status{StatusCode::kDisconnected, "no pipeline: " + message_};
    if (writerNonce() != sent_nonce_) {
        return Status{StatusCode::kNotFound,
                      "command " + std::to_string(seq) + " was lost: the pipeline restarted"};
    }
    CommandSlot& slot = h->commands[seq % kCommandSlots];
    CommandRequest req;
    CommandAck ack;
    if (!seqlockRead(slot.request_lock, slot.request, req) ||
        !seqlockRead(slot.ack_lock, slot.ack, ack)) {
        return Status{StatusCode::kTimeout, "command slot busy, try again"};
    }
    if (req.seq != seq) {
        return Status{StatusCode::kNotFound,
                      "command " + std::to_string(seq) + " no longer tracked (slot reused)"};
    }
    if (ack.seq != seq) {
        CommandAck pending;
        pending.seq = seq;
        pending.state = static_cast<std::uint32_t>(CommandState::kPending);
        return pending;
    }
    if (isFinal(static_cast<CommandState>(ack.state))) {
        atomicWord(slot.collected_seq)
            .store(seq, std::memory_order_release);  // the slot may be reused
    }
    return ack;
}

}  // namespace handscan::shm
