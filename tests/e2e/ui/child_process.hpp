// Runs a program as a child process (stdout + stderr to a log file) while the test keeps doing
// its own work, e.g. publishing heartbeats as a pipeline would; and an X display for UI tests:
// $DISPLAY if set, else an Xvfb started once for this test process.
#pragma once

#include <sys/types.h>

#include <functional>
#include <string>
#include <vector>

namespace handscan::e2e {

struct ChildResult {
    int exit_code = -1;  // -1: killed after the timeout
    std::string output;  // stdout + stderr
};

class ChildProcess {
public:
    ChildProcess(const std::vector<std::string>& argv, const std::string& log_path);
    ~ChildProcess();  // kills the child if still running
    ChildProcess(const ChildProcess&) = delete;
    ChildProcess& operator=(const ChildProcess&) = delete;
    bool running();
    // Waits up to timeout_s, calling `tick` every 10 ms meanwhile.
    ChildResult wait(double timeout_s, const std::function<void()>& tick = {});
    void terminate();

private:
    pid_t pid_ = -1;
    int status_ = 0;
    bool reaped_ = false;
    std::string log_path_;
};

// Runs to completion (see ChildProcess::wait).
ChildResult runChild(const std::vector<std::string>& argv, double timeout_s,
                     const std::function<void()>& tick = {});

// Empty when a display is available (DISPLAY set, or an Xvfb started here); otherwise why not,
// for GTEST_SKIP.
std::string ensureDisplay();

}  // namespace handscan::e2e
