#include "tool_process.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace handscan::exporter {
namespace {

constexpr std::size_t kStderrTail = 4096;

bool executable(const std::string& path) { return ::access(path.c_str(), X_OK) == 0; }

// Closes its descriptors on every way out.
struct Pipe {
    int fd[2] = {-1, -1};
    ~Pipe() {
        for (int f : fd)
            if (f >= 0) ::close(f);
    }
    void closeEnd(int i) {
        if (fd[i] >= 0) ::close(fd[i]);
        fd[i] = -1;
    }
};

ToolRun reap(pid_t pid, ToolRun run) {
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    run.exited = WIFEXITED(status);
    run.exit_code = run.exited ? WEXITSTATUS(status) : 0;
    return run;
}

}  // namespace

std::optional<std::string> findProgram(const std::string& name) {
    if (name.empty()) return std::nullopt;
    if (name.find('/') != std::string::npos)
        return executable(name) ? std::optional<std::string>(name) : std::nullopt;
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path ? path : "/usr/bin:/bin");
    for (std::string dir; std::getline(dirs, dir, ':');) {
        const std::string candidate = (dir.empty() ? std::string(".") : dir) + "/" + name;
        if (executable(candidate)) return candidate;
    }
    return std::nullopt;
}

Result<ToolRun> runTool(const std::vector<std::string>& argv,
                        const std::function<std::string(std::span<const std::uint8_t>)>& on_stdout,
                        double timeout_s) {
    const auto started = std::chrono::steady_clock::now();
    Pipe out, err;
    if (::pipe2(out.fd, O_CLOEXEC) != 0 || ::pipe2(err.fd, O_CLOEXEC) != 0)
        return Status(StatusCode::kIoError,
                      "cannot make a pipe for " + argv[0] + ": " + std::strerror(errno));
    std::vector<std::string> copy(argv);
    std::vector<char*> args;
    for (auto& s : copy) args.push_back(s.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_adddup2(&fa, out.fd[1], 1);
    posix_spawn_file_actions_adddup2(&fa, err.fd[1], 2);
    pid_t pid = -1;
    const int rc = ::posix_spawn(&pid, args[0], &fa, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0)
        return Status(StatusCode::kIoError, "cannot start " + argv[0] + ": " + std::strerror(rc));
    out.closeEnd(1);
    err.closeEnd(1);

    ToolRun run;
    std::string failure;  // the consumer's error: the program is killed
    std::array<std::uint8_t, 1 << 16> buf{};
    std::array<pollfd, 2> fds{{{out.fd[0], POLLIN, 0}, {err.fd[0], POLLIN, 0}}};
    int open_fds = 2;
    while (open_fds > 0 && failure.empty()) {
        const double left =
            timeout_s -
            std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
        if (left <= 0) {
            run.timed_out = true;
            break;
        }
        const int n = ::poll(fds.data(), fds.size(), static_cast<int>(left * 1000) + 1);
        if (n < 0 && errno != EINTR) {
            failure = std::string("poll: ") + std::strerror(errno);
            break;
        }
        for (std::size_t i = 0; i < fds.size() && failure.empty(); ++i) {
            if (fds[i].fd < 0 || fds[i].revents == 0) continue;
            const ssize_t got = ::read(fds[i].fd, buf.data(), buf.size());
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) {  // end of that stream
                fds[i].fd = -1;
                --open_fds;
                continue;
            }
            const std::span<const std::uint8_t> bytes(buf.data(), static_cast<std::size_t>(got));
            if (i == 0) {
                failure = on_stdout(bytes);
            } else {
                run.stderr_tail.append(reinterpret_cast<const char*>(bytes.data()), bytes.size());
                if (run.stderr_tail.size() > 2 * kStderrTail)
                    run.stderr_tail.erase(0, run.stderr_tail.size() - kStderrTail);
            }
        }
    }
    if (open_fds > 0) ::kill(pid, SIGKILL);  // overran its time, or the output has nowhere to go
    run = reap(pid, std::move(run));
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (run.stderr_tail.size() > kStderrTail)
        run.stderr_tail.erase(0, run.stderr_tail.size() - kStderrTail);
    if (!failure.empty()) return Status(StatusCode::kIoError, failure);
    return run;
}

}  // namespace handscan::exporter
