#include "handscan/hil/daemon_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace handscan::hil {

std::string ProcessEnd::describe() const {
    if (exited) return "exited with code " + std::to_string(exit_code);
    return std::string("killed by signal ") + std::to_string(signal) + " (" + strsignal(signal) +
           ")";
}

DaemonProcess::~DaemonProcess() {
    if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        (void)wait(5 * kNsPerSec);
    }
}

Status DaemonProcess::start(const std::vector<std::string>& argv,
                            const std::filesystem::path& log) {
    if (pid_ > 0) return Status(StatusCode::kInvalidArgument, "the daemon is running already");
    std::vector<std::string> copy(argv);
    std::vector<char*> args;
    for (auto& s : copy) args.push_back(s.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = -1;
    const int rc = ::posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
        return Status(StatusCode::kIoError, "cannot start " + argv[0] + ": " + std::strerror(rc) +
                                                " (build it: cmake --build --target "
                                                "handscan-pipeline, or pass --daemon PATH)");
    }
    pid_ = pid;
    return Status::ok();
}

void DaemonProcess::signal(int sig) const {
    if (pid_ > 0) ::kill(pid_, sig);
}

std::optional<ProcessEnd> DaemonProcess::wait(TimeNs timeout) {
    if (pid_ <= 0) return std::nullopt;
    const TimeNs deadline = monotonicNow() + timeout;
    for (;;) {
        int status = 0;
        rusage usage{};
        const pid_t r = ::wait4(pid_, &status, WNOHANG, &usage);
        if (r == pid_) {
            pid_ = -1;
            ProcessEnd end;
            end.exited = WIFEXITED(status);
            end.exit_code = end.exited ? WEXITSTATUS(status) : 0;
            end.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
            end.user_cpu_s = static_cast<double>(usage.ru_utime.tv_sec) +
                             static_cast<double>(usage.ru_utime.tv_usec) * 1e-6;
            end.system_cpu_s = static_cast<double>(usage.ru_stime.tv_sec) +
                               static_cast<double>(usage.ru_stime.tv_usec) * 1e-6;
            end.peak_rss_mib = static_cast<double>(usage.ru_maxrss) / 1024.0;  // ru_maxrss: KiB
            return end;
        }
        if (r < 0 && errno != EINTR) {
            pid_ = -1;
            return std::nullopt;
        }
        if (monotonicNow() >= deadline) return std::nullopt;
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
}

std::string logTail(const std::filesystem::path& log, std::size_t max_bytes) {
    std::ifstream in(log);
    std::stringstream ss;
    ss << in.rdbuf();
    std::string s = ss.str();
    return s.size() > max_bytes ? "..." + s.substr(s.size() - max_bytes) : s;
}

}  // namespace handscan::hil
