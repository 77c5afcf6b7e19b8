// `handscan-pipeline` as systemd runs it: its own process, $NOTIFY_SOCKET and $WATCHDOG_USEC set
// (the test is the service manager: a datagram socket collecting what sd_notify sends), the fake
// Hokuyo on loopback TCP, the fake Xsens on a pty, the emulated motor bus. READY=1 comes once the
// devices are open, STATUS= lines name them, WATCHDOG=1 keeps coming; a scan started through the
// shared memory is cut by SIGTERM, and the process exits 0 with the journal finished and intact.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "daemon_rig.hpp"
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
