#include "handscan/gpio/button_debouncer.hpp"

#include <gtest/gtest.h>

namespace handscan::gpio {
namespace {

constexpr TimeNs ms = kNsPerMs;
constexpr auto R = GpioEdgeType::kRising;
constexpr auto F = GpioEdgeType::kFalling;

TEST(ButtonDebouncer, TakesTheFirstContactAndIgnoresBounce) {
    ButtonDebouncer d(20 * ms);
    auto c = d.onEdge(100 * ms, R);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_EQ(c[0].t_host, 100 * ms);
    EXPECT_TRUE(c[0].pressed);
    for (TimeNs t : {101, 102, 103, 104, 105, 106}) {
        EXPECT_TRUE(d.onEdge(t * ms, t % 2 ? F : R).empty()) << t;
    }
    EXPECT_FALSE(d.onTime(130 * ms)) << "settled on pressed: no change";
    EXPECT_TRUE(d.pressed());
    EXPECT_EQ(d.bounces(), 6u);
    auto rel = d.onEdge(500 * ms, F);
    ASSERT_EQ(rel.size(), 1u);
    EXPECT_FALSE(rel[0].pressed);
    EXPECT_EQ(rel[0].t_host, 500 * ms);
}

TEST(ButtonDebouncer, ATapShorterThanTheWindowIsPressAndRelease) {
    ButtonDebouncer d(20 * ms);
    ASSERT_EQ(d.onEdge(0, R).size(), 1u);
    EXPECT_TRUE(d.onEdge(8 * ms, F).empty());
    EXPECT_EQ(d.deadline(), 20 * ms);
    EXPECT_FALSE(d.onTime(19 * ms));
    auto c = d.onTime(20 * ms);
    ASSERT_TRUE(c);
    EXPECT_FALSE(c->pressed);
    EXPECT_EQ(c->t_host, 8 * ms);
    EXPECT_FALSE(d.pressed());
}

TEST(ButtonDebouncer, SettlesAPendingWindowBeforeALaterEdge) {
    ButtonDebouncer d(20 * ms);
    ASSERT_EQ(d.onEdge(0, R).size(), 1u);
    EXPECT_TRUE(d.onEdge(5 * ms, F).empty());
    // No onTime() call in between: the next edge first settles the release, then presses again.
    auto c = d.onEdge(100 * ms, R);
    ASSERT_EQ(c.size(), 2u);
    EXPECT_FALSE(c[0].pressed);
    EXPECT_EQ(c[0].t_host, 5 * ms);
    EXPECT_TRUE(c[1].pressed);
    EXPECT_EQ(c[1].t_host, 100 * ms);
}

TEST(ButtonDebouncer, RepeatedEdgesOfTheSameLevelAreNotChanges) {
    ButtonDebouncer d(20 * ms, true);
    EXPECT_TRUE(d.onEdge(0, R).empty());
    EXPECT_EQ(d.deadline(), ButtonDebouncer::kNoDeadline);
}

}  // namespace
}  // namespace handscan::gpio
