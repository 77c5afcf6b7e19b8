// A scan's journal as a viz file (VizWriter): what `handscan export --format mcap` writes and
// what `handscan hil --viz` writes from the daemon's journal. The journal holds the poses and the
// map points the pipeline kept, not its sweeps: /pose, /tf (world->body, the camchain's frames)
// and /path from the trajectory, and /sweep + /map from the points in windows of `window_s` of
// the scan clock (the pipeline journals each sweep's points together; at the default spin a sweep
// window is about one sweep; /map every 2 s). There is no /status, /imu or encoder (body->laser):
// the journal does not keep them. With a recording (`hil`), its camera frames and ground truth join
// in time order (RecordedExtras), the journal's times shifted onto the recording's clock.
#pragma once

#include <cstdint>
#include <string>

#include "handscan/core/config.hpp"
#include "handscan/core/status.hpp"
#include "handscan/viz/viz_writer.hpp"

namespace handscan::viz {

struct JournalVizOptions {
    std::string journal;  // journal.hsj, or a directory holding it
    std::string out;      // the viz file
    double window_s = 0.5;
    // Optional: a recording whose /camera/* frames and ground truth are added, and the journal's
    // clock minus the recording's (hil's time_offset_ns), taken off the journal's times.
    std::string recording;
    TimeNs journal_minus_recording_ns = 0;
    VizConfig config = journalConfig();

    static VizConfig journalConfig() {
        VizConfig c;
        c.map_every_s = 2.0;  // /map every 4th window: the file stays under 2x the recording
        return c;
    }
};

struct JournalVizReport {
    std::uint64_t poses = 0, windows = 0, points = 0, recorded_messages = 0;
    std::uint64_t bytes = 0, messages = 0;
};

[[nodiscard]] Result<JournalVizReport> writeJournalViz(const JournalVizOptions& options,
                                                       const Calibration& calibration);

}  // namespace handscan::viz
