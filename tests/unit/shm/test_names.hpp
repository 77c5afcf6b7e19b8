// Region names unique per test process, so parallel CTest runs never share a region.
#pragma once

#include <unistd.h>

#include <string>

namespace handscan::shm::testing {

inline std::string uniqueRegionName(const std::string& tag) {
    static int counter = 0;
    return "/handscan-test-" + tag + "-" + std::to_string(::getpid()) + "-" +
           std::to_string(++counter);
}

}  // namespace handscan::shm::testing
