#include "handscan/core/realtime.hpp"

#include <linux/capability.h>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include "handscan/core/log.hpp"

namespace handscan {
namespace {

std::atomic<bool> g_warned_scheduling{false};
std::atomic<bool> g_warned_memory{false};

void warnOnce(std::atomic<bool>& warned, const std::string& message) {
    if (!warned.exchange(true)) log().warn("{}", message);
}

// Whether `capability` is in the calling thread's effective set (capget: no libcap needed).
bool hasEffectiveCapability(int capability) {
    __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
    __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
    if (::syscall(SYS_capget, &header, data) != 0) return false;
    return (data[capability / 32].effective & (1u << (capability % 32))) != 0;
}

}  // namespace

Status enterRealtimeThread(const std::string& name, int fifo_priority) {
    ::pthread_setname_np(::pthread_self(), name.substr(0, 15).c_str());
    if (fifo_priority == 0) return Status::ok();
    const int lo = ::sched_get_priority_min(SCHED_FIFO);
    const int hi = ::sched_get_priority_max(SCHED_FIFO);
    if (fifo_priority < lo || fifo_priority > hi) {
        return Status(StatusCode::kInvalidArgument,
                      name + ": SCHED_FIFO priority " + std::to_string(fifo_priority) +
                          " is outside " + std::to_string(lo) + ".." + std::to_string(hi) +
                          " (realtime: in device.yaml)");
    }
    sched_param param{};
    param.sched_priority = fifo_priority;
    const int err = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &param);
    if (err == 0) return Status::ok();
    rlimit rt{};
    ::getrlimit(RLIMIT_RTPRIO, &rt);
    const std::string message =
        "real-time scheduling not permitted (" + name + ": SCHED_FIFO " +
        std::to_string(fifo_priority) + ": " + std::strerror(err) + ", RLIMIT_RTPRIO " +
        std::to_string(rt.rlim_cur) +
        "): the device and pipeline threads run at normal priority; grant LimitRTPRIO= in the "
        "unit (handscan-pipeline.service) or CAP_SYS_NICE";
    warnOnce(g_warned_scheduling, message);
    return Status(StatusCode::kUnsupported, message);
}

Status lockProcessMemory() {
    rlimit memlock{};
    ::getrlimit(RLIMIT_MEMLOCK, &memlock);
    std::string why;
    if (memlock.rlim_cur != RLIM_INFINITY && !hasEffectiveCapability(CAP_IPC_LOCK)) {
        why = "RLIMIT_MEMLOCK is " + std::to_string(memlock.rlim_cur) +
              " bytes and CAP_IPC_LOCK is not held";
    } else if (::mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
        why = std::string("mlockall: ") + std::strerror(errno);
    } else {
        return Status::ok();
    }
    const std::string message = "memory locking not permitted (" + why +
                                "): page faults may delay the device threads; grant "
                                "LimitMEMLOCK=infinity in the unit or CAP_IPC_LOCK";
    warnOnce(g_warned_memory, message);
    return Status(StatusCode::kUnsupported, message);
}

}  // namespace handscan
