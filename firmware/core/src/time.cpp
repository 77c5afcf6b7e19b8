#include "handscan/core/time.hpp"

#include <ctime>

namespace handscan {

TimeNs monotonicNow() {
    timespec ts{};
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return static_cast<TimeNs>(ts.tv_sec) * kNsPerSec + ts.tv_nsec;
}

}  // namespace handscan
