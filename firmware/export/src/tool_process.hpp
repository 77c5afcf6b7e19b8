// Runs an external program (the export's optional helpers, e.g. weasyprint for report.pdf) as a
// child process without a shell: its standard output streams to a callback while it runs, the
// tail of its standard error is kept for the error message, and it is killed when it overruns
// its time. The program is looked up on PATH first, so "not installed" is told apart from
// "failed".
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"

namespace handscan::exporter {

// The program's full path found on PATH (or `name` itself when it holds a '/' and is
// executable); nullopt when there is none.
std::optional<std::string> findProgram(const std::string& name);

struct ToolRun {
    bool exited = false;  // false: killed by a signal (or by us at the timeout)
    int exit_code = 0;
    bool timed_out = false;
    std::string stderr_tail;  // the last few KiB the program wrote to its standard error
    double seconds = 0.0;
};

// `argv[0]` is a full path (findProgram). `on_stdout` gets the output as it arrives; when it
// returns a non-empty text (e.g. the medium failed), the program is killed and that text is the
// returned error. Fails only when the program cannot be started or read from.
Result<ToolRun> runTool(const std::vector<std::string>& argv,
                        const std::function<std::string(std::span<const std::uint8_t>)>& on_stdout,
                        double timeout_s);

}  // namespace handscan::exporter
