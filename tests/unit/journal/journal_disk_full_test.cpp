// Disk full while scanning: on a real, small filesystem the writer warns first (lowSpace), then
// stops cleanly at the reserve with every committed chunk readable; a write that fails half-way
// through a chunk is cut back so the journal ends on a whole chunk.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>

#include "../common/scratch_dir.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::journal {
namespace {

namespace fs = std::filesystem;

class JournalDiskFull : public ::testing::Test {
protected:
    // An 8 MiB tmpfs standing in for the internal storage; empty when mounting is not permitted.
    std::string smallDisk() { return scratch_.mountSmallDisk("8m").string(); }
    static std::vector<MapPoint> batch(std::uint64_t first, std::size_t n) {
        std::vector<MapPoint> v(n);
        for (std::size_t i = 0; i < n; ++i)
            v[i] = {(first + i) * 1e-5, static_cast<float>(first + i), 0, 0, 1, 2, 3, 4};
        return v;
    }
    // Every point is there exactly once, in order: 0, 1, 2, ...
    static void expectIntactPrefix(const std::string& path, std::uint64_t points) {
        auto r = JournalReader::open(path);
        ASSERT_TRUE(r.isOk()) << r.status().message();
        EXPECT_TRUE(r->summary().damage.empty()) << r->summary().damage;
        EXPECT_EQ(r->summary().points, points);
        std::uint64_t next = 0;
        ASSERT_TRUE(r->forEachPoints([&](std::span<const MapPoint> pts) {
                         for (const MapPoint& p : pts) {
                             if (p.x != static_cast<float>(next))
                                 ADD_FAILURE() << "point " << next << " damaged";
                             ++next;
                         }
                     }).isOk());
        EXPECT_EQ(next, points);
    }

    testing::ScratchDir scratch_{"handscan_journal_full_"};
    const fs::path dir_ = scratch_.path();
};

TEST_F(JournalDiskFull, WarnsFirstThenStopsAtTheReserveWithEverythingReadable) {
    const std::string disk = smallDisk();
    if (disk.empty()) GTEST_SKIP() << "mounting a tmpfs is not permitted here";
    JournalOptions opts;
    opts.reserve_bytes = 1u << 20;
    opts.warn_bytes = 2u << 20;
    const std::string path = disk + "/journal.hsj";
    auto w = JournalWriter::create(path, "{}", opts);
    ASSERT_TRUE(w.isOk()) << w.status().message();
    EXPECT_FALSE((*w)->lowSpace());
    int first_warning = -1, stopped_at = -1;
    Status stop;
    std::uint64_t appended = 0;
    for (int i = 0; i < 100 && stopped_at < 0; ++i) {  // 20000 points = 560 kB per chunk
        ASSERT_TRUE((*w)->appendPoints(batch(appended, 20'000)).isOk());
        appended += 20'000;
        stop = (*w)->flush();
        if (!stop.isOk()) stopped_at = i;
        if ((*w)->lowSpace() && first_warning < 0) first_warning = i;
    }
    ASSERT_GE(stopped_at, 0) << "the writer never stopped on an 8 MiB disk";
    EXPECT_EQ(stop.code(), StatusCode::kNoSpace);
    EXPECT_NE(stop.message().find("scan stopped; everything up to chunk"), std::string::npos)
        << stop.message();
    // The UI had at least two chunks' time of warning before the stop.
    ASSERT_GE(first_warning, 0);
    EXPECT_LE(first_warning + 2, stopped_at)
        << "warned at chunk " << first_warning << ", stopped at " << stopped_at;
    EXPECT_TRUE((*w)->stopped());
    EXPECT_EQ((*w)->appendPoints(batch(appended, 1)).code(), StatusCode::kNoSpace);
    // The reserve was kept: the rest of the system can still write.
    EXPECT_GE(fs::space(disk).available, opts.reserve_bytes);
    const std::uint64_t committed = (*w)->committedPoints();
    EXPECT_EQ(committed, static_cast<std::uint64_t>(stopped_at) * 20'000);
    w->reset();  // destruction flushes nothing more: the writer is stopped
    expectIntactPrefix(path, committed);
}

TEST_F(JournalDiskFull, WriteFailingMidChunkLeavesWholeChunksOnly) {
    // RLIMIT_FSIZE makes the kernel cut a write short and then fail it (EFBIG), like a medium that
    // fills up half-way through a chunk. In a child process, so the limit stays there.
    const std::string path = (dir_ / "journal.hsj").string();
    int fds[2];
    ASSERT_EQ(::pipe(fds), 0);
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        ::signal(SIGXFSZ, SIG_IGN);
        JournalOptions opts;
        opts.reserve_bytes = 0;
        auto w = JournalWriter::create(path, "{}", opts);
        if (!w.isOk()) _exit(2);
        const rlimit lim{1'500'000, 1'500'000};  // 2.7 chunks of 560 kB
        if (::setrlimit(RLIMIT_FSIZE, &lim) != 0) _exit(3);
        std::uint64_t appended = 0;
        Status s;
        for (int i = 0; i < 10 && s.isOk(); ++i) {
            if (!(*w)->appendPoints(batch(appended, 20'000)).isOk()) break;
            appended += 20'000;
            s = (*w)->flush();
        }
        const std::uint64_t committed = (*w)->committedPoints();
        const bool ok = !s.isOk() &&
                        s.message().find("write failed at byte") != std::string::npos &&
                        fs::file_size(path) < 1'500'000;
        if (::write(fds[1], &committed, sizeof committed) != sizeof committed) _exit(4);
        _exit(ok ? 0 : 5);
    }
    ::close(fds[1]);
    std::uint64_t committed = 0;
    ASSERT_EQ(::read(fds[0], &committed, sizeof committed), static_cast<ssize_t>(sizeof committed));
    ::close(fds[0]);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    ASSERT_EQ(WEXITSTATUS(status), 0) << "the writer did not stop with a clear write error";
    EXPECT_EQ(committed, 40'000u);  // two whole chunks fit under the limit, the third did not
    expectIntactPrefix(path, committed);
}

}  // namespace
}  // namespace handscan::journal
