#include "child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

extern char** environ;

namespace handscan::e2e {
namespace {

pid_t spawn(const std::vector<std::string>& argv, const std::string& log_path) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = -1;
    if (posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), environ) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

std::string readFile(const std::string& path) {
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

// An Xvfb for this test process, stopped when the process exits.
struct Xvfb {
    pid_t pid = -1;
    ~Xvfb() {
        if (pid > 0) {
            ::kill(pid, SIGTERM);
            ::waitpid(pid, nullptr, 0);
        }
    }
};

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& log_path)
    : pid_(spawn(argv, log_path)), log_path_(log_path) {}

ChildProcess::~ChildProcess() { terminate(); }

bool ChildProcess::running() {
    if (pid_ <= 0 || reaped_) return false;
    if (::waitpid(pid_, &status_, WNOHANG) == pid_) reaped_ = true;
    return !reaped_;
}

void ChildProcess::terminate() {
    if (pid_ > 0 && !reaped_) {
        ::kill(pid_, SIGTERM);
        for (int i = 0; i < 200 && running(); ++i)
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        if (running()) ::kill(pid_, SIGKILL);
        if (!reaped_) ::waitpid(pid_, &status_, 0);
        reaped_ = true;
    }
}

ChildResult ChildProcess::wait(double timeout_s, const std::function<void()>& tick) {
    ChildResult r;
    if (pid_ <= 0) {
        r.output = "cannot start the program";
        return r;
    }
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (running() && std::chrono::steady_clock::now() < end) {
        if (tick) tick();
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!reaped_) {
        terminate();
        r.exit_code = -1;
    } else {
        r.exit_code = WIFEXITED(status_) ? WEXITSTATUS(status_) : 128 + WTERMSIG(status_);
    }
    r.output = readFile(log_path_);
    return r;
}

ChildResult runChild(const std::vector<std::string>& argv, double timeout_s,
                     const std::function<void()>& tick) {
    const std::string log =
        (std::filesystem::temp_directory_path() /
         ("handscan-e2e-" + std::to_string(::getpid()) + "-" +
          std::to_string(std::chrono::steady_clock::now().time_since_epoch().count()) + ".log"))
            .string();
    ChildProcess p(argv, log);
    ChildResult r = p.wait(timeout_s, tick);
    std::filesystem::remove(log);
    return r;
}

std::string ensureDisplay() {
    static Xvfb xvfb;
    static std::string reason = [] {
        const char* d = std::getenv("DISPLAY");
        if (d && *d) return std::string();
        bool have_xvfb = false;
        for (const char* dir : {"/usr/bin", "/usr/local/bin", "/bin"}) {
            have_xvfb = have_xvfb || std::filesystem::exists(std::string(dir) + "/Xvfb");
        }
        if (!have_xvfb)
            return std::string("Xvfb not installed (apt install xvfb) and DISPLAY not set");
        // A display number nobody uses: no lock file and no socket.
        for (int n = 90 + ::getpid() % 300, tries = 0; tries < 50; ++n, ++tries) {
            const std::string lock = "/tmp/.X" + std::to_string(n) + "-lock";
            const std::string sock = "/tmp/.X11-unix/X" + std::to_string(n);
            if (std::filesystem::exists(lock) || std::filesystem::exists(sock)) continue;
            const std::string display = ":" + std::to_string(n);
            xvfb.pid = spawn({"Xvfb", display, "-screen", "0", "1600x1200x24", "-nolisten", "tcp"},
                             "/dev/null");
            if (xvfb.pid <= 0) return std::string("cannot start Xvfb");
            for (int i = 0; i < 500 && !std::filesystem::exists(sock); ++i) {
                std::this_thread::sleep_for(std::chrono::milliseconds(10));
            }
            if (!std::filesystem::exists(sock)) {
                ::kill(xvfb.pid, SIGTERM);
                ::waitpid(xvfb.pid, nullptr, 0);
                xvfb.pid = -1;
                continue;  // lost a race for that number: try the next
            }
            ::setenv("DISPLAY", display.c_str(), 1);
            return std::string();
        }
        return std::string("no free X display number for Xvfb");
    }();
    return reason;
}

}  // namespace handscan::e2e
