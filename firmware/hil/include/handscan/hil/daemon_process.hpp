// DaemonProcess: a child process (the real handscan-pipeline) with its output in a log file, and
// what it cost: CPU time of all its threads and peak resident set size, from wait4()'s rusage.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/core/time.hpp"

namespace handscan::hil {

struct ProcessEnd {
    bool exited = false;  // else killed by `signal`
    int exit_code = 0;
    int signal = 0;
    double user_cpu_s = 0.0;  // all threads, from the rusage of the reaped child
    double system_cpu_s = 0.0;
    double peak_rss_mib = 0.0;
    std::string describe() const;
};

class DaemonProcess {
public:
    DaemonProcess() = default;
    ~DaemonProcess();  // kills (SIGKILL) and reaps a child still running
    DaemonProcess(const DaemonProcess&) = delete;
    DaemonProcess& operator=(const DaemonProcess&) = delete;

    // Spawns argv[0] (a path) with stdout and stderr into `log`.
    [[nodiscard]] Status start(const std::vector<std::string>& argv,
                               const std::filesystem::path& log);
    bool running() const { return pid_ > 0; }
    pid_t pid() const { return pid_; }
    // Sends `sig`; then wait() reaps.
    void signal(int sig) const;
    // Reaps the child if it ends within `timeout`.
    std::optional<ProcessEnd> wait(TimeNs timeout);

private:
    pid_t pid_ = -1;
};

// The last `max_bytes` of a log file, for error messages.
std::string logTail(const std::filesystem::path& log, std::size_t max_bytes = 2000);

}  // namespace handscan::hil
