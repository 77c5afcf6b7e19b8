// Write/read round trips of the MCAP writer and reader: every message back, in log-time order,
// with its channel, sequence and bytes, for both chunk compressions and several chunk sizes.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"
#include "mcap_test_util.hpp"

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
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 5 * kNsPerMs)
        out.push_back({0, t0 + t, payload(rng, 40)});
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 25 * kNsPerMs)
        out.push_back({1, t0 + t + 3, payload(rng, 3000)});
    for (TimeNs t = 0; t < seconds * kNsPerSec; t += 20 * kNsPerMs)
        out.push_back({2, t0 + t + 7, payload(rng, 20000)});
    std::stable_sort(out.begin(), out.end(),
                     [](const Sent& a, const Sent& b) { return a.t < b.t; });
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
        ASSERT_TRUE(
            std::equal(m.data.begin(), m.data.end(), msgs[i].data.begin(), msgs[i].data.end()))
            << "message " << i;
        ++i;
    }
    EXPECT_TRUE(it.status());
    EXPECT_EQ(i, msgs.size());
}

TEST(RoundTrip, TopicAndTimeFilters) {
    std::mt19937 rng(3);
    const auto msgs = makeStreams(rng, 2);
    McapWriterOptions opts;
    opts.chunk_size_bytes = 8192;
    auto r = McapReader::fromBuffer(writeAll(msgs, opts));
    ASSERT_TRUE(r);
    ReadOptions o;
    o.topics = {"/laser", "/nope"};
    o.start_time = msgs[100].t;
    o.end_time = msgs[400].t;
    std::vector<TimeNs> expected;
    for (const auto& m : msgs) {
        if (m.channel == 1 && m.t >= o.start_time && m.t <= o.end_time) expected.push_back(m.t);
    }
    std::vector<TimeNs> got;
    ASSERT_TRUE((*r)->forEachMessage(o, [&](const RecordedMessage& m) {
        EXPECT_EQ(m.channel->topic, "/laser");
        got.push_back(m.log_time);
    }));
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(got, expected);
    o.topics = {"/nope"};
    EXPECT_EQ(test::readAll(**r, o).size(), 0u);
}

// Messages written out of log-time order (a late device) come back sorted across chunks.
TEST(RoundTrip, OutOfOrderArrivalsComeBackSorted) {
    McapWriterOptions opts;
    opts.chunk_size_bytes = 256;
    auto w = McapWriter::inMemory(opts);
    const auto a = *(*w)->addChannel("/a", "x-test");
    const auto b = *(*w)->addChannel("/b", "x-test");
    for (TimeNs t = 0; t < 100; ++t) {
        ASSERT_TRUE((*w)->write(a, 1000 + t * 10, std::vector<std::uint8_t>(40, 1)));
        if (t % 10 == 9) {  // /b arrives in bursts, 95 ns late
            for (TimeNs k = 9; k >= 0; --k)
                ASSERT_TRUE(
                    (*w)->write(b, 1000 + (t - k) * 10 + 5, std::vector<std::uint8_t>(40, 2)));
        }
    }
    ASSERT_TRUE((*w)->close());
    auto r = McapReader::fromBuffer((*w)->takeBuffer());
    ASSERT_TRUE(r);
    const auto got = test::readAll(**r);
    ASSERT_EQ(got.size(), 200u);
    for (std::size_t i = 0; i < got.size(); ++i)
        EXPECT_EQ(got[i].t, 1000 + static_cast<TimeNs>(i) * 5) << i;
}

TEST(RoundTrip, EmptyRecordingAndSchemas) {
    auto w = McapWriter::inMemory();
    const auto schema = (*w)->addSchema("handscan.Note", "x-handscan-text", {'t', 'x', 't'});
    ASSERT_TRUE(schema);
    EXPECT_EQ(*schema, 1);
    ASSERT_TRUE((*w)->addChannel("/notes", "x-text", *schema, {{"k", "v"}}));
    ASSERT_TRUE((*w)->close());
    auto r = McapReader::fromBuffer((*w)->takeBuffer());
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE((*r)->indexed());
    EXPECT_EQ((*r)->statistics()->message_count, 0u);
    ASSERT_EQ((*r)->schemas().size(), 1u);
    EXPECT_EQ((*r)->schemas()[0].data, (std::vector<std::uint8_t>{'t', 'x', 't'}));
    ASSERT_EQ((*r)->channels().size(), 1u);
    EXPECT_EQ((*r)->channels()[0].schema_id, 1);
    EXPECT_EQ((*r)->channels()[0].metadata.at("k"), "v");
    EXPECT_TRUE(test::readAll(**r).empty());
    EXPECT_TRUE((*r)->verify());
}

TEST(RoundTrip, WriterRefusesBadUse) {
    McapWriterOptions o;
    o.compression = "lz4";
    auto bad = McapWriter::inMemory(o);
    ASSERT_FALSE(bad);
    EXPECT_EQ(bad.status().code(), StatusCode::kUnsupported);

    auto w = McapWriter::inMemory();
    const auto ch = *(*w)->addChannel("/a", "x-test");
    EXPECT_EQ((*w)->addChannel("/a", "x-test").status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ((*w)->addChannel("/b", "x-test", 7).status().code(), StatusCode::kInvalidArgument);
    EXPECT_EQ((*w)->write(9, 1, {}).code(), StatusCode::kInvalidArgument);
    EXPECT_EQ((*w)->write(ch, -1, {}).code(), StatusCode::kInvalidArgument);
    ASSERT_TRUE((*w)->close());
    EXPECT_EQ((*w)->write(ch, 1, {}).code(), StatusCode::kInvalidArgument);
}

TEST(RoundTrip, ChunksCloseAtTheConfiguredDuration) {
    McapWriterOptions opts;
    opts.chunk_duration_ns = 100 * kNsPerMs;
    auto w = McapWriter::inMemory(opts);
    const auto ch = *(*w)->addChannel("/imu", "x-test");
    for (int i = 0; i < 200; ++i)
        ASSERT_TRUE((*w)->write(ch, i * 5 * kNsPerMs, std::vector<std::uint8_t>(70, 0)));
    ASSERT_TRUE((*w)->close());
    EXPECT_EQ((*w)->chunkCount(), 10u);  // 1 s of 200 Hz samples, a chunk per 100 ms
}

INSTANTIATE_TEST_SUITE_P(Compressions, RoundTrip,
                         ::testing::Combine(::testing::Values(std::string(""), std::string("zstd")),
                                            ::testing::Values(std::size_t{4096},
                                                              std::size_t{1} << 20)));

}  // namespace
}  // namespace handscan::recording
