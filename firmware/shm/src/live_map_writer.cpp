// The pipeline's side of the live-map region.
#include "handscan/shm/live_map_writer.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>

#include "handscan/core/time.hpp"
#include "handscan/shm/seqlock.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::shm {
namespace {

std::uint64_t freshNonce() {
    std::random_device rd;
    const std::uint64_t r = (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
    const std::uint64_t n =
        r ^ static_cast<std::uint64_t>(monotonicNow()) ^ (SharedRegion::currentProcessId() << 48);
    return n == 0 ? 1 : n;  // 0 means "no writer seen yet" to readers
}

}  // namespace

PoseRecord toPoseRecord(const PoseEstimate& pose, std::uint8_t vio_dof_mask,
                        std::uint8_t scan_dof_mask) {
    PoseRecord r;
    r.t_ns = pose.t_host;
    const Eigen::Vector3d p = pose.T_world_body.translation();
    const Eigen::Quaterniond q(pose.T_world_body.rotation());
    for (int i = 0; i < 3; ++i) r.position_m[i] = p[i];
    r.orientation_xyzw[0] = q.x();
    r.orientation_xyzw[1] = q.y();
    r.orientation_xyzw[2] = q.z();
    r.orientation_xyzw[3] = q.w();
    for (int i = 0; i < 6; ++i) r.covariance_diag[i] = static_cast<float>(pose.covariance(i, i));
    r.vio_dof_mask = vio_dof_mask & 0x3F;
    r.scan_dof_mask = scan_dof_mask & 0x3F;
    r.source = static_cast<std::uint8_t>(pose.source);
    return r;
}

PoseRecord toPoseRecord(const PoseEstimate& pose) {
    switch (pose.source) {
        case PoseSource::kVisualOdometry:
            return toPoseRecord(pose, pose.solved_dof_mask, 0);
        case PoseSource::kScanMatching:
        case PoseSource::kIntegrated:
            return toPoseRecord(pose, pose.visual_solved_dof_mask, pose.solved_dof_mask);
        case PoseSource::kImuPrediction:
            break;
    }
    return toPoseRecord(pose, 0, 0);
}

Result<std::unique_ptr<LiveMapWriter>> LiveMapWriter::create(const WriterOptions& options) {
    auto region = SharedRegion::create(options.name, regionBytes(options.map_capacity_points));
    if (!region) return region.status();
    return attach(std::move(*region), options);
}

Result<std::unique_ptr<LiveMapWriter>> LiveMapWriter::attach(std::shared_ptr<SharedRegion> region,
                                                             const WriterOptions& options) {
    if (!region || region->size() < regionBytes(options.map_capacity_points)) {
        return Status{StatusCode::kInvalidArgument,
                      "live-map region too small for " +
                          std::to_string(options.map_capacity_points) + " points: need " +
                          std::to_string(regionBytes(options.map_capacity_points)) + " bytes"};
    }
    return std::unique_ptr<LiveMapWriter>(new LiveMapWriter(std::move(region), options));
}

LiveMapWriter::LiveMapWriter(std::shared_ptr<SharedRegion> region, const WriterOptions& options)
    : region_(std::move(region)),
      options_(options),
      capacity_(options.map_capacity_points),
      nonce_(freshNonce()) {
    RegionHeader& h = header();
    // Readers accept the region only once the magic is there (stored last, with release), so
    // they never see a half-initialised header.
    atomicWord(h.magic).store(0, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    h.version = kLayoutVersion;
    h.header_bytes = sizeof(RegionHeader);
    atomicWord(h.total_bytes).store(region_->size(), std::memory_order_relaxed);
    atomicWord(h.map_capacity_points).store(capacity_, std::memory_order_relaxed);
    atomicWord(h.points_offset).store(sizeof(RegionHeader), std::memory_order_relaxed);
    atomicWord(h.writer_nonce).store(nonce_, std::memory_order_relaxed);
    atomicWord(h.writer_pid).store(SharedRegion::currentProcessId(), std::memory_order_relaxed);
    atomicWord(h.writer_started_ns).store(monotonicNow(), std::memory_order_relaxed);
    atomicWord(h.heartbeat_ns).store(monotonicNow(), std::memory_order_relaxed);
    atomicWord(h.writer_state)
        .store(static_cast<std::uint64_t>(WriterState::kRunning), std::memory_order_relaxed);
    // A re-used region (tests) starts a new epoch so readers drop the previous writer's map.
    auto lock = atomicWord(h.map_lock);
    const std::uint64_t s = lock.load(std::memory_order_relaxed);
    lock.store(s + (s & 1u ? 1 : 2), std::memory_order_relaxed);
    atomicWord(h.map_points).store(0, std::memory_order_relaxed);
    atomicWord(h.track_points).store(0, std::memory_order_relaxed);
    clearChanges();
    const ScanList no_scans;  // the daemon lists its own
    seqlockWrite(h.scans_lock, h.scans, no_scans);
    // Re-attaching to a used region continues its counters so readers see changes, not repeats.
    for (std::size_t i = 0; i < kCommandSlots; ++i) {
        CommandRequest req;
        if (seqlockRead(h.commands[i].request_lock, h.commands[i].request, req))
            processed_[i] = req.seq;
    }
    atomicWord(h.magic).store(kMagic, std::memory_order_release);
}

LiveMapWriter::~LiveMapWriter() {
    atomicWord(header().writer_state)
        .store(static_cast<std::uint64_t>(WriterState::kClosed), std::memory_order_release);
    if (options_.unlink_on_close && !region_->name().empty()) {
        // Only remove the name if it is still ours (a newer writer may have replaced it).
        auto id = SharedRegion::identityOf(region_->name());
        if (id && *id == region_->identity()) SharedRegion::unlink(region_->name());
    }
}

DisplayPoint* LiveMapWriter::points() const {
    return reinterpret_cast<DisplayPoint*>(region_->data() + sizeof(RegionHeader));
}

void LiveMapWriter::heartbeat() {
    atomicWord(header().heartbeat_ns).store(monotonicNow(), std::memory_order_release);
}

void LiveMapWriter::publishPose(const PoseRecord& pose) {
    RegionHeader& h = header();
    auto count = atomicWord(h.pose_count);
    const std::uint64_t n = count.load(std::memory_order_relaxed);
    PoseSlot& slot = h.poses[n % kPoseRingCapacity];
    auto seq = atomicWord(slot.seq);
    seq.store(2 * n + 1, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    storeRelaxed(slot.pose, pose);
    seq.store(2 * n + 2, std::memory_order_release);
    count.store(n + 1, std::memory_order_release);
    appendTrack(pose);
    heartbeat();
}

void LiveMapWriter::appendTrack(const PoseRecord& pose) {
    if (last_track_) {
        const double dx = pose.position_m[0] - last_track_->position_m[0];
        const double dy = pose.position_m[1] - last_track_->position_m[1];
        const double dz = pose.position_m[2] - last_track_->position_m[2];
        const bool moved = std::sqrt(dx * dx + dy * dy + dz * dz) >= options_.track_min_step_m;
        const bool waited =
            toSeconds(pose.t_ns - last_track_->t_ns) >= options_.track_max_interval_s;
        if (!moved && !waited) return;
    }
    RegionHeader& h = header();
    auto committed = atomicWord(h.track_points);
    const std::uint64_t n = committed.load(std::memory_order_relaxed);
    if (n >= kTrackCapacity)
        return;  // the pose ring still has the latest; the drawn path stops growing
    TrackPoint tp;
    tp.t_ns = pose.t_ns;
    tp.x_m = static_cast<float>(pose.position_m[0]);
    tp.y_m = static_cast<float>(pose.position_m[1]);
    tp.z_m = static_cast<float>(pose.position_m[2]);
    storeRelaxed(h.track[n], tp);
    committed.store(n + 1, std::memory_order_release);
    last_track_ = pose;
}

Status LiveMapWriter::appendPoints(std::span<const DisplayPoint> new_points) {
    RegionHeader& h = header();
    auto committed = atomicWord(h.map_points);
    const std::uint64_t n = committed.load(std::memory_order_relaxed);
    const std::uint64_t room = capacity_ - n;
    const std::uint64_t take = std::min<std::uint64_t>(room, new_points.size());
    // Points beyond the committed count are invisible to readers, so plain word stores suffice;
    // the release store of the count publishes them.
    storeWordsRelaxed(points() + n, new_points.data(), take * sizeof(DisplayPoint));
    committed.store(n + take, std::memory_order_release);
    heartbeat();
    if (take < new_points.size()) {
        return {StatusCode::kNoSpace,
                "live map display capacity of " + std::to_string(capacity_) +
                    " points reached: " + std::to_string(new_points.size() - take) +
                    " points not shown (the recorded map is complete; raise "
                    "map_capacity_points or use a coarser display voxel)"};
    }
    return Status::ok();
}

void LiveMapWriter::setStatus(const StatusBlock& status) {
    RegionHeader& h = header();
    seqlockWrite(h.status_lock, h.status, status);
    heartbeat();
}

void LiveMapWriter::setChanges(const ChangeReport& report) {
    RegionHeader& h = header();
    ChangeReport r = report;
    r.epoch = epoch();
    r.t_ns = monotonicNow();
    r.count = std::min<std::uint32_t>(r.count, kMaxChangeCells);
    seqlockWrite(h.changes_lock, h.changes, r);
    heartbeat();
}

void LiveMapWriter::setScanList(const ScanList& scans) {
    RegionHeader& h = header();
    ScanList l = scans;
    l.count = std::min<std::uint32_t>(l.count, kMaxListedScans);
    seqlockWrite(h.scans_lock, h.scans, l);
    heartbeat();
}

void LiveMapWriter::clearChanges() {
    RegionHeader& h = header();
    ChangeReport empty;
    empty.epoch = epoch();
    seqlockWrite(h.changes_lock, h.changes, empty);
}

void LiveMapWriter::newScan() {
    RegionHeader& h = header();
    auto lock = atomicWord(h.map_lock);
    const std::uint64_t s = lock.load(std::memory_order_relaxed);
    lock.store(s + 1, std::memory_order_relaxed);  // odd: readers discard what they copy now
    std::atomic_thread_fence(std::memory_order_release);
    atomicWord(h.map_points).store(0, std::memory_order_relaxed);
    atomicWord(h.track_points).store(0, std::memory_order_relaxed);
    lock.store(s + 2, std::memory_order_release);  // next epoch
    clearChanges();                                // the new scan's own report (none yet)
    last_track_.reset();
    heartbeat();
}

std::uint64_t LiveMapWriter::epoch() const {
    return atomicWord(header().map_lock).load(std::memory_order_relaxed) / 2;
}
std::uint64_t LiveMapWriter::mapPoints() const {
    return atomicWord(header().map_points).load(std::memory_order_relaxed);
}

std::optional<Command> LiveMapWriter::pollCommand() {
    RegionHeader& h = header();
    // Oldest pending request over all slots: a UI that claimed a sequence number and was slow to
    // fill its slot is still served, in order of sequence numbers.
    std::optional<std::size_t> best;
    CommandRequest best_req;
    for (std::size_t i = 0; i < kCommandSlots; ++i) {
        CommandRequest req;
        if (!seqlockRead(h.commands[i].request_lock, h.commands[i].request, req, 16))
            continue;  // being written
        if (req.seq == 0 || req.seq == processed_[i]) continue;
        if (!best || req.seq < best_req.seq) {
            best = i;
            best_req = req;
        }
    }
    if (!best) return std::nullopt;
    processed_[*best] = best_req.seq;
    Command cmd;
    cmd.seq = best_req.seq;
    cmd.type = static_cast<CommandType>(best_req.type);
    cmd.argument = std::string(getText(best_req.argument));
    cmd.sent_ns = best_req.sent_ns;
    return cmd;
}

void LiveMapWriter::ack(std::uint64_t seq, CommandState state, std::string_view message,
                        float progress) {
    CommandSlot& slot = header().commands[seq % kCommandSlots];
    CommandRequest req;
    // A slot reused by a newer request (16 commands in flight) keeps that request's answer.
    if (!seqlockRead(slot.request_lock, slot.request, req) || req.seq != seq) return;
    CommandAck a;
    a.seq = seq;
    a.state = static_cast<std::uint32_t>(state);
    a.progress = std::clamp(progress, 0.0f, 1.0f);
    a.t_ns = monotonicNow();
    setText(a.message, message);
    seqlockWrite(slot.ack_lock, slot.ack, a);
    heartbeat();
}

}  // namespace handscan::shm
