// A recording cut short (power cut, full disk, interrupted copy) reads back every chunk that was
// completely written, whatever the cut: inside the header, a chunk, a message index, Data End,
// the summary or the footer. What was lost is reported with its offset.
#include <gtest/gtest.h>

#include <set>

#include "handscan/recording/mcap_reader.hpp"
#include "handscan/recording/mcap_writer.hpp"
#include "mcap_test_util.hpp"

namespace handscan::recording {
namespace {

using test::Msg;

struct Written {
    std::vector<std::uint8_t> bytes;
    std::vector<Msg> sent;
    std::vector<std::size_t> chunk_end;       // end of each chunk record
    std::vector<std::size_t> chunk_messages;  // messages in the chunks up to and including this one
};

Written writeGroups(const std::string& compression, int groups) {
    McapWriterOptions o;
    o.compression = compression;
    o.chunk_size_bytes = 1u << 30;  // chunks close only at flush(): known boundaries
    o.chunk_duration_ns = 0;
    auto w = McapWriter::inMemory(o);
    Written out;
    const std::vector<std::string> topics = {"/hokuyo/raw", "/xsens/raw", "/gpio/events"};
    for (const auto& t : topics) EXPECT_TRUE((*w)->addChannel(t, "x-test"));
    TimeNs t = kNsPerSec;
    for (int g = 0; g < groups; ++g) {
        const int n = 5 + g % 4;
        for (int i = 0; i < n; ++i, t += 5 * kNsPerMs) {
            const auto ch = static_cast<std::uint16_t>((g + i) % 3);
            std::vector<std::uint8_t> data(20 + 13 * i);
            for (std::size_t k = 0; k < data.size(); ++k)
                data[k] = static_cast<std::uint8_t>(k * 31 + g);
            EXPECT_TRUE((*w)->write(ch, t, data));
            out.sent.push_back({topics[ch], t, data});
        }
        EXPECT_TRUE((*w)->flush());
        out.chunk_messages.push_back(out.sent.size());
    }
    EXPECT_TRUE((*w)->close());
    out.bytes = (*w)->takeBuffer();
    for (const auto& r : test::recordsWithOp(out.bytes, 0x06)) out.chunk_end.push_back(r.end());
    EXPECT_EQ(out.chunk_end.size(), static_cast<std::size_t>(groups));
    return out;
}

// Every cut point of interest: around each top-level record boundary and every 7th byte.
std::set<std::size_t> cutPoints(const std::vector<std::uint8_t>& bytes) {
    std::set<std::size_t> cuts;
    for (std::size_t c = 0; c <= bytes.size(); c += 7) cuts.insert(c);
    for (const auto& r : test::topLevelRecords(bytes)) {
        for (std::size_t d : {r.offset, r.offset + 1, r.offset + 9, r.offset + 10, r.end() - 1})
            cuts.insert(d);
    }
    cuts.insert(bytes.size() - 1);
    cuts.insert(bytes.size());
    return cuts;
}

class Truncation : public ::testing::TestWithParam<std::string> {};

TEST_P(Truncation, EveryCompleteChunkReadsBackAtAnyCut) {
    const Written w = writeGroups(GetParam(), 12);
    const auto records = test::topLevelRecords(w.bytes);
    const std::size_t header_end = records.front().end();
    const std::size_t first_chunk = test::recordsWithOp(w.bytes, 0x06).front().offset;
    int checked = 0;
    for (std::size_t cut : cutPoints(w.bytes)) {
        SCOPED_TRACE("cut at byte " + std::to_string(cut) + " of " +
                     std::to_string(w.bytes.size()));
        std::vector<std::uint8_t> part(w.bytes.begin(),
                                       w.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
        auto r = McapReader::fromBuffer(part);
        if (cut < header_end) {
            ASSERT_FALSE(r);  // nothing was recorded yet
            continue;
        }
        ASSERT_TRUE(r) << r.status().message();
        std::size_t complete = 0;
        while (complete < w.chunk_end.size() && w.chunk_end[complete] <= cut) ++complete;
        const std::size_t n = complete == 0 ? 0 : w.chunk_messages[complete - 1];
        const auto got = test::readAll(**r);
        ASSERT_EQ(got.size(), n);
        ASSERT_TRUE(std::equal(got.begin(), got.end(), w.sent.begin()));
        EXPECT_EQ((*r)->truncated(), cut != w.bytes.size());
        // A cut inside a chunk is reported at that chunk's offset; nothing else goes missing.
        if (complete < w.chunk_end.size() && cut > first_chunk) {
            const std::size_t chunk_start =
                complete == 0 ? first_chunk : test::recordsWithOp(w.bytes, 0x06)[complete].offset;
            if (cut > chunk_start) {
                ASSERT_FALSE((*r)->dropped().empty());
                EXPECT_EQ((*r)->dropped().back().offset, chunk_start);
                EXPECT_EQ((*r)->dropped().back().length, cut - chunk_start);
                EXPECT_NE((*r)->dropped().back().reason.find("cut short"), std::string::npos);
            }
        }
        ++checked;
    }
    EXPECT_GT(checked, 300);
}

INSTANTIATE_TEST_SUITE_P(Compressions, Truncation,
                         ::testing::Values(std::string(""), std::string("zstd")));

TEST(Truncation, CutInsideSummaryKeepsEveryMessage) {
    const Written w = writeGroups("zstd", 6);
    const auto data_end = test::recordsWithOp(w.bytes, 0x0F).front();
    for (std::size_t cut = data_end.end(); cut < w.bytes.size(); ++cut) {
        std::vector<std::uint8_t> part(w.bytes.begin(),
                                       w.bytes.begin() + static_cast<std::ptrdiff_t>(cut));
        auto r = McapReader::fromBuffer(part);
        ASSERT_TRUE(r);
        EXPECT_TRUE((*r)->truncated());
        EXPECT_FALSE((*r)->indexed());
        EXPECT_TRUE((*r)->dropped().empty())
            << "cut " << cut << ": " << (*r)->dropped().front().reason;
        ASSERT_EQ(test::readAll(**r), w.sent) << "cut " << cut;
    }
}

TEST(Truncation, RealFileCutShortOnDisk) {
    const std::string path = ::testing::TempDir() + "/truncated.mcap";
    const Written w = writeGroups("zstd", 4);
    const std::size_t cut =
        (w.chunk_end[2] + w.chunk_end[3]) / 2;  // power cut while writing chunk 3
    {
        std::FILE* f = std::fopen(path.c_str(), "wb");
        ASSERT_NE(f, nullptr);
        ASSERT_EQ(std::fwrite(w.bytes.data(), 1, cut, f), cut);
        std::fclose(f);
    }
    auto r = McapReader::open(path);
    ASSERT_TRUE(r) << r.status().message();
    EXPECT_TRUE((*r)->truncated());
    EXPECT_EQ(test::readAll(**r).size(), w.chunk_messages[2]);
    ASSERT_EQ((*r)->dropped().size(), 1u);
    EXPECT_EQ((*r)->dropped()[0].reason.rfind(path + ": Chunk record at byte ", 0), 0u)
        << (*r)->dropped()[0].reason;
    std::remove(path.c_str());
}

}  // namespace
}  // namespace handscan::recording
