// `handscan-pipeline` as systemd runs it: its own process, $NOTIFY_SOCKET and $WATCHDOG_USEC set
// (the test is the service manager: a datagram socket collecting what sd_notify sends), the fake
// Hokuyo on loopback TCP, the fake Xsens on a pty, the emulated motor bus. READY=1 comes once the
// devices are open, STATUS= lines name them, WATCHDOG=1 keeps coming; a scan started through the
// shared memory is cut by SIGTERM, and the process exits 0 with the journal finished and intact.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

#include "daemon_rig.hpp"
#include "handscan/core/realtime.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/shm/text_field.hpp"

extern char** environ;

namespace handscan::pipeline_daemon::test {
namespace {

const std::string kDaemon =
    std::string(HANDSCAN_BINARY_DIR) + "/firmware/pipeline_daemon/handscan-pipeline";

// The service manager's end of the notify protocol.
class NotifySocket {
public:
    explicit NotifySocket(const fs::path& path) : path_(path) {
        fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
        sockaddr_un a{};
        a.sun_family = AF_UNIX;
        std::snprintf(a.sun_path, sizeof(a.sun_path), "%s", path.c_str());
        if (::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) != 0)
            throw std::runtime_error("bind " + path.string());
    }
    ~NotifySocket() { ::close(fd_); }
    // Every message received so far, in order.
    const std::vector<std::string>& messages() {
        char buf[4096];
        for (ssize_t n; (n = ::recv(fd_, buf, sizeof(buf), 0)) > 0;)
            received_.emplace_back(buf, static_cast<std::size_t>(n));
        return received_;
    }
    bool saw(const std::string& needle) {
        for (const std::string& m : messages()) {
            if (m.find(needle) != std::string::npos) return true;
        }
        return false;
    }

private:
    fs::path path_;
    int fd_ = -1;
    std::vector<std::string> received_;
};

pid_t spawnDaemon(const std::vector<std::string>& argv, const std::vector<std::string>& extra_env,
                  const fs::path& log) {
    std::vector<std::string> env_strings(extra_env);
    for (char** e = environ; *e; ++e) env_strings.emplace_back(*e);
    std::vector<char*> env, args;
    for (auto& s : env_strings) env.push_back(s.data());
    env.push_back(nullptr);
    std::vector<std::string> argv_copy(argv);
    for (auto& s : argv_copy) args.push_back(s.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    pid_t pid = -1;
    if (posix_spawn(&pid, args[0], &fa, nullptr, args.data(), env.data()) != 0) pid = -1;
    posix_spawn_file_actions_destroy(&fa);
    return pid;
}

std::string readAll(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
}

bool waitUntil(const std::function<bool()>& pred, double timeout_s) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
        if (pred()) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    return false;
}

TEST(PipelineDaemonProcess, NotifiesSystemdAndStopsCleanlyOnSigterm) {
    if (!fs::exists(kDaemon)) GTEST_SKIP() << kDaemon << " not built";
    DaemonRig rig("process");
    NotifySocket notify(rig.dir() / "notify.sock");
    const fs::path log = rig.dir() / "daemon.log";
    const pid_t pid = spawnDaemon(
        {kDaemon, "--config", rig.deviceYaml(), "--calibration", DaemonRig::calibrationYaml(),
         "--shm", rig.shmName(), "--map-capacity", "262144"},
        {"NOTIFY_SOCKET=" + (rig.dir() / "notify.sock").string(), "WATCHDOG_USEC=400000"}, log);
    ASSERT_GT(pid, 0);
    int status = 0;
    bool reaped = false;
    const auto cleanup = [&] {
        if (!reaped) {
            ::kill(pid, SIGKILL);
            ::waitpid(pid, &status, 0);
        }
    };

    EXPECT_TRUE(waitUntil([&] { return notify.saw("READY=1"); }, 10.0)) << readAll(log);
    EXPECT_TRUE(waitUntil(
        [&] {
            return notify.saw("hokuyo ok") && notify.saw("xsens ok") && notify.saw("encoder ok");
        },
        10.0))
        << readAll(log);
    const auto count = [&](const std::string& what) {
        return std::count_if(
            notify.messages().begin(), notify.messages().end(),
            [&](const std::string& m) { return m.find(what) != std::string::npos; });
    };
    EXPECT_TRUE(waitUntil([&] { return count("WATCHDOG=1") >= 3; },
                          3.0));  // every 200 ms (half of WATCHDOG_USEC)

    auto ack = rig.command(shm::CommandType::kStartScan);
    EXPECT_EQ(ack.state, static_cast<std::uint32_t>(shm::CommandState::kDone))
        << shm::getText(ack.message);
    EXPECT_TRUE(rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 0; }, 15.0))
        << readAll(log);
    EXPECT_TRUE(waitUntil([&] { return notify.saw("STATUS=scanning"); }, 3.0));

    // SIGTERM mid-scan: a clean exit, the journal finished and intact.
    ASSERT_EQ(::kill(pid, SIGTERM), 0);
    reaped = waitUntil([&] { return ::waitpid(pid, &status, WNOHANG) == pid; }, 10.0);
    cleanup();
    ASSERT_TRUE(reaped) << "no exit within 10 s of SIGTERM\n" << readAll(log);
    ASSERT_TRUE(WIFEXITED(status)) << readAll(log);
    EXPECT_EQ(WEXITSTATUS(status), 0) << readAll(log);
    EXPECT_TRUE(notify.saw("STOPPING=1"));
    ASSERT_EQ(rig.scanDirs().size(), 1u);
    auto j = journal::JournalReader::open((rig.scanDirs()[0] / "journal.hsj").string());
    ASSERT_TRUE(j.isOk()) << j.status().message();
    EXPECT_TRUE(j->summary().finished);
    EXPECT_TRUE(j->summary().damage.empty()) << j->summary().damage;
    EXPECT_GT(j->summary().points, 0u);
    EXPECT_GT(j->summary().trajectory.size(), 100u);
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test

