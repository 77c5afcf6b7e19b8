// Stress: one writer and several readers hammer the region concurrently; readers check every
// record they accept (all fields derived from one counter) and every map point (append-only
// order). Two variants: separate processes over a named region with the writer restarting once
// (fork), and threads over one mapping (run under ThreadSanitizer by tools/test).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <thread>

#include "stress_workload.hpp"
#include "test_names.hpp"

namespace handscan::shm {
namespace {

using namespace std::chrono_literals;
using stress::ReaderStats;

void expectClean(const ReaderStats& st, const std::string& who) {
    SCOPED_TRACE(who);
    EXPECT_EQ(st.torn, 0u);
    EXPECT_EQ(st.bad_points, 0u);
    EXPECT_EQ(st.bad_answers, 0u);
    EXPECT_GT(st.status_reads, 50u);
    EXPECT_GT(st.pose_reads, 500u);
    EXPECT_GT(st.points_checked, 1000u);
    EXPECT_GE(st.resets, 2u);  // new scans seen while reading
    EXPECT_GT(st.commands_answered, 0u);
    std::printf(
        "%s: status %llu, poses %llu, points %llu, resets %llu, writers %llu, commands %llu/%llu\n",
        who.c_str(), static_cast<unsigned long long>(st.status_reads),
        static_cast<unsigned long long>(st.pose_reads),
        static_cast<unsigned long long>(st.points_checked),
        static_cast<unsigned long long>(st.resets), static_cast<unsigned long long>(st.nonces_seen),
        static_cast<unsigned long long>(st.commands_answered),
        static_cast<unsigned long long>(st.commands_sent));
}

TEST(ShmStress, ForkedWriterRestartsWhileForkedReadersRead) {
    const std::string name = testing::uniqueRegionName("stress");
    constexpr int kReaders = 2;
    int pipes[kReaders][2];
    pid_t readers[kReaders];
    for (int r = 0; r < kReaders; ++r) {
        ASSERT_EQ(::pipe(pipes[r]), 0);
        readers[r] = ::fork();
        ASSERT_GE(readers[r], 0);
        if (readers[r] == 0) {
            ::close(pipes[r][0]);
            ReaderOptions ro;
            ro.name = name;
            ro.recheck_interval_ns = 5 * kNsPerMs;
            LiveMapReader reader(ro);
            const ReaderStats st = stress::runReader(reader, 1800ms);
            const bool ok = ::write(pipes[r][1], &st, sizeof st) == static_cast<ssize_t>(sizeof st);
            ::_exit(ok ? 0 : 3);
        }
        ::close(pipes[r][1]);
    }
    const pid_t writer = ::fork();
    ASSERT_GE(writer, 0);
    if (writer == 0) {
        // Two lifetimes: the second writer replaces the first region under the same name.
        for (int life = 0; life < 2; ++life) {
            WriterOptions wo;
            wo.name = name;
            wo.map_capacity_points = 200000;
            auto w = LiveMapWriter::create(wo);
            if (!w) ::_exit(4);
            stress::runWriter(**w, 600ms, 20000);
            std::this_thread::sleep_for(100ms);  // a gap with no writer at all
        }
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(writer, &status, 0), writer);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    for (int r = 0; r < kReaders; ++r) {
        ReaderStats st;
        const ssize_t got = ::read(pipes[r][0], &st, sizeof st);
        ::close(pipes[r][0]);
        ASSERT_EQ(::waitpid(readers[r], &status, 0), readers[r]);
        EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
        ASSERT_EQ(got, static_cast<ssize_t>(sizeof st));
        expectClean(st, "reader process " + std::to_string(r));
        EXPECT_EQ(st.nonces_seen, 2u);  // followed the restarted writer
    }
    SharedRegion::unlink(name);
}

TEST(ShmStress, WriterCarriesOnWhenAReaderIsKilled) {
    const std::string name = testing::uniqueRegionName("killed");
    WriterOptions wo;
    wo.name = name;
    wo.map_capacity_points = 100000;
    auto writer = LiveMapWriter::create(wo);
    ASSERT_TRUE(writer.isOk());
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        // A UI hammering commands and reads until it is killed, at any instruction.
        ReaderOptions ro;
        ro.name = name;
        LiveMapReader reader(ro);
        MapCursor cursor;
        MapDelta delta;
        for (;;) {
            reader.poll();
            (void)reader.readMap(cursor, delta);
            (void)reader.readStatus();
            (void)reader.sendCommand(CommandType::kStopScan, "from the reader that will be killed");
        }
    }
    const auto writeFor = [&](std::chrono::milliseconds d) {
        std::uint64_t commands = 0;
        const auto end = std::chrono::steady_clock::now() + d;
        std::vector<DisplayPoint> chunk(100);
        PoseRecord pose;
        StatusBlock block;
        while (std::chrono::steady_clock::now() < end) {
            ++pose.t_ns;
            (*writer)->publishPose(pose);
            (*writer)->setStatus(block);
            if (!(*writer)->appendPoints(chunk).isOk()) (*writer)->newScan();
            while (auto cmd = (*writer)->pollCommand()) {
                (*writer)->ack(cmd->seq, CommandState::kDone, "ok");
                ++commands;
            }
        }
        return commands;
    };
    EXPECT_GT(writeFor(300ms), 0u);  // the child's commands arrive
    ASSERT_EQ(::kill(child, SIGKILL), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    writeFor(50ms);  // the writer does not care

    // A new UI still gets its command through, even if the killed one left a slot half-written.
    ReaderOptions ro;
    ro.name = name;
    LiveMapReader fresh(ro);
    ASSERT_EQ(fresh.poll(), Connection::kConnected);
    auto seq = fresh.sendCommand(CommandType::kStartScan);
    ASSERT_TRUE(seq.isOk()) << seq.status().message();
    std::optional<Command> got;
    for (int i = 0; i < 100 && !(got && got->seq == *seq); ++i) got = (*writer)->pollCommand();
    ASSERT_TRUE(got.has_value());
    EXPECT_EQ(got->seq, *seq);
    EXPECT_EQ(got->type, CommandType::kStartScan);
    (*writer)->ack(*seq, CommandState::kDone, "scanning");
    auto r = fresh.commandResult(*seq);
    ASSERT_TRUE(r.isOk());
    EXPECT_EQ(static_cast<CommandState>(r->state), CommandState::kDone);
}

TEST(ShmStress, ThreadsOnOneMapping) {
    // One mapping seen by all threads, so ThreadSanitizer can check every access pair.
    WriterOptions wo;
    wo.map_capacity_points = 100000;
    auto region = SharedRegion::anonymous(regionBytes(wo.map_capacity_points));
    ASSERT_TRUE(region.isOk());
    auto writer = LiveMapWriter::attach(*region, wo);
    ASSERT_TRUE(writer.isOk());
    constexpr int kReaders = 3;
    ReaderStats stats[kReaders];
    std::vector<std::thread> threads;
    for (int r = 0; r < kReaders; ++r) {
        threads.emplace_back([&, r] {
            LiveMapReader reader(*region);
            stats[r] = stress::runReader(reader, 900ms);
        });
    }
    stress::runWriter(**writer, 1000ms, 10000);
    for (auto& t : threads) t.join();
    for (int r = 0; r < kReaders; ++r) {
        expectClean(stats[r], "reader thread " + std::to_string(r));
        // One writer all along: however fast the other UIs send, no answer is lost to slot reuse.
        EXPECT_EQ(stats[r].commands_lost, 0u) << "reader thread " << r;
    }
}

}  // namespace
}  // namespace handscan::shm
