// What `handscan hil` leaves in DIR besides the daemon's own files: trajectory.tum (on the
// recording's clock), trajectory.host.tum, map.ply (the exported cloud) and stats.json.
#pragma once

#include <filesystem>

#include "handscan/hil/hil_run.hpp"

namespace handscan::hil {

struct OutputsInputs {
    const RecordedStreams& rec;
    TimeNs offset;  // host - recording clock
    RecordingFakes::Counts played;
    const HilOptions& options;
    std::filesystem::path log;
    std::filesystem::path out;
};

// Fills the report's journal, pose, point and drop figures and writes the files.
[[nodiscard]] Status writeHilOutputs(const OutputsInputs& in, HilReport& report);

// Samples the daemon dropped, from its log: at full queues ("... (N in all)") and unprocessed
// at shutdown.
std::uint64_t droppedSamplesInLog(const std::filesystem::path& log);

}  // namespace handscan::hil
