#include "handscan/motor/position_unwrapper.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace handscan::motor {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

TEST(PositionUnwrapper, UnwrapsASingleTurnCounterForwardAndBackward) {
    PositionUnwrapper u({4096, 4096, false, 20 * kNsPerMs});
    // 1000 counts per ms forwards across the 4095 -> 0 wrap, twice around.
    std::uint32_t raw = 3000;
    double last = 0;
    for (int i = 0; i < 10; ++i) {
        auto s = u.update(i * kNsPerMs, raw);
        ASSERT_TRUE(s) << s.status().message();
        if (i > 0) {
            EXPECT_NEAR(s->angle_rad - last, 1000.0 * kTwoPi / 4096, 1e-12);
        }
        last = s->angle_rad;
        raw = (raw + 1000) % 4096;
    }
    EXPECT_EQ(u.unwrappedCounts(), 3000 + 9 * 1000);
    EXPECT_EQ(u.wraps(), 2u);
    // Backwards across 0 -> 4095.
    PositionUnwrapper b({4096, 4096, false, 20 * kNsPerMs});
    ASSERT_TRUE(b.update(0, 10));
    auto s = b.update(kNsPerMs, 4090);
    ASSERT_TRUE(s);
    EXPECT_EQ(b.unwrappedCounts(), 10 - 16);
    EXPECT_NEAR(s->angle_rad, -6.0 * kTwoPi / 4096, 1e-12);
}

TEST(PositionUnwrapper, WrapsTheFull32BitCounter) {
    PositionUnwrapper u({8192, 0, false, 20 * kNsPerMs});
    ASSERT_TRUE(u.update(0, 0xFFFFFF00u));
    auto s = u.update(kNsPerMs, 0x00000100u);
    ASSERT_TRUE(s);
    EXPECT_EQ(u.unwrappedCounts(), std::int64_t{0xFFFFFF00u} + 0x200);
    EXPECT_EQ(u.wraps(), 1u);
}

TEST(PositionUnwrapper, EstimatesConstantSpeedExactlyAndReversesSign) {
    for (bool reverse : {false, true}) {
        PositionUnwrapper u({4096, 4096 * 16, reverse, 20 * kNsPerMs});
        // 2 rev/s = 8192 counts/s: 8.192 counts per ms; quantised to whole counts.
        EncoderSample last;
        for (int i = 0; i < 100; ++i) {
            const auto raw = static_cast<std::uint32_t>(
                static_cast<std::int64_t>(i * 8192LL / 1000) % (4096 * 16));
            auto s = u.update(i * kNsPerMs, raw);
            ASSERT_TRUE(s);
            last = *s;
        }
        EXPECT_NEAR(last.speed_radps, (reverse ? -1 : 1) * 2.0 * kTwoPi, 0.02 * kTwoPi);
    }
}

TEST(PositionUnwrapper, RejectsOutOfRangeValuesAndTimeGoingBackwards) {
    PositionUnwrapper u({4096, 4096, false, 20 * kNsPerMs});
    auto bad = u.update(0, 5000);
    ASSERT_FALSE(bad);
    EXPECT_NE(bad.status().message().find("6002h"), std::string::npos);
    ASSERT_TRUE(u.update(10, 100));
    EXPECT_FALSE(u.update(5, 101));
    auto ok = u.update(20, 102);
    ASSERT_TRUE(ok) << "state kept after a rejected value";
    EXPECT_EQ(u.unwrappedCounts(), 102);
}

}  // namespace
}  // namespace handscan::motor
