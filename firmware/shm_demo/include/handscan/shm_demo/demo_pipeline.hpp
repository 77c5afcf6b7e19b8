// DemoPipeline: stands in for the pipeline daemon behind the live-map region until replay and the
// daemon publish real output. It answers the UI's commands the way the daemon will (start / stop /
// new scan / export / shutdown, with acknowledgements and export progress), walks a synthetic
// room while scanning, and publishes 200 Hz poses, display points and a 10 Hz status block.
// Faults can be injected so the UI's warnings can be shown and tested.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "handscan/shm/live_map_writer.hpp"
#include "handscan/shm_demo/synthetic_room.hpp"

namespace handscan::shm_demo {

struct DemoFaults {
    bool camera_dark = false;       // tracking camera brightness 8/255, VIO bypassed
    bool laser_degenerate = false;  // scan matching degenerate along tx (a long corridor)
    bool sensor_lost = false;       // the colour camera disconnected with an error text
    bool too_fast = false;          // walking speed and turn rate above the UI's limits
};

struct DemoOptions {
    RoomOptions room;
    int samples_per_second = 40000;    // surface samples drawn per second (before voxel filter)
    std::string export_root = "/tmp";  // where an export without a target argument goes
    std::string preview_png;  // the map's picture for the UI after an export ("" writes none)
    DemoFaults faults;
};

class DemoPipeline {
public:
    DemoPipeline(shm::LiveMapWriter& writer, DemoOptions options);
    // Advances to `now` (host monotonic): handles commands, then publishes what a scan produces.
    void step(TimeNs now);
    void startScan(TimeNs now);
    bool shutdownRequested() const { return shutdown_; }
    shm::ScanState scanState() const { return state_; }
    std::uint64_t pointsPublished() const { return points_; }

private:
    void handle(const shm::Command& cmd, TimeNs now);
    void exportMap(const shm::Command& cmd);
    void writePreview() const;
    void publishStatus(TimeNs now);

    shm::LiveMapWriter& writer_;
    DemoOptions o_;
    SyntheticRoom room_;
    shm::ScanState state_ = shm::ScanState::kIdle;
    bool shutdown_ = false;
    double scan_time_s_ = 0;  // walking time of this scan
    double distance_m_ = 0;
    std::uint64_t points_ = 0;
    TimeNs last_step_ = 0;
    TimeNs last_status_ = 0;
    double sample_debt_ = 0;
    std::optional<Eigen::Vector3d> last_position_;
    shm::ExportStatus export_;
    std::vector<shm::DisplayPoint> map_;  // what has been published this scan (export source)
    int scan_number_ = 0;
};

}  // namespace handscan::shm_demo
