// Corruption is found and contained: a flipped byte in a chunk costs that chunk only (reported
// with its offset and the CRC values), a damaged summary falls back to a scan, a damaged byte
// outside chunks fails the data-section CRC in verify(), and non-MCAP input is refused.
#include <gtest/gtest.h>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"
#include "mcap_test_util.hpp"

namespace handscan::recording {
namespace {

using test::Msg;

// 3 channels, 8 chunks of 30 messages each (chunks closed by flush()).
std::vector<std::uint8_t> makeFile(const std::string& compression, std::vector<Msg>& sent) {
    McapWriterOptions o;
    o.compression = compression;
    o.chunk_size_bytes = 1u << 30;
    o.chunk_duration_ns = 0;
    auto w = McapWriter::inMemory(o);
    const std::vector<std::string> topics = {"/a", "/b", "/c"};
    for (const auto& t : topics) EXPECT_TRUE((*w)->addChannel(t, "x-test"));
    TimeNs t = 100;
    for (int chunk = 0; chunk < 8; ++chunk) {
        for (int i = 0; i < 30; ++i, t += 1000) {
            const std::uint16_t ch = static_cast<std::uint16_t>(i % 3);
            std::vector<std::uint8_t> data(50 + i, static_cast<std::uint8_t>(i * 7 + chunk));
            EXPECT_TRUE((*w)->write(ch, t, data));
            sent.push_back({topics[ch], t, data});
        }
        EXPECT_TRUE((*w)->flush());
    }
    EXPECT_TRUE((*w)->close());
    return (*w)->takeBuffer();
}

class Corruption : public ::testing::TestWithParam<std::string> {};

TEST_P(Corruption, FlippedByteInChunkLosesOnlyThatChunk) {
    std::vector<Msg> sent;
    auto bytes = makeFile(GetParam(), sent);
    const auto chunks = test::recordsWithOp(bytes, 0x06);
    ASSERT_EQ(chunks.size(), 8u);
    const auto& victim = chunks[2];
    bytes[victim.offset + victim.size / 2] ^= 0x5A;

    auto r = McapReader::fromBuffer(bytes, "rec.mcap");
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE((*r)->indexed());
    const auto got = test::readAll(**r);
    // Chunk 2 held messages 60..89.
    std::vector<Msg> expected(sent.begin(), sent.begin() + 60);
    expected.insert(expected.end(), sent.begin() + 90, sent.end());
    EXPECT_EQ(got, expected);
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_EQ((*r)->dropped()[0].offset, victim.offset);
    EXPECT_EQ((*r)->dropped()[0].length, victim.size);
    const std::string& reason = (*r)->dropped()[0].reason;
    EXPECT_NE(reason.find("rec.mcap: chunk at byte " + std::to_string(victim.offset)),
              std::string::npos)
        << reason;
    if (GetParam().empty()) {
        EXPECT_NE(reason.find("CRC32 mismatch (stored 0x"), std::string::npos) << reason;
    }

    const Status v = (*r)->verify();
    EXPECT_FALSE(v);
    EXPECT_EQ(v.code(), StatusCode::kChecksumError);
    EXPECT_NE(v.message().find("chunk at byte " + std::to_string(victim.offset)), std::string::npos)
        << v.message();
}

TEST_P(Corruption, CorruptChunkFoundByLinearScanToo) {
    std::vector<Msg> sent;
    auto bytes = makeFile(GetParam(), sent);
    const auto chunks = test::recordsWithOp(bytes, 0x06);
    bytes[chunks[5].offset + chunks[5].size - 3] ^= 0x01;
    bytes.resize(
        test::recordsWithOp(bytes, 0x0F).at(0).offset);  // cut at Data End: no summary, no footer
    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r);
    EXPECT_TRUE((*r)->truncated());
    EXPECT_EQ(test::readAll(**r).size(), sent.size() - 30);
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_EQ((*r)->dropped()[0].offset, chunks[5].offset);
}

// A chunk header that claims a later start time than its first messages (found by the fuzzer:
// the header's times are outside the chunk CRC). The merge has already handed out later messages
// by then, so those early messages are reported and skipped; the rest stays in log-time order.
TEST_P(Corruption, ChunkStartTimeLaterThanItsMessagesKeepsOrder) {
    std::vector<Msg> sent;
    auto bytes = makeFile(GetParam(), sent);
    const auto chunks = test::recordsWithOp(bytes, 0x06);
    bytes.resize(
        test::recordsWithOp(bytes, 0x0F).at(0).offset);  // no summary: times from the chunk headers
    // Chunk 3 holds messages 90..119; claim it starts at message 100's time.
    const TimeNs claimed = sent[100].t;
    for (int i = 0; i < 8; ++i) {
        bytes[chunks[3].offset + 9 + static_cast<std::size_t>(i)] =
            static_cast<std::uint8_t>(static_cast<std::uint64_t>(claimed) >> (8 * i));
    }
    auto r = McapReader::fromBuffer(bytes, "rec.mcap");
    ASSERT_TRUE(r) << r.status().message();
    std::vector<Msg> expected(sent.begin(), sent.begin() + 90);
    expected.insert(expected.end(), sent.begin() + 100, sent.end());
    EXPECT_EQ(test::readAll(**r), expected);
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_EQ((*r)->dropped()[0].offset, chunks[3].offset);
    EXPECT_NE(
        (*r)->dropped()[0].reason.find("10 message(s) logged before the chunk's stated start time"),
        std::string::npos)
        << (*r)->dropped()[0].reason;
}

INSTANTIATE_TEST_SUITE_P(Compressions, Corruption,
                         ::testing::Values(std::string(""), std::string("zstd")));

// A power cut on a file system with delayed allocation can leave a block of zeros where data
// was: the scan loses the chunks the zeros touch and resumes at the next intact chunk.
TEST(Corruption, ZeroedBlockInTheMiddleIsSkippedAndTheScanResumes) {
    std::vector<Msg> sent;
    auto bytes = makeFile("zstd", sent);
    const auto chunks = test::recordsWithOp(bytes, 0x06);
    const std::size_t from = chunks[3].offset + chunks[3].size / 2;
    const std::size_t to = chunks[4].offset + 20;  // chunk 4's header is gone too
    const std::size_t data_end = test::recordsWithOp(bytes, 0x0F).at(0).offset;
    std::fill(bytes.begin() + static_cast<std::ptrdiff_t>(from),
              bytes.begin() + static_cast<std::ptrdiff_t>(to), 0);
    bytes.resize(data_end);  // and the summary never made it
    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r) << r.status().message();
    std::vector<Msg> expected(sent.begin(), sent.begin() + 90);
    expected.insert(expected.end(), sent.begin() + 150, sent.end());
    EXPECT_EQ(test::readAll(**r), expected);
    ASSERT_EQ((*r)->dropped().size(), 2u);
    EXPECT_EQ((*r)->dropped()[0].offset, chunks[3].offset);  // its content fails to decode
    EXPECT_EQ((*r)->dropped()[1].offset, chunks[3].end());   // zeros up to chunk 5
    EXPECT_EQ((*r)->dropped()[1].length, chunks[5].offset - chunks[3].end());
    EXPECT_NE((*r)->dropped()[1].reason.find("resumed at the chunk at byte " +
                                             std::to_string(chunks[5].offset)),
              std::string::npos)
        << (*r)->dropped()[1].reason;
}

