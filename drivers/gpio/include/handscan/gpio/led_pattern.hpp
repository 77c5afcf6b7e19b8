// LED blink patterns as pure functions of time, so the panel only writes a line when its level
// changes and tests can check any instant. Periods are chosen to be told apart at a glance.
#pragma once

#include <cstdint>

#include "handscan/core/time.hpp"

namespace handscan::gpio {

enum class LedPattern : std::uint8_t {
    kOff,
    kOn,
    kBlinkSlow,    // 1 Hz, 50 %: busy (exporting)
    kBlinkFast,    // 4 Hz, 50 %: attention (fault)
    kDoubleFlash,  // two 100 ms flashes per second: waiting (ready, not scanning)
};
const char* toString(LedPattern p);

// The LED level `since` after the pattern was set.
bool ledLevel(LedPattern pattern, TimeNs since);
// The next instant (relative to the pattern start) at which the level changes after `since`.
TimeNs nextLedChange(LedPattern pattern, TimeNs since);

}  // namespace handscan::gpio
