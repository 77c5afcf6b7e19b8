#include "handscan/gpio/led_pattern.hpp"

#include <initializer_list>
#include <limits>

namespace handscan::gpio {
namespace {

constexpr TimeNs kMs = kNsPerMs;

// Each blinking pattern is a period and the on-intervals within it.
struct Interval {
    TimeNs on, off;
};
struct Shape {
    TimeNs period;
    Interval on[2];
    int count;
};

Shape shape(LedPattern p) {
    switch (p) {
        case LedPattern::kBlinkSlow:
            return {1000 * kMs, {{0, 500 * kMs}, {0, 0}}, 1};
        case LedPattern::kBlinkFast:
            return {250 * kMs, {{0, 125 * kMs}, {0, 0}}, 1};
        case LedPattern::kDoubleFlash:
            return {1000 * kMs, {{0, 100 * kMs}, {200 * kMs, 300 * kMs}}, 2};
        default:
            return {0, {{0, 0}, {0, 0}}, 0};
    }
}

}  // namespace

const char* toString(LedPattern p) {
    switch (p) {
        case LedPattern::kOff:
            return "off";
        case LedPattern::kOn:
            return "on";
        case LedPattern::kBlinkSlow:
            return "blink_slow";
        case LedPattern::kBlinkFast:
            return "blink_fast";
        case LedPattern::kDoubleFlash:
            return "double_flash";
    }
    return "?";
}

bool ledLevel(LedPattern p, TimeNs since) {
    if (p == LedPattern::kOff) return false;
    if (p == LedPattern::kOn) return true;
    const Shape s = shape(p);
    const TimeNs phase = ((since % s.period) + s.period) % s.period;
    for (int i = 0; i < s.count; ++i) {
        if (phase >= s.on[i].on && phase < s.on[i].off) return true;
    }
    return false;
}

TimeNs nextLedChange(LedPattern p, TimeNs since) {
    if (p == LedPattern::kOff || p == LedPattern::kOn) return std::numeric_limits<TimeNs>::max();
    const Shape s = shape(p);
    const TimeNs base = since - (((since % s.period) + s.period) % s.period);
    TimeNs best = std::numeric_limits<TimeNs>::max();
    for (TimeNs cycle : {base, base + s.period}) {
        for (int i = 0; i < s.count; ++i) {
            for (TimeNs edge : {cycle + s.on[i].on, cycle + s.on[i].off}) {
                if (edge > since && edge < best) best = edge;
            }
        }
    }
    return best;
}

}  // namespace handscan::gpio
