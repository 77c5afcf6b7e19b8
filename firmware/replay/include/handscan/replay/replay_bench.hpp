// `handscan replay REC --bench N`: the pipeline's speed on a recording, measured as the brief asks
// (per run, not by a timed test): the recording replayed N times --fast through the one worker,
// each run's wall-clock and process CPU time (the machine is shared: CPU time is what one core
// spends; wall time what the operator waits), their medians as real-time factors, and the
// modules' per-call costs of the last run (stats.json "modules"). Written to DIR/bench.json.
#pragma once

#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/replay/replay_engine.hpp"

namespace handscan::replay {

struct BenchRun {
    double wall_s = 0.0;
    double cpu_s = 0.0;  // user + system of the whole process (every thread)
};

struct ReplayBench {
    double recording_s = 0.0;
    std::vector<BenchRun> runs;
    double median_wall_s = 0.0, median_cpu_s = 0.0;
    double realtime_wall = 0.0;  // recording_s / median wall
    double realtime_cpu = 0.0;   // recording_s / median CPU: "x real time on one core"
    std::string bench_json_path;
    std::string modules_line;  // the main modules' mean cost per call, one line
};

// `options.fast` is forced; every run writes the usual outputs into options.out_dir.
Result<ReplayBench> benchReplay(ReplayOptions options, int runs);

}  // namespace handscan::replay
