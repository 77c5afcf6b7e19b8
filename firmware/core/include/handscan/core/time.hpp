// Time on the device: int64 nanoseconds of the host's CLOCK_MONOTONIC. Every sample carries one;
// device clocks are mapped onto it by ClockMapper.
#pragma once

#include <cstdint>

namespace handscan {

using TimeNs = std::int64_t;  // nanoseconds of host CLOCK_MONOTONIC

constexpr TimeNs kNsPerUs = 1'000;
constexpr TimeNs kNsPerMs = 1'000'000;
constexpr TimeNs kNsPerSec = 1'000'000'000;

constexpr double toSeconds(TimeNs t) { return static_cast<double>(t) * 1e-9; }
constexpr TimeNs fromSeconds(double s) {
    return static_cast<TimeNs>(s * 1e9 + (s >= 0 ? 0.5 : -0.5));
}

// The host's CLOCK_MONOTONIC now.
TimeNs monotonicNow();
// The calling thread's CPU time in ms (CLOCK_THREAD_CPUTIME_ID): the cost of a computation on a
// shared machine, where wall time says little.
double threadCpuMs();

}  // namespace handscan
