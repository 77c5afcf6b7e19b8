// LiveMapWriter: the pipeline's side of the live-map region. One writer per region: it publishes
// the 200 Hz pose ring, the status block and the append-only display map, and takes commands from
// the UIs. Nothing here blocks or allocates on the publish paths (poses, points, status), so the
// daemon can call it from its output thread at sensor rate.
//
//   auto w = LiveMapWriter::create({.name = "/handscan-live"});
//   w->publishPose(pose);                 // every IMU-rate pose
//   w->appendPoints(new_voxels);          // each map update
//   w->setStatus(status);                 // ~10 Hz
//   w->setChanges(report);                // a continued scan's change cells, 0.5 Hz
//   while (auto cmd = w->pollCommand()) { ...; w->ack(cmd->seq, CommandState::kDone, "ok"); }
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "handscan/core/samples.hpp"
#include "handscan/core/status.hpp"
#include "handscan/shm/layout.hpp"
#include "handscan/shm/shared_region.hpp"

namespace handscan::shm {

struct WriterOptions {
    std::string name = kDefaultRegionName;
    std::size_t map_capacity_points = std::size_t{4} << 20;  // 64 MiB of display points
    bool unlink_on_close = true;        // remove the name when the writer goes away cleanly
    double track_min_step_m = 0.05;     // decimation of the stored trajectory
    double track_max_interval_s = 1.0;  // ... but at least one track point per second
};

// A command taken from a UI.
struct Command {
    std::uint64_t seq = 0;
    CommandType type = CommandType::kNone;
    std::string argument;
    TimeNs sent_ns = 0;
};

// Pose record of an estimate. Without explicit masks the estimate's own solved-DOF mask is
// attributed to the module that produced it (VIO -> green, scan matching / integrated -> blue).
PoseRecord toPoseRecord(const PoseEstimate& pose);
PoseRecord toPoseRecord(const PoseEstimate& pose, std::uint8_t vio_dof_mask,
                        std::uint8_t scan_dof_mask);

class LiveMapWriter {
public:
    // Creates (replacing) the named region and starts publishing.
    static Result<std::unique_ptr<LiveMapWriter>> create(const WriterOptions& options);
    // Initialises an already-mapped region (anonymous mappings in tests). The region must hold
    // regionBytes(options.map_capacity_points) bytes.
    static Result<std::unique_ptr<LiveMapWriter>> attach(std::shared_ptr<SharedRegion> region,
                                                         const WriterOptions& options);
    ~LiveMapWriter();  // marks the region closed (readers show "pipeline stopped")
    LiveMapWriter(const LiveMapWriter&) = delete;
    LiveMapWriter& operator=(const LiveMapWriter&) = delete;

    void publishPose(const PoseEstimate& pose) { publishPose(toPoseRecord(pose)); }
    void publishPose(const PoseRecord& pose);
    // Appends display points to the current scan's map. kNoSpace (points dropped, the rest kept)
    // when the display capacity is exhausted; the full-resolution map is not affected.
    [[nodiscard]] Status appendPoints(std::span<const DisplayPoint> points);
    void setStatus(const StatusBlock& status);
    // Replaces the change report (stamped with the current epoch and time; at most
    // kMaxChangeCells cells are taken). A new scan empties it.
    void setChanges(const ChangeReport& report);
    // Replaces the list of scans that can be continued (count capped at kMaxListedScans).
    void setScanList(const ScanList& scans);
    // Starts a new scan: empties map and trajectory and changes the epoch so readers drop theirs.
    void newScan();
    // Appends to the drawn path only (not the pose ring), thinned as publishPose's: an earlier
    // scan's path shown under a continued one.
    void appendTrack(const PoseRecord& pose);
    // Updates the heartbeat only (publishes do it too); call at least every second when idle.
    void heartbeat();

    // The oldest command not yet returned, if any.
    std::optional<Command> pollCommand();
    // Answers command `seq` (call repeatedly with kInProgress for progress).
    void ack(std::uint64_t seq, CommandState state, std::string_view message,
             float progress = 0.0f);

    std::uint64_t epoch() const;
    std::uint64_t mapPoints() const;
    std::uint64_t mapCapacity() const { return capacity_; }
    std::uint64_t nonce() const { return nonce_; }
    const SharedRegion& region() const { return *region_; }

private:
    LiveMapWriter(std::shared_ptr<SharedRegion> region, const WriterOptions& options);
    RegionHeader& header() const { return *reinterpret_cast<RegionHeader*>(region_->data()); }
    DisplayPoint* points() const;
    void clearChanges();  // an empty report of the current epoch

    std::shared_ptr<SharedRegion> region_;
    WriterOptions options_;
    std::uint64_t capacity_ = 0;
    std::uint64_t nonce_ = 0;
    std::array<std::uint64_t, kCommandSlots> processed_{};  // last seq taken from each slot
    std::optional<PoseRecord> last_track_;
};

}  // namespace handscan::shm
