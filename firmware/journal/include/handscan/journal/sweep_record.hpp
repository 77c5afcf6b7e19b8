// One registered sweep as the scan keeps it: which module solved each direction (section 8,
// figure 14), the tracking monitor's verdict, the matcher's figures, where the sweep was placed,
// and how many samples of each device the pipeline took since the previous sweep. The worker
// makes one per sweep handed on; the daemon journals it (ChunkKind::kSweepStats), replay journals
// it and writes it as stats.json's per_sweep, and the export's report draws its timeline and the
// devices' rates from it.
#pragma once

#include <cstdint>
#include <string>

namespace handscan::journal {

enum class SweepTracking : std::uint8_t { kOk = 0, kRejected = 1, kLost = 2 };
// The visual-inertial odometry during the sweep: not running, running, bypassed (section 8).
enum class SweepVio : std::uint8_t { kOff = 0, kRunning = 1, kBypassed = 2 };

// Samples of each device the pipeline took in a window of sample time (rates: count / window).
struct DeviceCounts {
    double window_s = 0.0;  // sample time covered, since the previous sweep's record
    std::uint32_t laser_scans = 0, imu_samples = 0, encoder_samples = 0;
    std::uint32_t colour_frames = 0, tracking_frames = 0;
};

struct SweepRecord {
    double t_start_s = 0.0;  // sweep start, seconds of the scan clock (as MapPoint::t_s)
    std::uint64_t index = 0;
    std::uint8_t solved_mask = 0;  // the scan matcher's, bit k: direction k (rx ry rz tx ty tz)
    std::uint8_t vio_mask = 0;     // the VIO's over the sweep's prior
    SweepTracking tracking = SweepTracking::kOk;
    bool in_map = true;  // consistent and not lost: its points entered the map and journal
    SweepVio vio = SweepVio::kOff;
    std::uint32_t points = 0, edges = 0, planars = 0;
    std::int32_t associations = 0;
    double rms_m = 0.0, total_ms = 0.0;
    double pose[7] = {0, 0, 0, 0, 0, 0, 1};  // T_world_body at t_start: x y z qx qy qz qw
    double prior_xyz[3] = {0, 0, 0};         // the match's prior (IMU prediction)
    DeviceCounts devices;
    std::string tracking_reason;  // fusion::lostReasonName when the monitor gave one, else ""

    // Directions no module of the laser solved (section 8): 6 minus the matcher's.
    int degenerateDirections() const;
};

const char* sweepTrackingName(SweepTracking t);  // "ok", "rejected", "lost" (stats.json)

}  // namespace handscan::journal
