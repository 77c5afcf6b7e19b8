// `handscan hil REC.mcap --out DIR`: the recording's raw device streams played by fake devices
// over their real transports (RecordingFakes) into the real handscan-pipeline binary, started as
// a child process with a generated device.yaml and driven through the shared-memory commands as
// the UI drives it: start the scan before the recording plays, stop it at the end, export it.
//
// Time: the fakes play the recording on the host clock shifted by `time_offset_ns` (host
// CLOCK_MONOTONIC - recording clock), so the daemon stamps every sample about where the
// recording had it plus that offset. DIR/trajectory.tum is the daemon's journaled trajectory
// moved back by the offset, i.e. on the recording's clock like `handscan replay`'s and the
// simulator's ground truth: `handscan eval --gt REC.gt.tum --est DIR/trajectory.tum` works as
// for replay. DIR/trajectory.host.tum keeps the daemon's own times; stats.json has the offset.
//
// DIR holds: device.yaml, daemon.log, journal/scan-*/journal.hsj (the daemon's journal),
// export/<scan>/ (the daemon's export: PLY, LAS, trajectory), map.ply (the exported cloud),
// trajectory.tum, trajectory.host.tum, stats.json (daemon CPU time of all threads and peak RSS,
// samples dropped, what the fakes played).
// With `continue_scan`, DIR/journal/earlier-scan is the scan continued; trajectory.tum is then in
// its frame.
#pragma once

#include <optional>
#include <string>

#include "handscan/core/status.hpp"
#include "handscan/hil/recording_fakes.hpp"

namespace handscan::hil {

struct HilOptions {
    std::string recording;
    std::string out_dir;
    std::string daemon;             // handscan-pipeline (default: found next to this program)
    std::string device_config;      // the recording's device.yaml (default: the config dir's)
    std::string calibration;        // default: the config dir's calibration.yaml
    std::string field_calibration;  // the daemon's --field-calibration ("": none)
    FakesOptions fakes;
    // kill -9 the daemon this many seconds into the recording, start it again: the journal must
    // be recovered and its export (DIR/export-recovered) must contain the scan up to the kill;
    // then a new scan records the rest of the recording (DIR/export, trajectory.tum).
    std::optional<double> kill_at_s;
    // Seconds the daemon gets to open its devices and start the scan before the recording plays.
    double startup_s = 4.0;
    // Non-empty: the daemon's journal (poses, map points) with the recording's camera frames and
    // ground truth as a viz file (viz::writeJournalViz), on the recording's clock.
    std::string viz_path;
    // Non-empty: an earlier scan's directory (journal.hsj and feature_map.hsf, as replay or the
    // daemon leaves them), copied into the daemon's journal directory as `earlier-scan`; the
    // daemon continues it ("continue scan", section 9) instead of scanning on its own, from
    // `initial_pose` (x,y,z,qx,qy,qz,qw in its frame; empty: where it started).
    std::string continue_scan;
    std::string initial_pose;
    // Non-zero: after the export, the UI's "calibrate" (CommandType::kCalibrate) with at most
    // this many rounds; the daemon replaces `calibration`'s file, keeping it as .prev.
    int calibrate_rounds = 0;
};

struct HilReport {
    std::string journal;  // the scan's journal
    std::size_t poses = 0;
    std::uint64_t points = 0;           // in the journal
    std::uint64_t coloured_points = 0;  // in the journal, seen by the colour camera
    std::uint64_t export_points = 0;    // in the export
    std::uint64_t samples_dropped = 0;
    double daemon_user_cpu_s = 0.0, daemon_system_cpu_s = 0.0, daemon_peak_rss_mib = 0.0;
    double recording_s = 0.0;
    bool recovered_after_kill = false;
    std::uint64_t recovered_points = 0;         // after --kill-at: the recovered scan's journal
    std::uint64_t recovered_export_points = 0;  // and its export
    std::uint64_t viz_bytes = 0;                // --viz: the file's size
    std::string calibration;                    // calibrate_rounds: the daemon's answer
    std::string summary;                        // one line per figure, for the console
    // --continue: the status block said locked this long after the recording began (< 0: never).
    double locked_after_s = -1.0;
};

[[nodiscard]] Result<HilReport> runHil(const HilOptions& options);

}  // namespace handscan::hil