namespace handscan::pipeline_daemon::test {
namespace {

// A power cut or crash mid-scan (SIGKILL: no clean-up at all): the journal stays readable, every
// chunk intact, and it lacks at most the last second of the scan (flushes every 0.5 s); the
// restarted daemon offers the cut scan for export.
TEST(PipelineDaemonProcess, KilledMidScanLeavesARecoverableJournal) {
    if (!fs::exists(kDaemon)) GTEST_SKIP() << kDaemon << " not built";
    DaemonRig rig("kill9");
    const fs::path log = rig.dir() / "daemon.log";
    const pid_t pid = spawnDaemon(
        {kDaemon, "--config", rig.deviceYaml(), "--calibration", DaemonRig::calibrationYaml(),
         "--shm", rig.shmName(), "--map-capacity", "262144"},
        {}, log);
    ASSERT_GT(pid, 0);
    int status = 0;
    const auto kill9 = [&] {
        ::kill(pid, SIGKILL);
        ::waitpid(pid, &status, 0);
    };
    ASSERT_TRUE(rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return sensorConnected(s, "encoder") && sensorConnected(s, "hokuyo");
        },
        10.0))
        << readAll(log);
    auto ack = rig.command(shm::CommandType::kStartScan);
    EXPECT_EQ(ack.state, static_cast<std::uint32_t>(shm::CommandState::kDone))
        << shm::getText(ack.message);
    auto before =
        rig.waitStatus([](const shm::StatusBlock& s) { return s.point_count > 30000; }, 15.0);
    if (!before) kill9();
    ASSERT_TRUE(before) << readAll(log);
    // The points counted 1 s before the kill are all on disk afterwards (flushed every 0.5 s).
    std::this_thread::sleep_for(std::chrono::milliseconds(1000));
    kill9();
    ASSERT_TRUE(WIFSIGNALED(status));
    ASSERT_EQ(rig.scanDirs().size(), 1u);
    auto j = journal::JournalReader::open((rig.scanDirs()[0] / "journal.hsj").string());
    ASSERT_TRUE(j.isOk()) << j.status().message();
    EXPECT_FALSE(j->summary().finished);
    EXPECT_GE(j->summary().points, before->point_count);
    EXPECT_GT(j->summary().chunks, 1u);
    // A torn last chunk, if the kill hit a write, is reported and cut; everything before it reads.
    std::uint64_t intact_points = j->summary().points;
    if (!j->summary().damage.empty()) {
        auto recovered = journal::recoverJournal((rig.scanDirs()[0] / "journal.hsj").string());
        ASSERT_TRUE(recovered.isOk()) << recovered.status().message();
        EXPECT_GE(recovered->points, before->point_count);
        intact_points = recovered->points;
    }

