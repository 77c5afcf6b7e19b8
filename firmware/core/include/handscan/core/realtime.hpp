// Real-time scheduling for the daemon's threads. A driver thread that reads a device late
// time-stamps its bytes late (every ms of the 200 Hz IMU's receive jitter is a ms of motion
// misplaced), so the device threads and the pipeline thread run SCHED_FIFO at the priorities of
// device.yaml `realtime:` and the process locks its memory so that no page fault stalls them.
// Permission comes from the unit (LimitRTPRIO=, LimitMEMLOCK=) or CAP_SYS_NICE / CAP_IPC_LOCK.
// Where it is not permitted (a developer's shell, a container) each function says so once per
// process, as a warning naming what to grant, and the thread runs on at normal priority: a scan
// at normal priority is better than no scan.
#pragma once

#include <string>

#include "handscan/core/status.hpp"

namespace handscan {

// device.yaml `realtime:`: SCHED_FIFO priorities (1..99; 0 = normal scheduling) and memory
// locking of handscan-pipeline. The device threads sit above the pipeline thread: they only move
// bytes and time-stamp them, and a late read is a wrong timestamp; the pipeline may lag and
// catch up from its queues.
struct RealtimeConfig {
    int device_priority = 50;
    int pipeline_priority = 40;
    bool lock_memory = true;
};

// The `realtime:` section of device.yaml `path` (validated by loadDeviceConfig as well); the
// defaults above where it is absent. Throws ConfigError like loadDeviceConfig.
RealtimeConfig loadRealtimeConfig(const std::string& path);

// Names the calling thread (`name`, cut to the kernel's 15 characters: `ps -L`, /proc/PID/task)
// and, for `fifo_priority` in 1..99, makes it SCHED_FIFO at that priority; 0 leaves it at the
// normal policy. Not permitted: one warning per process, the status says why.
[[nodiscard]] Status enterRealtimeThread(const std::string& name, int fifo_priority);

// mlockall(MCL_CURRENT | MCL_FUTURE), only when the whole process may be locked (CAP_IPC_LOCK
// or an unlimited RLIMIT_MEMLOCK): with a finite limit, MCL_FUTURE would make later allocations
// fail once the limit is reached. Not permitted: one warning per process.
[[nodiscard]] Status lockProcessMemory();

}  // namespace handscan
