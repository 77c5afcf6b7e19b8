// Write/read round trips of the MCAP writer and reader: every message back, in log-time order,
// with its channel, sequence and bytes, for both chunk compressions and several chunk sizes.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"

namespace handscan::recording {
namespace {

struct Sent {
    std::uint16_t channel;
    TimeNs t;
    std::vector<std::uint8_t> data;
};

std::vector<std::uint8_t> payload(std::mt19937& rng, std::size_t n) {
    std::vector<std::uint8_t> v(n);
    for (auto& b : v) b = static_cast<std::uint8_t>(rng());
    return v;
}

// Three interleaved streams at IMU, laser and camera-like rates with arrival jitter.
std::vector<Sent> makeStreams(std::mt19937& rng, int seconds) {
    std::vector<Sent> out;
    const TimeNs t0 = 1'000 * kNsPerSec;
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 5 * kNsPerMs) out.push_back({0, t0 + t, payload(rng, 40)});
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 25 * kNsPerMs) out.push_back({1, t0 + t + 3, payload(rng, 3000)});
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 20 * kNsPerMs) out.push_back({2, t0 + t + 7, payload(rng, 20000)});
    std::stable_sort(out.begin(), out.end(), [](const Sent& a, const Sent& b) { return a.t < b.t; });
    return out;
}

std::vector<std::uint8_t> writeAll(const std::vector<Sent>& msgs, McapWriterOptions opts) {
    auto w = McapWriter::inMemory(opts);
    EXPECT_TRUE(w) << w.status().message();
    EXPECT_EQ(*(*w)->addChannel("/imu", "x-test"), 0);
    EXPECT_EQ(*(*w)->addChannel("/laser", "x-test"), 1);
    EXPECT_EQ(*(*w)->addChannel("/camera", "x-test"), 2);
    for (const auto& m : msgs) EXPECT_TRUE((*w)->write(m.channel, m.t, m.data));
    EXPECT_TRUE((*w)->close());
    return (*w)->takeBuffer();
}

class RoundTrip : public ::testing::TestWithParam<std::tuple<std::string, std::size_t>> {};

TEST_P(RoundTrip, EveryMessageBackInOrder) {
    std::mt19937 rng(42);
    const auto msgs = makeStreams(rng, 3);
    McapWriterOptions opts;
    opts.compression = std::get<0>(GetParam());
    opts.chunk_size_bytes = std::get<1>(GetParam());
    const auto bytes = writeAll(msgs, opts);

    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r) << r.status().message();
    McapReader& reader = **r;
    EXPECT_TRUE(reader.indexed());
    EXPECT_FALSE(reader.truncated());
    EXPECT_TRUE(reader.dropped().empty());
    ASSERT_EQ(reader.channels().size(), 3u);
    EXPECT_EQ(reader.channels()[1].topic, "/laser");
    ASSERT_TRUE(reader.statistics());
    EXPECT_EQ(reader.statistics()->message_count, msgs.size());
    EXPECT_GT(reader.chunkCount(), 1u);
    EXPECT_TRUE(reader.verify()) << reader.verify().message();

    std::size_t i = 0;
    std::vector<std::uint32_t> seq(3, 0);
    RecordedMessage m;
    auto it = reader.messages();
    while (it.next(m)) {
        ASSERT_LT(i, msgs.size());
        EXPECT_EQ(m.log_time, msgs[i].t);
        EXPECT_EQ(m.channel->id, msgs[i].channel);
        EXPECT_EQ(m.sequence, seq[m.channel->id]++);
        ASSERT_TRUE(std::equal(m.data.begin(), m.data.end(), msgs[i].data.begin(), msgs[i].data.end())) << "message " << i;
        ++i;
    }
    EXPECT_TRUE(it.status());
    EXPECT_EQ(i, msgs.size());
}

INSTANTIATE_TEST_SUITE_P(Compressions, RoundTrip,
                         ::testing::Combine(::testing::Values(std::string(""), std::string("zstd")),
                                            ::testing::Values(std::size_t{4096}, std::size_t{1} << 20)));

}  // namespace
}  // namespace handscan::recording
