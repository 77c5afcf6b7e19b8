// Bad targets (vanished mid-write, full, read-only, missing) each get a clear error, leave no file
// that looks complete, keep the journal untouched, and a retry works.
#include <gtest/gtest.h>

#include <cerrno>

#include "export_test_support.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_reader.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

// Nothing but finished files (no *.partial) and no cloud file unless complete.
std::vector<std::string> filesIn(const fs::path& dir) {
    std::vector<std::string> out;
    if (!fs::exists(dir)) return out;
    for (const auto& e : fs::recursive_directory_iterator(dir)) {
        if (e.is_regular_file()) out.push_back(e.path().filename().string());
    }
    std::sort(out.begin(), out.end());
    return out;
}

TEST_F(ExportTest, StickPulledMidWriteThenRetry) {
    const std::string journal = makeJournal(300'000);
    const auto before = fs::file_size(journal);
    fs::create_directories(dir_ / "stick");
    ExportOptions opt{{"ply"}, 0.0, "scan", {}, {}, true, ""};
    opt.faults.before_write = [](std::uint64_t written) { return written >= (4u << 20) ? EIO : 0; };
    auto r = exportScan(journal, (dir_ / "stick").string(), opt);
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("Input/output error"), std::string::npos)
        << r.status().message();
    EXPECT_NE(r.status().message().find("stick pulled?"), std::string::npos)
        << r.status().message();
    EXPECT_NE(r.status().message().find("internal storage is untouched"), std::string::npos);
    EXPECT_TRUE(filesIn(dir_ / "stick").empty()) << "a partial file was left behind";
    EXPECT_EQ(fs::file_size(journal), before);
    auto reread = journal::JournalReader::open(journal);
    ASSERT_TRUE(reread.isOk());
    EXPECT_TRUE(reread->summary().damage.empty());
    // Retry with the stick back.
    opt.faults = {};
    auto again = exportScan(journal, (dir_ / "stick").string(), opt);
    ASSERT_TRUE(again.isOk()) << again.status().message();
    EXPECT_EQ(filesIn(dir_ / "stick"),
              (std::vector<std::string>{"cloud.ply", "report.html", "scan.json", "trajectory.csv",
                                        "trajectory.tum"}));
}

TEST_F(ExportTest, TargetDirectoryVanished) {
    const std::string journal = makeJournal(10);
    auto r = exportScan(journal, (dir_ / "not-mounted").string(), {});
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().message(), "export: target " + (dir_ / "not-mounted").string() +
                                        " is not a directory (vanished or not mounted?)");
}

TEST_F(ExportTest, FullTargetRefusedBeforeWriting) {
    const std::string stick = mountTmpfs("1m");
    if (stick.empty()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const std::string journal = makeJournal(100'000);  // ~6 MB of PLY + LAS
    auto r = exportScan(journal, stick, {});
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kNoSpace);
    EXPECT_NE(r.status().message().find("MiB free but the export needs"), std::string::npos)
        << r.status().message();
    EXPECT_TRUE(filesIn(stick).empty());
}

TEST_F(ExportTest, TargetFillsUpDuringWrite) {
    // The free-space estimate passes, but another writer fills the stick: ENOSPC mid-file.
    const std::string stick = mountTmpfs("8m");
    if (stick.empty()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const std::string journal = makeJournal(100'000);
    ExportOptions opt{{"ply", "las"}, 0.0, "scan", {}, {}, true, ""};
    opt.faults.before_write = [&](std::uint64_t written) {
        if (written == 0) {  // first write of a file: fill the stick behind our back
            std::FILE* f = std::fopen((stick + "/other.bin").c_str(), "ab");
            std::vector<char> junk(1 << 20, 'x');
            while (std::fwrite(junk.data(), 1, junk.size(), f) == junk.size()) {
            }
            std::fclose(f);
        }
        return 0;
    };
    auto r = exportScan(journal, stick, opt);
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kNoSpace) << r.status().message();
    EXPECT_NE(r.status().message().find("the target is full"), std::string::npos)
        << r.status().message();
    EXPECT_EQ(filesIn(fs::path(stick) / "scan"), std::vector<std::string>{});
}

TEST_F(ExportTest, ReadOnlyTarget) {
    const std::string stick = mountTmpfs("4m", /*read_only=*/true);
    if (stick.empty()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    const std::string journal = makeJournal(10);
    auto r = exportScan(journal, stick, {});
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("Read-only file system"), std::string::npos)
        << r.status().message();
}

}  // namespace
}  // namespace handscan::exporter::testing
