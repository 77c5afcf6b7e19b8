#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "handscan/journal/journal_reader.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::journal {
namespace {

namespace fs = std::filesystem;

class JournalTest : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("handscan_journal_" + std::to_string(::getpid()) + "_" +
                ::testing::UnitTest::GetInstance()->current_test_info()->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        path_ = (dir_ / "scan.hsj").string();
    }
    void TearDown() override { fs::remove_all(dir_); }

    static std::vector<MapPoint> makePoints(std::size_t first, std::size_t n) {
        std::vector<MapPoint> v;
        for (std::size_t i = first; i < first + n; ++i) {
            v.push_back({static_cast<double>(i) * 1e-3, static_cast<float>(i), 0.f, 1.f, 1, 2, 3,
                         static_cast<std::uint16_t>(i)});
        }
        return v;
    }
    fs::path dir_;
    std::string path_;
};

TEST_F(JournalTest, WriteFinishReadBack) {
    {
        auto w = JournalWriter::create(path_, R"({"device":"test"})");
        ASSERT_TRUE(w.isOk()) << w.status().message();
        for (int c = 0; c < 5; ++c) {
            ASSERT_TRUE((*w)->appendPoints(makePoints(c * 1000, 1000)).isOk());
            ASSERT_TRUE((*w)->appendPose({c * 1.0, 1, 2, 3, 0, 0, 0, 1}).isOk());
            ASSERT_TRUE((*w)->flush().isOk());
        }
        ASSERT_TRUE((*w)->finish().isOk());
    }
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->summary().points, 5000u);
    EXPECT_EQ(r->summary().trajectory.size(), 5u);
    EXPECT_TRUE(r->summary().finished);
    EXPECT_TRUE(r->summary().damage.empty());
    EXPECT_EQ(r->summary().metadata_json, R"({"device":"test"})");
    std::size_t next = 0;
    ASSERT_TRUE(r->forEachPoints([&](std::span<const MapPoint> pts) {
                     for (const MapPoint& p : pts) EXPECT_EQ(p.x, static_cast<float>(next++));
                 }).isOk());
    EXPECT_EQ(next, 5000u);
}

TEST_F(JournalTest, TruncatedAtEveryOffsetKeepsEveryCompleteChunk) {
    std::vector<std::uint64_t> chunk_ends;  // file size after each committed chunk
    {
        auto w = JournalWriter::create(path_, "{}");
        ASSERT_TRUE(w.isOk());
        chunk_ends.push_back(fs::file_size(path_));
        for (int c = 0; c < 4; ++c) {
            ASSERT_TRUE((*w)->appendPoints(makePoints(c * 10, 10)).isOk());
            ASSERT_TRUE((*w)->flush().isOk());
            chunk_ends.push_back(fs::file_size(path_));
        }
    }
    const std::uint64_t full = fs::file_size(path_);
    std::vector<char> bytes(full);
    std::ifstream(path_, std::ios::binary).read(bytes.data(), static_cast<std::streamsize>(full));
    for (std::uint64_t cut = chunk_ends[0]; cut <= full; cut += 7) {
        const std::string p = (dir_ / "cut.hsj").string();
        std::ofstream(p, std::ios::binary | std::ios::trunc)
            .write(bytes.data(), static_cast<std::streamsize>(cut));
        auto r = JournalReader::open(p);
        ASSERT_TRUE(r.isOk()) << "cut " << cut;
        std::size_t complete = 0;
        while (complete + 1 < chunk_ends.size() && chunk_ends[complete + 1] <= cut) ++complete;
        EXPECT_EQ(r->summary().points, complete * 10) << "cut at " << cut;
        EXPECT_EQ(r->summary().damage.empty(), cut == chunk_ends[complete]) << "cut at " << cut;
    }
}

TEST_F(JournalTest, CorruptPayloadStopsAtThatChunkAndRecoveryResumes) {
    {
        auto w = JournalWriter::create(path_, "{}");
        ASSERT_TRUE(w.isOk());
        for (int c = 0; c < 3; ++c) {
            ASSERT_TRUE((*w)->appendPoints(makePoints(c * 100, 100)).isOk());
            ASSERT_TRUE((*w)->flush().isOk());
        }
    }
    // Flip a byte inside the last chunk's payload.
    {
        std::fstream f(path_, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(-10, std::ios::end);
        f.put('\x7f');
    }
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk());
    EXPECT_EQ(r->summary().points, 200u);
    EXPECT_NE(r->summary().damage.find("payload CRC mismatch"), std::string::npos)
        << r->summary().damage;
    // Resume appends after the intact prefix.
    auto w = JournalWriter::resume(path_);
    ASSERT_TRUE(w.isOk()) << w.status().message();
    ASSERT_TRUE((*w)->appendPoints(makePoints(200, 50)).isOk());
    ASSERT_TRUE((*w)->finish().isOk());
    w->reset();
    auto again = JournalReader::open(path_);
    ASSERT_TRUE(again.isOk());
    EXPECT_EQ(again->summary().points, 250u);
    EXPECT_TRUE(again->summary().damage.empty());
    EXPECT_TRUE(again->summary().finished);
}

TEST_F(JournalTest, ReserveReachedStopsCleanly) {
    JournalOptions opts;
    auto w = JournalWriter::create(path_, "{}", opts);
    ASSERT_TRUE(w.isOk());
    const std::uint64_t free_now = (*w)->freeBytes();
    ASSERT_GT(free_now, 0u);
    // A reserve just above what is free: the next chunk must be refused, nothing corrupted.
    w->reset();
    opts.reserve_bytes = free_now + (1ull << 30);
    auto resumed = JournalWriter::resume(path_, opts);
    ASSERT_TRUE(resumed.isOk());
    ASSERT_TRUE((*resumed)->appendPoints(makePoints(0, 10)).isOk());
    const Status s = (*resumed)->flush();
    EXPECT_EQ(s.code(), StatusCode::kNoSpace);
    EXPECT_NE(s.message().find("scan stopped"), std::string::npos) << s.message();
    EXPECT_TRUE((*resumed)->stopped());
    EXPECT_TRUE((*resumed)->lowSpace());
    EXPECT_EQ((*resumed)->appendPoints(makePoints(10, 1)).code(), StatusCode::kNoSpace);
    resumed->reset();
    auto r = JournalReader::open(path_);
    ASSERT_TRUE(r.isOk());
    EXPECT_TRUE(r->summary().damage.empty());
}

TEST_F(JournalTest, MissingAndEmptyFilesGetClearErrors) {
    auto missing = JournalReader::open((dir_ / "none.hsj").string());
    ASSERT_FALSE(missing.isOk());
    EXPECT_NE(missing.status().message().find("cannot open"), std::string::npos);
    std::ofstream((dir_ / "empty.hsj").string()).put('x');
    auto empty = JournalReader::open((dir_ / "empty.hsj").string());
    ASSERT_FALSE(empty.isOk());
    EXPECT_NE(empty.status().message().find("no intact chunk"), std::string::npos)
        << empty.status().message();
}

}  // namespace
}  // namespace handscan::journal
