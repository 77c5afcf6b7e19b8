// kill -9 the journal writer at random moments; after recovery every chunk it committed is there
// and nothing older than the last second (the flush interval is 0.5 s) is lost.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "handscan/core/time.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::journal {
namespace {

namespace fs = std::filesystem;

// The child appends points stamped with the monotonic clock at ~20 kHz and reports every committed
// point count through the pipe.
[[noreturn]] void writerChild(const std::string& path, int report_fd) {
    JournalOptions opts;
    opts.flush_interval_s = 0.5;
    auto w = JournalWriter::create(path, "{}", opts);
    if (!w.isOk()) _exit(3);
    std::uint64_t i = 0;
    while (true) {
        std::vector<MapPoint> batch;
        for (int k = 0; k < 200; ++k, ++i) {
            batch.push_back({toSeconds(monotonicNow()), static_cast<float>(i), 0, 0, 0, 0, 0, 0});
        }
        if (!(*w)->appendPoints(batch).isOk()) _exit(4);
        const std::uint64_t before = (*w)->committedPoints();
        if (!(*w)->flushIfDue().isOk()) _exit(5);
        if ((*w)->committedPoints() != before) {
            const std::uint64_t c = (*w)->committedPoints();
            if (::write(report_fd, &c, sizeof c) != sizeof c) _exit(6);
        }
        ::usleep(10'000);
    }
}

TEST(JournalCrash, KillNineAtRandomMomentsLosesAtMostTheLastSecond) {
    const fs::path dir =
        fs::temp_directory_path() / ("handscan_journal_crash_" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    std::mt19937 rng(12345);
    std::uniform_int_distribution<int> run_ms(600, 2500);
    for (int round = 0; round < 6; ++round) {
        const std::string path = (dir / ("scan" + std::to_string(round) + ".hsj")).string();
        int fds[2];
        ASSERT_EQ(::pipe(fds), 0);
        const pid_t pid = ::fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            ::close(fds[0]);
            writerChild(path, fds[1]);
        }
        ::close(fds[1]);
        ::usleep(static_cast<useconds_t>(run_ms(rng)) * 1000);
        const double killed_at = toSeconds(monotonicNow());
        ::kill(pid, SIGKILL);
        int status = 0;
        ::waitpid(pid, &status, 0);
        ASSERT_TRUE(WIFSIGNALED(status)) << "writer exited by itself with " << WEXITSTATUS(status);
        std::uint64_t committed = 0, c = 0;
        while (::read(fds[0], &c, sizeof c) == sizeof c) committed = c;
        ::close(fds[0]);

        auto recovered = recoverJournal(path);
        ASSERT_TRUE(recovered.isOk()) << recovered.status().message();
        EXPECT_GE(recovered->points, committed)
            << "round " << round << ": a committed chunk was lost";
        EXPECT_GE(recovered->t_last_s, killed_at - 1.0)
            << "round " << round << ": more than the last second lost";
        // The points are exactly 0..n-1: no hole, no duplicate, no garbage.
        auto reader = JournalReader::open(path);
        ASSERT_TRUE(reader.isOk());
        EXPECT_TRUE(reader->summary().damage.empty()) << reader->summary().damage;
        std::uint64_t next = 0;
        ASSERT_TRUE(reader
                        ->forEachPoints([&](std::span<const MapPoint> pts) {
                            for (const MapPoint& p : pts) {
                                if (p.x != static_cast<float>(next))
                                    ADD_FAILURE() << "point " << next << " damaged";
                                ++next;
                            }
                        })
                        .isOk());
        EXPECT_EQ(next, recovered->points);
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace handscan::journal
