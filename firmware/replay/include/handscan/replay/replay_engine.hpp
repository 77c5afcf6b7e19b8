// `handscan replay`: a recording's raw device streams through the drivers' decoders and the
// pipeline, as fast as possible on the recording's own clock (--fast, deterministic: the same
// recording gives the same bytes out) or at recorded pace, with the outputs a user and the tests
// need: DIR/trajectory.tum (200 Hz rig pose, TUM), DIR/map.ply (registered map), DIR/stats.json
// (per-module cost, real-time factor, sweeps, degenerate directions, peak memory), and
// DIR/journal.hsj (the full-resolution map journal `handscan export` reads). With `live` it
// publishes to the same shared memory as the daemon, so the UI can show any recording.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::replay {

struct ReplayOptions {
    std::string recording;
    std::string out_dir;
    bool fast = false;      // as fast as possible instead of recorded pace
    double speed = 1.0;     // pace multiplier without --fast
    bool use_laser = true;  // --modules imu | imu,vision: no laser
    // The visual-inertial odometry on /camera/track when recorded (--modules all | imu,vision).
    bool use_vision = false;
    bool vision_required = false;   // --modules imu,vision: the recording must have /camera/track
    bool skip_every_other = false;  // drop every other sample of every stream (2x speed)
    // Scan-matching poses correct the IMU predictor's pose, velocity, biases and gravity
    // direction (section 4.2) in the solved DOFs; the matcher's prior is then the integrated
    // pose. Off (--no-imu-feedback): the IMU runs open loop and its relative motion per sweep
    // seeds the matcher, which drifts (24.8 % on the 60 s office walk vs 0.66 % with feedback).
    bool imu_feedback = true;
    // The IMU's and the encoder's clocks tracked online (lio::ClockTracker). Off
    // (--no-clock-tracking): the configured latencies stand, as `handscan calibrate` needs them
    // to measure the calibration it was given.
    bool track_clocks = true;
    // The first seconds check the calibration (worker::CalibrationCheck) and, when it is wrong,
    // keep the scan out of the map. Off (--no-calibration-check): mapped whatever it is, as
    // `handscan calibrate` needs the trajectory of the calibration it was given.
    bool check_calibration = true;
    // Diagnostics: a TUM file (ground truth) to assemble sweeps with and match from, perturbed
    // (see ReferenceMotion): the scan matcher's own accuracy.
    std::string reference_motion;
    double reference_perturb_m = 0.0;
    double reference_perturb_deg = 0.0;
    bool colourise = true;        // colour points from /camera/colour when recorded
    std::string dump_sweeps_dir;  // each assembled sweep as PLY (x y z intensity t)
    std::string device_config;    // default: <config dir>/device.yaml
    std::string calibration;      // default: <config dir>/calibration.yaml
    double map_voxel_m = 0.02;    // map.ply density
    // map.ply is built in tiles of this edge; when their voxel tables exceed the budget, the tiles
    // farthest from the sensor go to a scratch file in map_spill_dir (default: out_dir) and are
    // merged back at the end (same bytes as all in memory; see TiledVoxelMap).
    double map_tile_m = 4.0;
    double map_memory_mib = 256.0;
    std::string map_spill_dir;
    bool write_journal = true;
    // A second MCAP with standard Foxglove channels (viz::VizSink: map, sweeps, poses, tf,
    // images, IMU, status, ground truth) for viewers; "" writes none.
    std::string viz_path;
    // Continue an earlier scan (section 9): its output directory (feature_map.hsf + journal or
    // trajectory.tum); the outputs are in its frame once the localizer locks, nothing before.
    std::string prior_map_dir;
    std::string initial_pose;  // "x,y,z,qx,qy,qz,qw" in the prior's frame; "": its start
    bool live = false;         // publish to shared memory
    bool hold = false;         // keep the final state published until interrupted
    std::string shm_name;      // default: the daemon's region
    std::function<void(double fraction)> progress;
    std::function<bool()> interrupted;  // polled while holding
};

struct ReplayReport {
    double recording_s = 0.0;
    double wall_s = 0.0;
    double realtime_factor = 0.0;
    std::uint64_t poses = 0;
    std::uint64_t sweeps = 0;
    std::uint64_t map_points = 0;
    std::string stats_json_path;
    std::uint64_t viz_bytes = 0;  // --viz file size
    bool prior_map = false;       // localized on a prior map (--prior-map)
    bool locked = false;          // ... and locked on it
};

Result<ReplayReport> runReplay(const ReplayOptions& options);

}  // namespace handscan::replay
