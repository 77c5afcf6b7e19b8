// The replay's per-module timing keeps constant memory and still reports what sorting every
// duration would: exact count, mean, total and maximum; median and 99th percentile within 0.25 %.
#include "handscan/core/call_timer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace handscan::replay {
namespace {

TEST(CallTimer, PercentilesMatchTheSortedDurations) {
    std::mt19937 rng(1);
    std::lognormal_distribution<double> d(std::log(3.0), 1.2);  // microseconds, long tail
    std::vector<double> v;
    CallTimer timer;
    for (int i = 0; i < 200000; ++i) {
        v.push_back(d(rng));
        timer.add("imu", v.back());
    }
    timer.add("one", 42.0);
    const auto s = timer.summary();
    std::sort(v.begin(), v.end());
    const CallStats& imu = s.at("imu");
    EXPECT_EQ(imu.calls, v.size());
    double sum = 0;
    for (double x : v) sum += x;
    EXPECT_NEAR(imu.mean_us, sum / static_cast<double>(v.size()), 1e-9 * sum);
    EXPECT_NEAR(imu.total_ms, sum * 1e-3, 1e-9 * sum);
    EXPECT_EQ(imu.max_us, v.back());
    EXPECT_NEAR(imu.p50_us, v[v.size() / 2], 0.0025 * v[v.size() / 2]);
    const double p99 = v[static_cast<std::size_t>(0.99 * static_cast<double>(v.size()))];
    EXPECT_NEAR(imu.p99_us, p99, 0.0025 * p99);
    // A single call: every statistic is that call.
    EXPECT_EQ(s.at("one").calls, 1u);
    EXPECT_EQ(s.at("one").p50_us, 42.0);
    EXPECT_EQ(s.at("one").p99_us, 42.0);
    EXPECT_EQ(s.at("one").max_us, 42.0);
}

TEST(CallTimer, OutOfRangeDurationsLandInTheEndBuckets) {
    CallTimer timer;
    timer.add("m", 0.0);
    timer.add("m", 5e9);  // longer than the last bucket's edge
    const CallStats s = timer.summary().at("m");
    EXPECT_EQ(s.calls, 2u);
    EXPECT_EQ(s.max_us, 5e9);
    EXPECT_EQ(s.p50_us, 5e9);  // rank 1 of 2: the long one, as seen
    EXPECT_EQ(s.mean_us, 2.5e9);
}

}  // namespace
}  // namespace handscan::replay