    // Restarted (as systemd's Restart=on-failure does), the daemon takes the cut scan back as a
    // stopped scan that the UI can export; SIGTERM then closes it as finished.
    const pid_t again = spawnDaemon(
        {kDaemon, "--config", rig.deviceYaml(), "--calibration", DaemonRig::calibrationYaml(),
         "--shm", rig.shmName(), "--map-capacity", "262144"},
        {}, rig.dir() / "daemon2.log");
    ASSERT_GT(again, 0);
    auto back = rig.waitStatus(
        [](const shm::StatusBlock& s) {
            return s.scan_state == static_cast<std::uint8_t>(shm::ScanState::kStopped) &&
                   s.point_count > 0;
        },
        10.0);
    std::vector<shm::CommandState> seen;
    const fs::path target = rig.dir() / "export";
    fs::create_directories(target);
    auto exported = rig.command(shm::CommandType::kExport, target.string(), &seen);
    ::kill(again, SIGTERM);
    int status2 = 0;
    const bool exited =
        waitUntil([&] { return ::waitpid(again, &status2, WNOHANG) == again; }, 10.0);
    if (!exited) {
        ::kill(again, SIGKILL);
        ::waitpid(again, &status2, 0);
    }
    ASSERT_TRUE(back) << "the cut scan was not recovered\n" << readAll(rig.dir() / "daemon2.log");
    EXPECT_NE(std::string(shm::getText(back->message)).find("recovered"), std::string::npos)
        << shm::getText(back->message);
    EXPECT_EQ(back->point_count, intact_points);
    EXPECT_EQ(exported.state, static_cast<std::uint32_t>(shm::CommandState::kDone))
        << shm::getText(exported.message);
    ASSERT_TRUE(exited);
    EXPECT_TRUE(WIFEXITED(status2) && WEXITSTATUS(status2) == 0)
        << readAll(rig.dir() / "daemon2.log");
    auto closed = journal::JournalReader::open((rig.scanDirs()[0] / "journal.hsj").string());
    ASSERT_TRUE(closed.isOk());
    EXPECT_TRUE(closed->summary().finished);
    EXPECT_EQ(closed->summary().points, back->point_count);
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test

namespace handscan::pipeline_daemon::test {
namespace {

struct TaskPolicy {
    std::string name;
    int policy = -1;
    int priority = -1;
};

// Every thread of process `pid`: its name (/proc/PID/task/TID/comm) and scheduling.
std::vector<TaskPolicy> taskPolicies(pid_t pid) {
    std::vector<TaskPolicy> tasks;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator("/proc/" + std::to_string(pid) + "/task", ec)) {
        const pid_t tid = std::stoi(e.path().filename().string());
        TaskPolicy t;
        std::ifstream(e.path() / "comm") >> t.name;
        t.policy = ::sched_getscheduler(tid);
        sched_param p{};
        if (::sched_getparam(tid, &p) == 0) t.priority = p.sched_priority;
        tasks.push_back(t);
    }
    return tasks;
}

const TaskPolicy* findTask(const std::vector<TaskPolicy>& tasks, const std::string& name) {
    for (const TaskPolicy& t : tasks) {
        if (t.name == name) return &t;
    }
    return nullptr;
}

std::uint64_t lockedKiB(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("VmLck:", 0) == 0) return std::stoull(line.substr(6));
    }
    return 0;
}

