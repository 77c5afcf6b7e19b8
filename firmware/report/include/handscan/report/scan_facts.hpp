// What the report says about a scan, gathered while the export streams its points once: duration,
// walked distance, point count and coloured share, the sensors' health over time from the journal
// (laser points per second, the camera's coloured share, the pose rate, and the dropouts where
// either stopped), the intervals where the matcher left a direction degenerate, which module solved
// each direction per sweep, where tracking was lost and where the camera's VIO was bypassed, each
// device's sample rate per sweep and its dropouts (from the journal's per-sweep records, which the
// daemon and replay both write; for an older journal from the replay's stats.json beside it), and
// the loop-closure gap when the walk came back to where it started.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/journal/map_point.hpp"
#include "handscan/journal/sweep_record.hpp"

namespace handscan::report {

struct HealthBin {
    double t_s = 0.0;  // start of the bin, seconds from the scan's start
    std::uint64_t points = 0, coloured = 0, poses = 0;
};

struct Interval {
    double from_s = 0.0, to_s = 0.0;  // seconds from the scan's start
    int directions = 0;               // degenerate directions (most in the interval)
    std::string what;                 // why (tracking lost: the monitor's reason)
};

// Which module solved each direction in one sweep (section 8, figure 14): the scan matcher's
// solved mask, the visual-inertial odometry's, and the tracking monitor's verdict. A direction
// neither solved was held from the IMU prediction.
struct SweepModules {
    double t_s = 0.0;                             // sweep start, seconds from the scan's start
    std::uint8_t scan_mask = 0x3F, vio_mask = 0;  // bit k: direction k (rx ry rz tx ty tz)
    char tracking = 'o';                          // 'o' ok, 'r' rejected, 'l' lost
};

// Each device's samples per second over one sweep's window (the pipeline's intake).
struct DeviceRates {
    double t_s = 0.0;  // sweep start, seconds from the scan's start
    double laser_hz = 0, imu_hz = 0, encoder_hz = 0, colour_hz = 0, tracking_hz = 0;
};

struct ScanFacts {
    double t0_s = 0.0;  // scan clock at the start
    double duration_s = 0.0;
    double distance_m = 0.0;  // along the trajectory
    std::uint64_t points = 0, coloured = 0;
    double bin_s = 1.0;
    std::vector<HealthBin> bins;
    std::vector<Interval> laser_dropouts, pose_dropouts;  // no points / no poses for > 1 s
    bool have_sweep_stats = false;
    std::vector<std::pair<double, int>> sweep_degenerate;  // (t from start, directions)
    std::vector<Interval> degenerate;
    std::vector<SweepModules> sweep_modules;  // from stats.json's per_sweep
    std::vector<Interval> tracking_lost;      // stats.json tracking.lost_intervals
    bool have_vio = false;                    // stats.json has a vio block (the VIO ran)
    double vio_from_s = 0.0;                  // its first frame
    std::vector<Interval> vio_bypassed;       // stats.json vio.bypassed
    std::string sweep_source;  // where the per-sweep facts came from ("journal", "stats.json")
    std::vector<DeviceRates> device_rates;  // per sweep (journal records only)
    // Sweep windows in which a device that delivered elsewhere in the scan delivered nothing
    // (`what`: the device).
    std::vector<Interval> device_dropouts;
    std::optional<double> loop_gap_m;  // end-to-start distance when the walk closed a loop
    std::string loop_note;             // why there is, or is not, a gap
};

class ScanFactsBuilder {
public:
    void add(std::span<const journal::MapPoint> points);
    // `sweeps`: the journal's per-sweep records; without any, `stats_json`: a replay's
    // stats.json (per_sweep degenerate_directions), or empty.
    ScanFacts finish(std::span<const journal::TrajectoryPose> trajectory,
                     std::span<const journal::SweepRecord> sweeps,
                     const std::string& stats_json) const;
    ScanFacts finish(std::span<const journal::TrajectoryPose> trajectory,
                     const std::string& stats_json) const {
        return finish(trajectory, {}, stats_json);
    }

private:
    struct Second {
        std::uint64_t points = 0, coloured = 0;
    };
    std::map<std::int64_t, Second> seconds_;  // by whole second of the scan clock
    std::int64_t last_key_ = 0;
    Second* last_ = nullptr;
    std::uint64_t points_ = 0, coloured_ = 0;
};

}  // namespace handscan::report
