// core/realtime.hpp: a thread made SCHED_FIFO where the process may (root here, or the unit's
// LimitRTPRIO on the device), and where it may not (RLIMIT_RTPRIO 0 and no CAP_SYS_NICE, as in a
// developer's shell) one warning for the whole process and the thread left at normal priority.
#include "handscan/core/realtime.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <linux/capability.h>
#include <pthread.h>
#include <sched.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "handscan/core/config.hpp"
#include "handscan/core/log.hpp"

namespace handscan {
namespace {

struct ThreadPolicy {
    int policy = -1;
    int priority = -1;
    std::string name;
    Status status;
};

ThreadPolicy runOnThread(const std::string& name, int priority) {
    ThreadPolicy seen;
    std::thread t([&] {
        seen.status = enterRealtimeThread(name, priority);
        sched_param p{};
        ::pthread_getschedparam(::pthread_self(), &seen.policy, &p);
        seen.priority = p.sched_priority;
        char buf[16] = {};
        ::pthread_getname_np(::pthread_self(), buf, sizeof(buf));
        seen.name = buf;
    });
    t.join();
    return seen;
}

bool mayUseFifo() {
    rlimit rt{};
    ::getrlimit(RLIMIT_RTPRIO, &rt);
    return ::geteuid() == 0 || rt.rlim_cur >= 42;
}

// Drops `capability` from the effective and permitted sets of the calling process (a child).
void dropCapability(int capability) {
    __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
    ::syscall(SYS_capget, &header, data);
    const unsigned bit = 1u << (capability % 32);
    data[capability / 32].effective &= ~bit;
    data[capability / 32].permitted &= ~bit;
    data[capability / 32].inheritable &= ~bit;
    ::syscall(SYS_capset, &header, data);
}

std::size_t countOf(const std::string& text, const std::string& needle) {
    std::size_t n = 0;
    for (auto at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
    return n;
}

TEST(Realtime, ThreadBecomesFifoAtTheGivenPriorityWhenPermitted) {
    if (!mayUseFifo()) GTEST_SKIP() << "neither root nor RLIMIT_RTPRIO >= 42 here";
    const ThreadPolicy seen = runOnThread("hs-test-device", 42);
    ASSERT_TRUE(seen.status.isOk()) << seen.status.message();
    EXPECT_EQ(seen.policy, SCHED_FIFO);
    EXPECT_EQ(seen.priority, 42);
    EXPECT_EQ(seen.name, "hs-test-device");
}

TEST(Realtime, PriorityZeroOnlyNamesTheThread) {
    const ThreadPolicy seen = runOnThread("a-very-long-thread-name", 0);
    ASSERT_TRUE(seen.status.isOk());
    EXPECT_EQ(seen.policy, SCHED_OTHER);
    EXPECT_EQ(seen.name, "a-very-long-thr");  // the kernel's 15 characters
}

TEST(Realtime, PriorityOutsideFifoRangeIsRefusedWithTheKey) {
    const ThreadPolicy seen = runOnThread("hs-bad", 120);
    ASSERT_FALSE(seen.status.isOk());
    EXPECT_NE(seen.status.message().find("realtime: in device.yaml"), std::string::npos);
    EXPECT_EQ(seen.policy, SCHED_OTHER);
}

// A child without the permission (RLIMIT_RTPRIO 0, CAP_SYS_NICE and CAP_IPC_LOCK dropped, a
// small RLIMIT_MEMLOCK) asks three threads for SCHED_FIFO and locks memory twice: every thread
// stays SCHED_OTHER and runs on, and the log says each "not permitted" exactly once.
TEST(Realtime, NotPermittedWarnsOncePerProcessAndRunsOn) {
    char log_path[] = "/tmp/handscan-realtime-XXXXXX";
    const int log_fd = ::mkstemp(log_path);
    ASSERT_GE(log_fd, 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::dup2(log_fd, STDERR_FILENO);
        const rlimit zero{0, 0};
        const rlimit small{64 * 1024, 64 * 1024};
        ::setrlimit(RLIMIT_RTPRIO, &zero);
        ::setrlimit(RLIMIT_MEMLOCK, &small);
        dropCapability(CAP_SYS_NICE);
        dropCapability(CAP_IPC_LOCK);
        initLogging("realtime_test");
        int exit_code = 0;
        for (const char* name : {"hs-hokuyo", "hs-xsens", "hs-pipeline"}) {
            const ThreadPolicy seen = runOnThread(name, 50);
            if (seen.status.isOk() || seen.policy != SCHED_OTHER) exit_code = 10;
        }
        if (lockProcessMemory().isOk() || lockProcessMemory().isOk()) exit_code = 11;
        std::fflush(nullptr);
        ::_exit(exit_code);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    std::ifstream in(log_path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string log = ss.str();
    ::close(log_fd);
    ::unlink(log_path);
    ASSERT_TRUE(WIFEXITED(status)) << log;
    EXPECT_EQ(WEXITSTATUS(status), 0) << "a thread became real-time without permission\n" << log;
    EXPECT_EQ(countOf(log, "real-time scheduling not permitted"), 1u) << log;
    EXPECT_EQ(countOf(log, "memory locking not permitted"), 1u) << log;
    EXPECT_NE(log.find("LimitRTPRIO="), std::string::npos) << log;
}

TEST(Realtime, ShippedDeviceYamlPutsTheDevicesAboveThePipeline) {
    const RealtimeConfig rt =
        loadRealtimeConfig(std::string(HANDSCAN_SOURCE_DIR) + "/config/device.yaml");
    EXPECT_GT(rt.device_priority, rt.pipeline_priority);
    EXPECT_GT(rt.pipeline_priority, 0);
    EXPECT_TRUE(rt.lock_memory);
}

TEST(Realtime, ConfigErrorsNameFileLineAndKey) {
    char path[] = "/tmp/handscan-realtime-yaml-XXXXXX";
    const int fd = ::mkstemp(path);
    ASSERT_GE(fd, 0);
    const std::string yaml = "realtime:\n  device_priority: 120\n";
    ASSERT_EQ(::write(fd, yaml.data(), yaml.size()), static_cast<ssize_t>(yaml.size()));
    ::close(fd);
    try {
        (void)loadRealtimeConfig(path);
        ADD_FAILURE() << "priority 120 accepted";
    } catch (const ConfigError& e) {
        EXPECT_NE(std::string(e.what()).find(":2: realtime.device_priority"), std::string::npos)
            << e.what();
    }
    EXPECT_THROW((void)loadDeviceConfig(path), ConfigError);
    ::unlink(path);
}

}  // namespace
}  // namespace handscan
