// The Recorder under load from several driver threads: every message offered is either in the
// file (per channel in order, bytes intact) or counted as dropped, and a full queue drops
// instead of blocking the driver.
#include "handscan/recording/recorder.hpp"

#include <gtest/gtest.h>

#include <thread>

#include "handscan/recording/mcap_reader.hpp"
#include "mcap_test_util.hpp"

namespace handscan::recording {
namespace {

std::vector<std::uint8_t> messageBytes(int channel, int i, std::size_t size) {
    std::vector<std::uint8_t> v(size);
    for (std::size_t k = 0; k < size; ++k) v[k] = static_cast<std::uint8_t>(channel * 50 + i + k);
    return v;
}

TEST(Recorder, ThreeDriverThreadsEveryMessageWrittenOrCounted) {
    const std::string path = ::testing::TempDir() + "/recorder_threads.mcap";
    RecorderOptions o;
    o.mcap.chunk_size_bytes = 64 * 1024;
    auto rec = Recorder::create(path, o);
    ASSERT_TRUE(rec) << rec.status().message();
    const ChannelSpec* specs[] = {&channels::kXsensRaw, &channels::kHokuyoRaw,
                                  &channels::kCameraTrack};
    const std::size_t sizes[] = {60, 3300, 40000};
    const int counts[] = {4000, 800, 200};
    std::vector<RawTap*> taps;
    for (const auto* s : specs) {
        auto tap = (*rec)->addChannel(*s);
        ASSERT_TRUE(tap);
        taps.push_back(*tap);
    }
    ASSERT_TRUE((*rec)->start());
    std::vector<std::thread> drivers;
    for (int c = 0; c < 3; ++c) {
        drivers.emplace_back([&, c] {
            for (int i = 0; i < counts[c]; ++i) {
                const auto bytes = messageBytes(c, i, sizes[c]);
                taps[static_cast<std::size_t>(c)]->onRaw(monotonicNow(), bytes);
                if (i % 64 == 0) std::this_thread::yield();
            }
        });
    }
    for (auto& t : drivers) t.join();
    ASSERT_TRUE((*rec)->stop());
    const auto counters = (*rec)->counters();

    auto r = McapReader::open(path);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE((*r)->indexed());
    for (int c = 0; c < 3; ++c) {
        SCOPED_TRACE(std::string(specs[c]->topic));
        const auto& k = counters[static_cast<std::size_t>(c)];
        EXPECT_EQ(k.topic, specs[c]->topic);
        EXPECT_EQ(k.written + k.dropped, static_cast<std::uint64_t>(counts[c]));
        const auto got = test::readAll(**r, {{std::string(specs[c]->topic)}});
        ASSERT_EQ(got.size(), k.written);
        EXPECT_EQ(k.bytes_written, k.written * sizes[c]);
        EXPECT_EQ((*r)->findTopic(specs[c]->topic)->message_encoding, specs[c]->message_encoding);
        // In order, intact; with no drops, exactly the offered sequence.
        TimeNs last = 0;
        for (std::size_t i = 0; i < got.size(); ++i) {
            EXPECT_GE(got[i].t, last);
            last = got[i].t;
            if (k.dropped == 0) {
                ASSERT_EQ(got[i].data, messageBytes(c, static_cast<int>(i), sizes[c]));
            }
        }
    }
    std::remove(path.c_str());
}

TEST(Recorder, FullQueueDropsAndCountsWithoutBlocking) {
    const std::string path = ::testing::TempDir() + "/recorder_drops.mcap";
    RecorderOptions o;
    o.queue_bytes = 150;  // room for two 60-byte messages
    auto rec = Recorder::create(path, o);
    ASSERT_TRUE(rec);
    auto tap = (*rec)->addChannel(channels::kXsensRaw);
    ASSERT_TRUE(tap);
    // The writer thread is not running yet: the queue fills and stays full.
    for (int i = 0; i < 10; ++i) (*tap)->onRaw(1000 + i, messageBytes(0, i, 60));
    ASSERT_TRUE((*rec)->start());
    ASSERT_TRUE((*rec)->stop());
    const auto k = (*rec)->counters().at(0);
    EXPECT_EQ(k.written, 2u);
    EXPECT_EQ(k.dropped, 8u);
    (*tap)->onRaw(5000, messageBytes(0, 0, 60));  // after stop(): counted, not written
    EXPECT_EQ((*rec)->counters().at(0).dropped, 9u);

    auto r = McapReader::open(path);
    ASSERT_TRUE(r);
    const auto got = test::readAll(**r);
    ASSERT_EQ(got.size(), 2u);
    EXPECT_EQ(got[0].t, 1000);
    EXPECT_EQ(got[1].data, messageBytes(0, 1, 60));
    std::remove(path.c_str());
}

// Devices go quiet: the open chunk reaches the disk after a chunk duration, while recording
// goes on (a power cut now would not lose it).
TEST(Recorder, QuietDevicesGetTheirLastChunkWritten) {
    const std::string path = ::testing::TempDir() + "/recorder_idle.mcap";
    RecorderOptions o;
    o.mcap.chunk_duration_ns = 50 * kNsPerMs;
    o.idle_sleep_ns = kNsPerMs;
    auto rec = Recorder::create(path, o);
    ASSERT_TRUE(rec);
    auto tap = (*rec)->addChannel(channels::kGpioEvents);
    ASSERT_TRUE(tap);
    ASSERT_TRUE((*rec)->start());
    for (int i = 0; i < 3; ++i) (*tap)->onRaw(monotonicNow(), messageBytes(0, i, 13));
    // Poll the file as a crash-recovery reader would see it, for up to 5 s.
    std::size_t seen = 0;
    for (int k = 0; k < 500 && seen < 3; ++k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(10));
        auto r = McapReader::open(path);
        if (r) seen = test::readAll(**r).size();
    }
    EXPECT_EQ(seen, 3u);
    ASSERT_TRUE((*rec)->stop());
    std::remove(path.c_str());
}

TEST(Recorder, UnwritableDirectoryIsAClearError) {
    auto rec = Recorder::create("/nonexistent-dir/rec.mcap");
    ASSERT_FALSE(rec);
    EXPECT_EQ(rec.status().code(), StatusCode::kIoError);
    EXPECT_NE(rec.status().message().find("/nonexistent-dir/rec.mcap: cannot create the recording"),
              std::string::npos);
}

TEST(Recorder, ChannelsMustBeAddedBeforeStart) {
    const std::string path = ::testing::TempDir() + "/recorder_late.mcap";
    auto rec = Recorder::create(path);
    ASSERT_TRUE(rec);
    ASSERT_TRUE((*rec)->start());
    auto tap = (*rec)->addChannel(channels::kGpioEvents);
    ASSERT_FALSE(tap);
    EXPECT_EQ(tap.status().code(), StatusCode::kInvalidArgument);
    ASSERT_TRUE((*rec)->stop());
    std::remove(path.c_str());
}

}  // namespace
}  // namespace handscan::recording
