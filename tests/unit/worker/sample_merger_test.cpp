// The worker's merge: samples of every device in sample-time order, each released once the
// source's clock is the hold-back window past it, whatever order and batches they arrived in.
#include "handscan/worker/sample_merger.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace handscan::worker {
namespace {

using sources::Sample;
using sources::sampleTime;

Sample imuAt(TimeNs t) {
    ImuSample s;
    s.t_host = t;
    return s;
}
Sample encoderAt(TimeNs t) {
    EncoderSample s;
    s.t_host = t;
    return s;
}
Sample scanAt(TimeNs t) {
    LaserScan s;
    s.t_host = t;
    return s;
}

struct Arrival {
    TimeNs t_rx;
    Sample sample;
};

// A second of a rig: IMU at 200 Hz (1-3 ms late), encoder at 200 Hz (0.2-2 ms late), scans at
// 40 Hz (first step 25-35 ms before arrival).
std::vector<Arrival> rig(std::mt19937& rng) {
    std::vector<Arrival> a;
    std::uniform_int_distribution<TimeNs> late_imu(kNsPerMs, 3 * kNsPerMs);
    std::uniform_int_distribution<TimeNs> late_enc(200 * kNsPerUs, 2 * kNsPerMs);
    std::uniform_int_distribution<TimeNs> late_scan(25 * kNsPerMs, 35 * kNsPerMs);
    for (TimeNs t = 0; t < kNsPerSec; t += 5 * kNsPerMs) {
        a.push_back({t + late_imu(rng), imuAt(t)});
        a.push_back({t + 1 * kNsPerMs + late_enc(rng), encoderAt(t + 1 * kNsPerMs)});
    }
    for (TimeNs t = 2 * kNsPerMs; t < kNsPerSec; t += 25 * kNsPerMs)
        a.push_back({t + late_scan(rng), scanAt(t)});
    std::stable_sort(a.begin(), a.end(),
                     [](const Arrival& x, const Arrival& y) { return x.t_rx < y.t_rx; });
    return a;
}

// Feeds the arrivals in batches of `batch` (the source's clock: the last arrival's time) and
// returns the release order.
std::vector<Sample> merge(const std::vector<Arrival>& arrivals, std::size_t batch,
                          TimeNs hold_back) {
    SampleMerger m;
    std::vector<Sample> out;
    for (std::size_t i = 0; i < arrivals.size(); i += batch) {
        const std::size_t end = std::min(arrivals.size(), i + batch);
        for (std::size_t k = i; k < end; ++k) m.push(arrivals[k].sample);
        const TimeNs clock = arrivals[end - 1].t_rx;
        while (auto s = m.pop(clock - hold_back)) {
            EXPECT_LE(sampleTime(*s), clock - hold_back);
            out.push_back(std::move(*s));
        }
    }
    while (auto s = m.pop(std::numeric_limits<TimeNs>::max())) out.push_back(std::move(*s));
    EXPECT_EQ(m.size(), 0u);
    return out;
}

TEST(SampleMerger, ReleasesInSampleTimeOrderWhateverTheBatching) {
    std::mt19937 rng(3);
    const std::vector<Arrival> arrivals = rig(rng);
    const std::vector<Sample> one = merge(arrivals, 1, 100 * kNsPerMs);
    ASSERT_EQ(one.size(), arrivals.size());
    for (std::size_t i = 1; i < one.size(); ++i)
        ASSERT_LE(sampleTime(one[i - 1]), sampleTime(one[i])) << "sample " << i;
    // A live source drains its queues in batches; the order is the same.
    for (std::size_t batch : {3u, 17u, 64u}) {
        const std::vector<Sample> other = merge(arrivals, batch, 100 * kNsPerMs);
        ASSERT_EQ(other.size(), one.size());
        for (std::size_t i = 0; i < one.size(); ++i) {
            ASSERT_EQ(sampleTime(other[i]), sampleTime(one[i])) << "batch " << batch;
            ASSERT_EQ(other[i].index(), one[i].index()) << "batch " << batch;
        }
    }
}

TEST(SampleMerger, AScanIsNotOvertakenByTheSamplesItNeeds) {
    // Without the hold-back a scan arriving 30 ms after its first step would come after the IMU
    // and encoder samples of those 30 ms; with it, it comes first.
    SampleMerger m;
    m.push(imuAt(10 * kNsPerMs));
    m.push(encoderAt(20 * kNsPerMs));
    m.push(scanAt(5 * kNsPerMs));  // arrives last, was taken first
    m.push(imuAt(15 * kNsPerMs));
    EXPECT_FALSE(m.pop(4 * kNsPerMs).has_value());
    auto first = m.pop(100 * kNsPerMs);
    ASSERT_TRUE(first);
    EXPECT_TRUE(std::holds_alternative<LaserScan>(*first));
    EXPECT_EQ(sampleTime(*m.pop(100 * kNsPerMs)), 10 * kNsPerMs);
    EXPECT_EQ(sampleTime(*m.pop(100 * kNsPerMs)), 15 * kNsPerMs);
    EXPECT_EQ(sampleTime(*m.pop(100 * kNsPerMs)), 20 * kNsPerMs);
    EXPECT_FALSE(m.pop(100 * kNsPerMs).has_value());
}

TEST(SampleMerger, EqualTimesGoImuEncoderScan) {
    SampleMerger m;
    m.push(scanAt(7));
    m.push(encoderAt(7));
    m.push(imuAt(7));
    EXPECT_TRUE(std::holds_alternative<ImuSample>(*m.pop(7)));
    EXPECT_TRUE(std::holds_alternative<EncoderSample>(*m.pop(7)));
    EXPECT_TRUE(std::holds_alternative<LaserScan>(*m.pop(7)));
}

}  // namespace
}  // namespace handscan::worker
