// LivePublisher: the pipeline's output into the live-map shared memory, the same for the daemon
// and `handscan replay --live`: 200 Hz poses, display points (the journaled points thinned to one
// per 5 cm voxel, only voxels not shown yet, in their camera colours), and the status block
// (sensors, modules, scan state, distance, points, free storage, export progress), and a continued
// scan's change report. It keeps the
// scan's elapsed time and walked distance from the poses it publishes while a scan runs.
// Single-threaded: the thread that feeds the pipeline owns it.
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/journal/map_point.hpp"
#include "handscan/lio/laser_inertial_odometry.hpp"
#include "handscan/localize/localizer.hpp"
#include "handscan/shm/display_voxel_filter.hpp"
#include "handscan/shm/live_map_writer.hpp"

namespace handscan::live_output {

// One sensor as the status bar shows it.
struct LiveSensor {
    std::string name;  // "hokuyo", "xsens", "encoder", "tracking-cam", ...
    bool connected = false;
    float rate_hz = 0;           // measured
    float expected_rate_hz = 0;  // nominal
    TimeNs last_sample_ns = 0;
    std::string last_error;  // empty when healthy
};

// What the publisher cannot see itself.
struct LiveStatus {
    std::vector<LiveSensor> sensors;
    shm::ScanState scan_state = shm::ScanState::kIdle;
    std::uint64_t point_count = 0;  // full-resolution points of the current scan
    std::string message;            // the pipeline's note to the operator
    std::optional<shm::ExportStatus> export_status;
    std::optional<shm::CalibrationStatus> calibration;
    float camera_brightness = 0;
    shm::LocalizationState localization = shm::LocalizationState::kNone;
    bool can_continue = false;
};

class LivePublisher {
public:
    // `storage_dir`: whose file system's free space is shown as the device's storage.
    static Result<std::unique_ptr<LivePublisher>> create(const shm::WriterOptions& options,
                                                         std::string storage_dir);
    static Result<std::unique_ptr<LivePublisher>> create(const std::string& name,
                                                         std::string storage_dir);

    void pose(const PoseEstimate& pose);
    // The sweep's journaled points (sweepMapPoints) and its match, for the display map.
    void sweep(const lio::RegisteredSweep& sweep, std::span<const journal::MapPoint> points);
    void status(const lio::LaserInertialOdometry& pipeline, const LiveStatus& status);
    // A continued scan's change report (live_output::toChangeReport), published again each time
    // the localizer has used another match to the earlier map: at its 0.5 Hz, not per sweep
    // (Localizer::changes() goes over the earlier map's points). Call it as often as convenient.
    void changes(const localize::Localizer& localizer);
    // Whether poses count towards the scan's elapsed time and distance (replay: always).
    void setScanning(bool scanning) { scanning_ = scanning; }
    // Empties the display map (new epoch) and the scan's time and distance.
    void newScan();
    // After newScan(), the earlier scan this one continues: its display points (already one per
    // display voxel; the new scan's points then fill only voxels it left empty) and its path.
    void showEarlierScan(std::span<const shm::DisplayPoint> points,
                         std::span<const journal::TrajectoryPose> trajectory);
    void heartbeat() { writer_->heartbeat(); }

    double distance_m() const { return distance_m_; }
    double elapsed_s() const { return elapsed_s_; }
    shm::LiveMapWriter& writer() { return *writer_; }

private:
    LivePublisher(std::unique_ptr<shm::LiveMapWriter> writer, std::string storage_dir)
        : writer_(std::move(writer)), storage_dir_(std::move(storage_dir)) {}

    std::unique_ptr<shm::LiveMapWriter> writer_;
    std::string storage_dir_;
    shm::DisplayVoxelFilter shown_voxels_;  // the touch screen shows one point per 5 cm voxel
    bool scanning_ = true;
    std::optional<PoseEstimate> last_pose_;
    double distance_m_ = 0;
    double elapsed_s_ = 0;
    float linear_speed_mps_ = 0;
    float angular_speed_radps_ = 0;
    std::uint8_t last_solved_mask_ = 0x3F;
    std::uint64_t changes_of_matches_ = 0;  // the localizer's used matches the report is of
};

}  // namespace handscan::live_output
