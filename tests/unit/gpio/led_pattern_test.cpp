#include "handscan/gpio/led_pattern.hpp"

#include <gtest/gtest.h>

namespace handscan::gpio {
namespace {

constexpr TimeNs ms = kNsPerMs;

TEST(LedPattern, LevelsAtKnownInstants) {
    EXPECT_FALSE(ledLevel(LedPattern::kOff, 0));
    EXPECT_TRUE(ledLevel(LedPattern::kOn, 123 * ms));
    EXPECT_TRUE(ledLevel(LedPattern::kBlinkSlow, 0));
    EXPECT_TRUE(ledLevel(LedPattern::kBlinkSlow, 499 * ms));
    EXPECT_FALSE(ledLevel(LedPattern::kBlinkSlow, 500 * ms));
    EXPECT_TRUE(ledLevel(LedPattern::kBlinkSlow, 1000 * ms));
    EXPECT_TRUE(ledLevel(LedPattern::kBlinkFast, 124 * ms));
    EXPECT_FALSE(ledLevel(LedPattern::kBlinkFast, 125 * ms));
    EXPECT_TRUE(ledLevel(LedPattern::kDoubleFlash, 50 * ms));
    EXPECT_FALSE(ledLevel(LedPattern::kDoubleFlash, 150 * ms));
    EXPECT_TRUE(ledLevel(LedPattern::kDoubleFlash, 250 * ms));
    EXPECT_FALSE(ledLevel(LedPattern::kDoubleFlash, 600 * ms));
}

TEST(LedPattern, NextChangeIsExactlyWhereTheLevelFlips) {
    for (LedPattern p :
         {LedPattern::kBlinkSlow, LedPattern::kBlinkFast, LedPattern::kDoubleFlash}) {
        TimeNs t = 0;
        int changes = 0;
        while (t < 3000 * ms) {
            const TimeNs next = nextLedChange(p, t);
            ASSERT_GT(next, t);
            // Constant until `next`, different at `next`.
            ASSERT_EQ(ledLevel(p, t), ledLevel(p, next - 1)) << toString(p) << " " << t;
            ASSERT_NE(ledLevel(p, next - 1), ledLevel(p, next)) << toString(p) << " " << next;
            t = next;
            ++changes;
        }
        const int per_second = p == LedPattern::kBlinkSlow   ? 2
                               : p == LedPattern::kBlinkFast ? 8
                                                             : 4;
        EXPECT_EQ(changes, 3 * per_second) << toString(p);
    }
    EXPECT_EQ(nextLedChange(LedPattern::kOn, 0), INT64_MAX);
}

}  // namespace
}  // namespace handscan::gpio