// The daemon as the unit runs it with LimitRTPRIO (here: root): each device thread and the
// driver's Xsens reader SCHED_FIFO at realtime.device_priority, the pipeline thread at
// realtime.pipeline_priority, the main thread (commands, watchdog) and export at normal
// priority, and its memory locked.
TEST(PipelineDaemonProcess, RealtimeThreadsRunFifoAtTheConfiguredPriorities) {
    if (!fs::exists(kDaemon)) GTEST_SKIP() << kDaemon << " not built";
    if (::geteuid() != 0) GTEST_SKIP() << "SCHED_FIFO needs root or LimitRTPRIO here";
    DaemonRig rig("realtime");
    const fs::path log = rig.dir() / "daemon.log";
    const pid_t pid = spawnDaemon(
        {kDaemon, "--config", rig.deviceYaml(), "--calibration", DaemonRig::calibrationYaml(),
         "--shm", rig.shmName(), "--map-capacity", "262144"},
        {}, log);
    ASSERT_GT(pid, 0);
    const RealtimeConfig rt;  // the rig's device.yaml has no realtime: section
    std::vector<TaskPolicy> tasks;
    const bool all_up = waitUntil(
        [&] {
            tasks = taskPolicies(pid);
            for (const char* n :
                 {"hs-hokuyo", "hs-xsens", "hs-xsens-rx", "hs-encoder", "hs-pipeline"}) {
                if (!findTask(tasks, n)) return false;
            }
            return true;
        },
        10.0);
    const std::uint64_t locked = lockedKiB(pid);
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(all_up) << readAll(log);
    for (const TaskPolicy& t : tasks) {
        std::printf("  %-16s %-11s priority %d\n", t.name.c_str(),
                    t.policy == SCHED_FIFO ? "SCHED_FIFO" : "SCHED_OTHER", t.priority);
        if (t.name == "hs-pipeline") {
            EXPECT_EQ(t.policy, SCHED_FIFO) << t.name;
            EXPECT_EQ(t.priority, rt.pipeline_priority) << t.name;
        } else if (t.name.rfind("hs-", 0) == 0) {
            EXPECT_EQ(t.policy, SCHED_FIFO) << t.name;
            EXPECT_EQ(t.priority, rt.device_priority) << t.name;
        } else {
            EXPECT_EQ(t.policy, SCHED_OTHER) << t.name;  // main loop, export, spdlog, fakes
        }
    }
    EXPECT_GT(locked, 10000u) << "VmLck: mlockall did not lock the daemon's memory";
    EXPECT_EQ(readAll(log).find("not permitted"), std::string::npos) << readAll(log);
}