TEST(Corruption, ZeroFilledTailAfterPowerCut) {
    std::vector<Msg> sent;
    auto bytes = makeFile("", sent);
    const std::size_t data_end = test::recordsWithOp(bytes, 0x0F).at(0).offset;
    bytes.resize(data_end);
    bytes.resize(data_end + 4096, 0);  // the file's size was committed, its last block was not
    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r);
    EXPECT_TRUE((*r)->truncated());
    EXPECT_EQ(test::readAll(**r), sent);
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_EQ((*r)->dropped()[0].offset, data_end);
    EXPECT_EQ((*r)->dropped()[0].length, 4096u);
    EXPECT_NE((*r)->dropped()[0].reason.find("zero-filled"), std::string::npos);
}

TEST(Corruption, DamagedSummaryFallsBackToScan) {
    std::vector<Msg> sent;
    auto bytes = makeFile("zstd", sent);
    const auto chunk_indexes = test::recordsWithOp(bytes, 0x08);
    ASSERT_EQ(chunk_indexes.size(), 8u);
    bytes[chunk_indexes[3].offset + 12] ^=
        0xFF;  // a chunk's start offset, covered by the summary CRC
    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_FALSE((*r)->indexed());
    EXPECT_FALSE((*r)->truncated());
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_NE((*r)->dropped()[0].reason.find("summary CRC32 mismatch"), std::string::npos)
        << (*r)->dropped()[0].reason;
    EXPECT_EQ(test::readAll(**r), sent);
}

TEST(Corruption, ByteOutsideChunksFailsDataSectionCrc) {
    std::vector<Msg> sent;
    auto bytes = makeFile("zstd", sent);
    const auto indexes =
        test::recordsWithOp(bytes, 0x07);  // Message Index: not covered by chunk CRCs
    ASSERT_FALSE(indexes.empty());
    bytes[indexes[0].offset + 9 + 2 + 4] ^= 0x01;
    auto r = McapReader::fromBuffer(bytes);
    ASSERT_TRUE(r);
    EXPECT_EQ(test::readAll(**r), sent);  // messages are intact
    const Status v = (*r)->verify();
    EXPECT_EQ(v.code(), StatusCode::kChecksumError);
    EXPECT_NE(v.message().find("data section CRC32 mismatch"), std::string::npos) << v.message();
}

TEST(Corruption, IntactFileVerifies) {
    std::vector<Msg> sent;
    auto r = McapReader::fromBuffer(makeFile("zstd", sent));
    ASSERT_TRUE(r);
    const Status v = (*r)->verify();
    EXPECT_TRUE(v) << v.message();
}

TEST(Corruption, NotAnMcapFileIsRefused) {
    auto r = McapReader::fromBuffer(std::vector<std::uint8_t>(100, 0x42), "scan.bin");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::kProtocolError);
    EXPECT_EQ(r.status().message(),
              "scan.bin: not an MCAP file (the first 8 bytes are not the MCAP0 magic)");
}

TEST(Corruption, MissingFileNamesThePath) {
    auto r = McapReader::open("/nonexistent/dir/rec.mcap");
    ASSERT_FALSE(r);
    EXPECT_EQ(r.status().code(), StatusCode::kNotFound);
    EXPECT_NE(r.status().message().find("/nonexistent/dir/rec.mcap"), std::string::npos);
}

}  // namespace
}  // namespace handscan::recording
