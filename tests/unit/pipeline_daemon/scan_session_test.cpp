// ScanSession: the scan state machine and its journal (idle -> scanning -> stopped -> resumed /
// new scan), what is journaled when, and a full disk refusing a scan with a clear error while
// what was written stays intact.
#include "handscan/pipeline_daemon/scan_session.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "handscan/journal/journal_reader.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

struct TempDir {
    TempDir()
        : path(fs::temp_directory_path() / ("handscan-session-" + std::to_string(::getpid()) + "-" +
                                            std::to_string(counter++))) {
        fs::remove_all(path);
    }
    ~TempDir() { fs::remove_all(path); }
    fs::path path;
    static inline int counter = 0;
};

std::vector<journal::MapPoint> points(int n, double t0) {
    std::vector<journal::MapPoint> v;
    for (int i = 0; i < n; ++i) v.push_back({t0 + i * 1e-4, 1.0f * i, 2.0f, 3.0f, 10, 20, 30, 400});
    return v;
}

journal::JournalSummary summaryOf(const std::string& path) {
    auto j = journal::JournalReader::open(path);
    EXPECT_TRUE(j.isOk()) << j.status().message();
    return j.isOk() ? j->summary() : journal::JournalSummary{};
}

TEST(ScanSession, StartStopResumeNewScan) {
    TempDir dir;
    ScanSession s(dir.path.string());
    EXPECT_EQ(s.stop().status().code(), StatusCode::kInvalidArgument);
    s.appendPoints(points(10, 0.0));  // idle: nothing is journaled
    EXPECT_EQ(s.points(), 0u);

    auto started = s.start();
    ASSERT_TRUE(started.isOk()) << started.status().message();
    EXPECT_EQ(s.state(), shm::ScanState::kScanning);
    const std::string first = s.journalPath();
    EXPECT_TRUE(fs::exists(first));
    EXPECT_EQ(fs::path(first).filename(), "journal.hsj");
    EXPECT_EQ(s.start().status().code(), StatusCode::kInvalidArgument);  // already scanning
    s.appendPoints(points(100, 1.0));
    s.appendPose({1.0, 0, 0, 0, 0, 0, 0, 1});
    ASSERT_TRUE(s.stop().isOk());
    EXPECT_EQ(s.state(), shm::ScanState::kStopped);
    // Stopped = flushed: exportable now, not finished (start resumes it).
    auto sum = summaryOf(first);
    EXPECT_EQ(sum.points, 100u);
    EXPECT_EQ(sum.trajectory.size(), 1u);
    EXPECT_FALSE(sum.finished);
    s.appendPoints(points(5, 2.0));  // stopped: not journaled
    ASSERT_TRUE(s.start().isOk());
    EXPECT_EQ(s.journalPath(), first);
    s.appendPoints(points(50, 3.0));
    EXPECT_EQ(s.newScan().status().code(), StatusCode::kInvalidArgument);  // stop first
    ASSERT_TRUE(s.stop().isOk());
    EXPECT_EQ(s.points(), 150u);

    ASSERT_TRUE(s.newScan().isOk());
    EXPECT_EQ(s.state(), shm::ScanState::kIdle);
    EXPECT_TRUE(s.journalPath().empty());
    sum = summaryOf(first);
    EXPECT_TRUE(sum.finished);
    EXPECT_EQ(sum.points, 150u);
    ASSERT_TRUE(s.start().isOk());
    EXPECT_NE(s.journalPath(), first);
    ASSERT_TRUE(s.finish().isOk());  // shutdown
    EXPECT_TRUE(summaryOf(s.journalPath()).finished);
}

TEST(ScanSession, RecoversTheNewestUnfinishedScanForExport) {
    TempDir dir;
    {
        ScanSession none(dir.path.string());
        auto r = none.recoverUnfinished();  // no journal directory at all yet
        ASSERT_TRUE(r.isOk());
        EXPECT_TRUE(r->empty());
    }
    // An older finished scan and a newer one cut short (the writer never finished it).
    fs::create_directories(dir.path / "scan-20260101-000000");
    fs::create_directories(dir.path / "scan-20260102-000000");
    {
        auto done = journal::JournalWriter::create(
            (dir.path / "scan-20260101-000000/journal.hsj").string(), "{}");
        ASSERT_TRUE(done.isOk());
        ASSERT_TRUE((*done)->appendPoints(points(10, 0.0)).isOk());
        ASSERT_TRUE((*done)->finish().isOk());
        auto cut = journal::JournalWriter::create(
            (dir.path / "scan-20260102-000000/journal.hsj").string(), "{}");
        ASSERT_TRUE(cut.isOk());
        ASSERT_TRUE((*cut)->appendPoints(points(70, 0.0)).isOk());
        ASSERT_TRUE((*cut)->flush().isOk());
    }
    const std::string cut_path = (dir.path / "scan-20260102-000000/journal.hsj").string();
    ScanSession s(dir.path.string());
    auto r = s.recoverUnfinished();
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_NE(r->find("70 points"), std::string::npos) << *r;
    EXPECT_EQ(s.state(), shm::ScanState::kStopped);
    EXPECT_EQ(s.journalPath(), cut_path);
    EXPECT_EQ(s.points(), 70u);
    EXPECT_FALSE(s.canResume());  // its points are in another run's world frame
    // Starting scanning begins a new scan; the recovered one is closed as it was.
    ASSERT_TRUE(s.start().isOk());
    EXPECT_NE(s.journalPath(), cut_path);
    auto recovered = summaryOf(cut_path);
    EXPECT_TRUE(recovered.finished);
    EXPECT_EQ(recovered.points, 70u);
}

TEST(ScanSession, UnwritableJournalDirectoryIsAClearError) {
    ScanSession s("/proc/handscan-no-such-dir");
    auto r = s.start();
    ASSERT_FALSE(r.isOk());
    EXPECT_NE(r.status().message().find("/proc/handscan-no-such-dir"), std::string::npos)
        << r.status().message();
    EXPECT_EQ(s.state(), shm::ScanState::kIdle);
}

TEST(ScanSession, FullDiskRefusesToStartAndLeavesOtherScansIntact) {
    TempDir dir;
    journal::JournalOptions o;
    o.flush_interval_s = 0.0;
    ScanSession s(dir.path.string(), o);
    ASSERT_TRUE(s.start().isOk());
    s.appendPoints(points(100, 0.0));
    s.flushIfDue();
    ASSERT_TRUE(s.scanning());
    const std::string path = s.journalPath();
    // Now the disk "fills": the reserve exceeds whatever is free.
    ScanSession full(dir.path.string(), journal::JournalOptions{0.0, ~0ull >> 2, 0, 1u << 18});
    auto refused = full.start();
    ASSERT_FALSE(refused.isOk());
    EXPECT_EQ(refused.status().code(), StatusCode::kNoSpace) << refused.status().message();
    EXPECT_EQ(full.state(), shm::ScanState::kIdle);
    // The first scan is unaffected.
    ASSERT_TRUE(s.stop().isOk());
    EXPECT_EQ(summaryOf(path).points, 100u);
}

}  // namespace
}  // namespace handscan::pipeline_daemon