// Without the permission (the capabilities dropped, RLIMIT_RTPRIO 0: a developer's shell) the
// daemon says so once per kind, runs every thread at normal priority, and works: READY, devices.
TEST(PipelineDaemonProcess, RealtimeNotPermittedWarnsOnceAndRunsOn) {
    if (!fs::exists(kDaemon)) GTEST_SKIP() << kDaemon << " not built";
    if (!fs::exists("/usr/bin/setpriv") || !fs::exists("/usr/bin/prlimit"))
        GTEST_SKIP() << "util-linux setpriv/prlimit missing";
    DaemonRig rig("realtime-denied");
    NotifySocket notify(rig.dir() / "notify.sock");
    const fs::path log = rig.dir() / "daemon.log";
    const pid_t pid = spawnDaemon(
        {"/usr/bin/setpriv", "--bounding-set=-sys_nice,-ipc_lock", "--inh-caps=-sys_nice,-ipc_lock",
         "--", "/usr/bin/prlimit", "--rtprio=0", "--memlock=65536", "--", kDaemon, "--config",
         rig.deviceYaml(), "--calibration", DaemonRig::calibrationYaml(), "--shm", rig.shmName(),
         "--map-capacity", "262144"},
        {"NOTIFY_SOCKET=" + (rig.dir() / "notify.sock").string()}, log);
    ASSERT_GT(pid, 0);
    const bool ready = waitUntil(
        [&] {
            return notify.saw("hokuyo ok") && notify.saw("xsens ok") && notify.saw("encoder ok");
        },
        10.0);
    std::vector<TaskPolicy> tasks = taskPolicies(pid);
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const std::string text = readAll(log);
    EXPECT_TRUE(ready) << text;
    ASSERT_TRUE(findTask(tasks, "hs-pipeline")) << text;
    for (const TaskPolicy& t : tasks) EXPECT_EQ(t.policy, SCHED_OTHER) << t.name;
    const auto count = [&](const std::string& needle) {
        std::size_t n = 0;
        for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
            ++n;
        return n;
    };
    EXPECT_EQ(count("real-time scheduling not permitted"), 1u) << text;
    EXPECT_EQ(count("memory locking not permitted"), 1u) << text;
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << text;
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test

namespace handscan::pipeline_daemon::test {
namespace {

// The package's config relocated to the rig's fake devices: /etc/handscan/device.yaml as
// installed, with each device section the rig sets (addresses, paths, storage) taken from the
// rig's device.yaml and everything else (realtime:, calibration files) as shipped.
void relocateInstalledConfig(const fs::path& installed, const std::string& rig_yaml) {
    YAML::Node config = YAML::LoadFile(installed.string());
    const YAML::Node rig = YAML::LoadFile(rig_yaml);
    for (const auto& section : rig) {
        for (const auto& key : section.second)
            config[section.first.as<std::string>()][key.first.as<std::string>()] = key.second;
    }
    YAML::Emitter out;
    out << config;
    std::ofstream(installed) << out.c_str() << "\n";
}

// `handscan-pipeline --config /etc/handscan/device.yaml` from the Debian package unpacked into a
// throwaway root (tests/e2e/package: HANDSCAN_PACKAGE_ROOT), against the fake devices: it reads
// the installed config and calibration, says READY=1, opens every device, stops cleanly.
TEST(PipelineDaemonInstalled, StartsFromThePackageRootAgainstFakeDevices) {
    const char* root_env = std::getenv("HANDSCAN_PACKAGE_ROOT");
    if (!root_env) GTEST_SKIP() << "HANDSCAN_PACKAGE_ROOT unset (ctest -R e2e.package sets it)";
    const fs::path root(root_env);
    const fs::path daemon = root / "usr/bin/handscan-pipeline";
    const fs::path etc = root / "etc/handscan";
    ASSERT_TRUE(fs::exists(daemon)) << daemon << ": run ctest -R e2e.package.unpack first";
    DaemonRig rig("installed");
    relocateInstalledConfig(etc / "device.yaml", rig.deviceYaml());
    NotifySocket notify(rig.dir() / "notify.sock");
    const fs::path log = rig.dir() / "daemon.log";
    const pid_t pid = spawnDaemon(
        {daemon.string(), "--config", (etc / "device.yaml").string(), "--calibration",
         (etc / "calibration.yaml").string(), "--shm", rig.shmName(), "--map-capacity", "262144"},
        {"NOTIFY_SOCKET=" + (rig.dir() / "notify.sock").string()}, log);
    ASSERT_GT(pid, 0);
    const bool ready = waitUntil([&] { return notify.saw("READY=1"); }, 10.0);
    const bool devices = waitUntil(
        [&] {
            return notify.saw("hokuyo ok") && notify.saw("xsens ok") && notify.saw("encoder ok");
        },
        10.0);
    ::kill(pid, SIGTERM);
    int status = 0;
    ::waitpid(pid, &status, 0);
    EXPECT_TRUE(ready) << readAll(log);
    EXPECT_TRUE(devices) << readAll(log);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << readAll(log);
    std::printf("%s", readAll(log).c_str());
}

}  // namespace
}  // namespace handscan::pipeline_daemon::test
