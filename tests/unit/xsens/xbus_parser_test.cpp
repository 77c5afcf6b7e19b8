// Incremental parser: the real MTi-G-710 captures split at every point, garbage, a lost byte, a
// corrupted checksum. Frames must equal the capture's messages.golden, and damage must cost only
// the damaged frame.
#include "handscan/xsens/xbus_parser.hpp"

#include <gtest/gtest.h>

#include "xsens_test_files.hpp"

namespace handscan::xsens {
namespace {

using Bytes = std::vector<std::uint8_t>;

std::vector<Bytes> parseAll(XbusParser& parser, std::span<const std::uint8_t> chunk) {
    std::vector<Bytes> frames;
    parser.feed(chunk);
    while (auto f = parser.next()) {
        // Re-encode to compare whole frames.
        frames.push_back(encodeFrame(f->mid, f->payload, f->bus_id));
    }
    return frames;
}

std::vector<Bytes> parseInPieces(std::span<const std::uint8_t> stream, std::size_t split,
                                 XbusParser& parser) {
    auto frames = parseAll(parser, stream.subspan(0, split));
    auto rest = parseAll(parser, stream.subspan(split));
    frames.insert(frames.end(), rest.begin(), rest.end());
    return frames;
}

class XbusCapture : public ::testing::TestWithParam<int> {
protected:
    void SetUp() override {
        const auto dir = test::xsensDataDir() / "mtig710" / std::to_string(GetParam());
        if (!std::filesystem::exists(dir)) GTEST_SKIP() << dir << " absent";
        stream_ = test::readBytes(dir / "output.bin");
        for (const auto& line : test::readLines(dir / "messages.golden")) {
            if (!line.empty()) golden_.push_back(test::fromHex(line));
        }
        ASSERT_EQ(golden_.size(), 100u);
    }
    Bytes stream_;
    std::vector<Bytes> golden_;
};

TEST_P(XbusCapture, SplitsIntoTheGoldenFrames) {
    XbusParser parser;
    EXPECT_EQ(parseAll(parser, stream_), golden_);
    EXPECT_EQ(parser.stats().frames, 100u);
    EXPECT_EQ(parser.stats().checksum_failures, 0u);
    EXPECT_EQ(parser.stats().resyncs, 0u);
    EXPECT_EQ(parser.pending(), 0u);
}

TEST_P(XbusCapture, EverySplitPointGivesTheSameFrames) {
    for (std::size_t split = 0; split <= stream_.size(); ++split) {
        XbusParser parser;
        ASSERT_TRUE(parseInPieces(stream_, split, parser) == golden_) << "split at byte " << split;
        ASSERT_EQ(parser.stats().resyncs, 0u);
    }
}

TEST_P(XbusCapture, ByteAtATime) {
    XbusParser parser;
    std::vector<Bytes> frames;
    for (std::uint8_t b : stream_) {
        auto f = parseAll(parser, std::span(&b, 1));
        frames.insert(frames.end(), f.begin(), f.end());
    }
    EXPECT_EQ(frames, golden_);
}

TEST_P(XbusCapture, LostByteCostsOnlyTheDamagedFrame) {
    // Drop one byte at many positions inside frame k: every other frame must come out intact.
    std::vector<std::size_t> frame_of(stream_.size());
    for (std::size_t k = 0, off = 0; k < golden_.size(); off += golden_[k].size(), ++k) {
        std::fill(frame_of.begin() + static_cast<std::ptrdiff_t>(off),
                  frame_of.begin() + static_cast<std::ptrdiff_t>(off + golden_[k].size()), k);
    }
    std::size_t offset = 0;
    int trials = 0;
    for (std::size_t k = 0; k < golden_.size(); ++k) {
        const std::size_t len = golden_[k].size();
        for (std::size_t inside : {std::size_t{0}, std::size_t{1}, std::size_t{3}, std::size_t{5},
                                   len / 2, len - 2, len - 1}) {
            std::size_t pos = offset + inside;
            Bytes damaged = stream_;
            damaged.erase(damaged.begin() + static_cast<std::ptrdiff_t>(pos));
            // Dropping one of a run of equal bytes gives the same stream as dropping the run's
            // last byte (e.g. a checksum of 0xFA before the next preamble): that one is "lost".
            while (pos + 1 < stream_.size() && stream_[pos + 1] == stream_[pos]) ++pos;
            XbusParser parser;
            auto frames = parseAll(parser, damaged);
            std::vector<Bytes> expected = golden_;
            expected.erase(expected.begin() + static_cast<std::ptrdiff_t>(frame_of[pos]));
            ASSERT_EQ(frames.size(), expected.size()) << "frame " << k << " byte " << inside;
            ASSERT_TRUE(frames == expected) << "frame " << k << " byte " << inside;
            // Damage is noticed (a resync), or the damaged last frame waits for bytes.
            ASSERT_TRUE(parser.stats().resyncs >= 1 || parser.pending() > 0) << "frame " << k;
            ++trials;
        }
        offset += len;
    }
    EXPECT_EQ(trials, 700);
}

TEST_P(XbusCapture, CorruptedChecksumCostsOnlyThatFrame) {
    std::size_t offset = 0;
    for (std::size_t k = 0; k < golden_.size(); k += 7) {
        offset = 0;
        for (std::size_t j = 0; j < k; ++j) offset += golden_[j].size();
        Bytes damaged = stream_;
        damaged[offset + golden_[k].size() - 1] ^= 0x5A;  // the checksum byte
        XbusParser parser;
        auto frames = parseAll(parser, damaged);
        std::vector<Bytes> expected = golden_;
        expected.erase(expected.begin() + static_cast<std::ptrdiff_t>(k));
        ASSERT_TRUE(frames == expected) << "frame " << k;
        EXPECT_EQ(parser.stats().checksum_failures, 1u);
        EXPECT_EQ(parser.stats().resyncs, 1u);
    }
}

INSTANTIATE_TEST_SUITE_P(MtiG710, XbusCapture, ::testing::Values(1, 2, 3, 5));

TEST(XbusParser, SkipsGarbageAndCountsOneResyncPerRun) {
    const Bytes ack = encodeFrame(MessageId::kGoToConfigAck);
    Bytes stream{0x00, 0x13, 0xFA, 0x37};  // noise incl. a lone preamble
    stream.insert(stream.end(), ack.begin(), ack.end());
    stream.insert(stream.end(), {0xFA, 0xFA, 0x01});
    stream.insert(stream.end(), ack.begin(), ack.end());
    XbusParser parser;
    const auto frames = parseAll(parser, stream);
    EXPECT_EQ(frames.size(), 2u);
    EXPECT_EQ(parser.stats().resyncs, 2u);
    EXPECT_EQ(parser.stats().bytes_discarded, 7u);
}

TEST(XbusParser, OversizeExtendedLengthIsGarbage) {
    const Bytes ack = encodeFrame(MessageId::kGoToConfigAck);
    Bytes stream{0xFA, 0xFF, 0x36, 0xFF, 0xFF, 0xFF};  // claims 65535 bytes
    stream.insert(stream.end(), ack.begin(), ack.end());
    XbusParser parser;
    EXPECT_EQ(parseAll(parser, stream).size(), 1u);
    EXPECT_EQ(parser.stats().oversize, 1u);
    EXPECT_EQ(parser.pending(), 0u);
}

TEST(XbusParser, BufferStaysBoundedOnNoise) {
    XbusParser parser;
    Bytes noise(4096);
    for (std::size_t i = 0; i < noise.size(); ++i)
        noise[i] = static_cast<std::uint8_t>(i * 37 + 11);
    for (int i = 0; i < 50; ++i) {
        parseAll(parser, noise);
        ASSERT_LE(parser.pending(), kMaxPayload + 8);
    }
}

}  // namespace
}  // namespace handscan::xsens
