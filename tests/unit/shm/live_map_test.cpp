// Functional tests of the live-map region: what the writer publishes is what readers get, the map
// is append-only per epoch, commands go round trip, and readers follow writers that come and go.
#include <gtest/gtest.h>

#include <cmath>
#include <thread>

#include "handscan/shm/display_voxel_filter.hpp"
#include "handscan/shm/live_map_reader.hpp"
#include "handscan/shm/live_map_writer.hpp"
#include "handscan/shm/seqlock.hpp"
#include "handscan/shm/text_field.hpp"
#include "test_names.hpp"

namespace handscan::shm {
namespace {

using testing::uniqueRegionName;

WriterOptions smallWriter(const std::string& name, std::size_t capacity = 1000) {
    WriterOptions o;
    o.name = name;
    o.map_capacity_points = capacity;
    return o;
}

ReaderOptions fastReader(const std::string& name) {
    ReaderOptions o;
    o.name = name;
    o.recheck_interval_ns = 0;  // look for a replaced region on every poll
    return o;
}

// A writer on an anonymous mapping, for readers in this process (ThreadSanitizer sees both sides).
struct InProcessMap {
    std::shared_ptr<SharedRegion> region;
    std::unique_ptr<LiveMapWriter> writer;

    void start(const WriterOptions& o) {
        auto r = SharedRegion::anonymous(regionBytes(o.map_capacity_points));
        ASSERT_TRUE(r.isOk()) << r.status().message();
        region = *r;
        auto w = LiveMapWriter::attach(region, o);
        ASSERT_TRUE(w.isOk()) << w.status().message();
        writer = std::move(*w);
    }
    void start(std::size_t capacity) {
        WriterOptions o;
        o.map_capacity_points = capacity;
        start(o);
    }
};

std::vector<DisplayPoint> pointsFrom(int first, int n) {
    std::vector<DisplayPoint> v;
    for (int i = first; i < first + n; ++i) {
        DisplayPoint p;
        p.x_m = static_cast<float>(i);
        p.r = static_cast<std::uint8_t>(i);
        v.push_back(p);
    }
    return v;
}

TEST(TextField, TruncatesAndTerminates) {
    char f[8];
    setText(f, "abcdefghijk");
    EXPECT_EQ(getText(f), "abcdefg");
    setText(f, "ab");
    EXPECT_EQ(getText(f), "ab");
    char raw[4] = {'w', 'x', 'y', 'z'};  // a writer that forgot the NUL cannot make us overread
    EXPECT_EQ(getText(raw), "wxyz");
}

TEST(SharedRegion, RejectsBadNames) {
    EXPECT_FALSE(SharedRegion::create("no-slash", 4096).isOk());
    EXPECT_FALSE(SharedRegion::create("/a/b", 4096).isOk());
    auto r = SharedRegion::open("/handscan-test-does-not-exist");
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().code(), StatusCode::kNotFound);
}

TEST(LiveMap, ReaderWaitsUntilWriterAppears) {
    const std::string name = uniqueRegionName("wait");
    LiveMapReader reader(fastReader(name));
    EXPECT_EQ(reader.poll(), Connection::kWaiting);
    EXPECT_NE(reader.message().find("waiting for pipeline"), std::string::npos);
    EXPECT_FALSE(reader.readStatus().has_value());
    auto writer = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(writer.isOk()) << writer.status().message();
    EXPECT_EQ(reader.poll(), Connection::kConnected);
    EXPECT_EQ(reader.writerNonce(), (*writer)->nonce());
}

TEST(LiveMap, StatusRoundTrip) {
    const std::string name = uniqueRegionName("status");
    auto writer = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(writer.isOk());
    StatusBlock s;
    s.sensor_count = 2;
    setText(s.sensors[0].name, "hokuyo");
    s.sensors[0].connected = 1;
    s.sensors[0].rate_hz = 40.0f;
    setText(s.sensors[1].name, "xsens");
    setText(s.sensors[1].last_error, "/dev/ttyUSB0: no data for 2 s: check the cable");
    s.module_count = 1;
    setText(s.modules[0].name, "scan-match");
    s.modules[0].degenerate_dof_mask = 0b101000;
    s.scan_state = static_cast<std::uint8_t>(ScanState::kScanning);
    s.elapsed_s = 12.5;
    s.distance_m = 7.25;
    s.point_count = 123456;
    s.free_storage_bytes = 1ull << 34;
    (*writer)->setStatus(s);

    LiveMapReader reader(fastReader(name));
    ASSERT_EQ(reader.poll(), Connection::kConnected);
    auto got = reader.readStatus();
    ASSERT_TRUE(got.has_value());
    EXPECT_EQ(got->sensor_count, 2u);
    EXPECT_EQ(getText(got->sensors[0].name), "hokuyo");
    EXPECT_EQ(got->sensors[0].rate_hz, 40.0f);
    EXPECT_EQ(getText(got->sensors[1].last_error),
              "/dev/ttyUSB0: no data for 2 s: check the cable");
    EXPECT_EQ(got->modules[0].degenerate_dof_mask, 0b101000);
    EXPECT_EQ(static_cast<ScanState>(got->scan_state), ScanState::kScanning);
    EXPECT_EQ(got->elapsed_s, 12.5);
    EXPECT_EQ(got->point_count, 123456u);
    EXPECT_EQ(got->free_storage_bytes, 1ull << 34);
}

TEST(LiveMap, PoseRingKeepsLatestAndSkipsOverwritten) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(16));
    LiveMapReader reader(m.region);
    EXPECT_FALSE(reader.latestPose().has_value());

    PoseEstimate e;
    e.t_host = 5;
    e.T_world_body.translation() = Eigen::Vector3d(1, 2, 3);
    e.T_world_body.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    e.source = PoseSource::kVisualOdometry;
    e.solved_dof_mask = 0b000111;
    m.writer->publishPose(e);
    auto latest = reader.latestPose();
    ASSERT_TRUE(latest.has_value());
    EXPECT_EQ(latest->t_ns, 5);
    EXPECT_DOUBLE_EQ(latest->position_m[1], 2.0);
    EXPECT_NEAR(latest->orientation_xyzw[2], std::sin(0.25), 1e-12);
    EXPECT_EQ(latest->vio_dof_mask, 0b000111);  // VIO-solved DOF are green in Figure 14
    EXPECT_EQ(latest->scan_dof_mask, 0);

    const std::uint64_t total = kPoseRingCapacity * 2 + 10;
    for (std::uint64_t i = 1; i < total; ++i) {
        PoseRecord p;
        p.t_ns = static_cast<std::int64_t>(i) + 5;
        m.writer->publishPose(p);
    }
    std::uint64_t next = 0;
    std::vector<PoseRecord> got;
    reader.readPoses(next, got);
    EXPECT_EQ(next, total);
    ASSERT_FALSE(got.empty());
    EXPECT_LE(got.size(), kPoseRingCapacity);
    EXPECT_GE(got.size(), kPoseRingCapacity - 8);
    EXPECT_EQ(got.back().t_ns, static_cast<std::int64_t>(total - 1 + 5));
    for (std::size_t i = 1; i < got.size(); ++i) EXPECT_EQ(got[i].t_ns, got[i - 1].t_ns + 1);
    got.clear();
    reader.readPoses(next, got);
    EXPECT_TRUE(got.empty());
}

TEST(LiveMap, MapIsAppendOnlyPerEpochAndResetsOnNewScan) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(100));
    LiveMapReader reader(m.region);
    MapCursor cursor;
    MapDelta delta;

    ASSERT_TRUE(m.writer->appendPoints(pointsFrom(0, 30)).isOk());
    ASSERT_TRUE(reader.readMap(cursor, delta, 20));
    EXPECT_TRUE(delta.reset);  // first read of a writer
    ASSERT_EQ(delta.points.size(), 20u);
    EXPECT_EQ(delta.points[19].x_m, 19.0f);
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_FALSE(delta.reset);
    ASSERT_EQ(delta.points.size(), 10u);
    EXPECT_EQ(delta.points[0].x_m, 20.0f);
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_TRUE(delta.points.empty());

    // Capacity: the overflow is reported, what fits is kept.
    Status s = m.writer->appendPoints(pointsFrom(30, 80));
    EXPECT_EQ(s.code(), StatusCode::kNoSpace);
    EXPECT_NE(s.message().find("10 points not shown"), std::string::npos) << s.message();
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_EQ(delta.points.size(), 70u);
    EXPECT_EQ(cursor.points, 100u);

    const std::uint64_t epoch = m.writer->epoch();
    m.writer->newScan();
    EXPECT_EQ(m.writer->epoch(), epoch + 1);
    ASSERT_TRUE(m.writer->appendPoints(pointsFrom(500, 3)).isOk());
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_TRUE(delta.reset);
    EXPECT_EQ(delta.epoch, epoch + 1);
    ASSERT_EQ(delta.points.size(), 3u);
    EXPECT_EQ(delta.points[0].x_m, 500.0f);
}

// A continued scan's change cells: what the writer publishes is what a reader gets, once per
// publication; the count is capped at kMaxChangeCells; a new scan empties the report; a reader
// of a replaced writer reads the new writer's report even where the counters coincide.
TEST(LiveMap, ChangeReportRoundTripOncePerPublicationAndEmptiedByANewScan) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(100));
    LiveMapReader reader(m.region);
    ChangesCursor cursor;
    ChangeReport got;
    ASSERT_TRUE(reader.readChanges(cursor, got));  // the writer's empty report
    EXPECT_EQ(got.count, 0u);
    EXPECT_FALSE(reader.readChanges(cursor, got));  // nothing new

    ChangeReport r;
    r.cell_m = 0.5f;
    r.appeared = 1;
    r.vanished = 300;
    r.count = kMaxChangeCells + 5;  // more than there is room for: only the room is taken
    for (std::size_t i = 0; i < kMaxChangeCells; ++i) {
        r.cells[i] = {
            static_cast<float>(i) + 0.25f, -2.5f, 1.75f, static_cast<std::uint32_t>(i),
            static_cast<std::uint8_t>(i == 0 ? ChangeKind::kAppeared : ChangeKind::kVanished)};
    }
    m.writer->setChanges(r);
    ASSERT_TRUE(reader.readChanges(cursor, got));
    EXPECT_EQ(got.epoch, m.writer->epoch());
    EXPECT_GT(got.t_ns, 0);
    EXPECT_EQ(got.cell_m, 0.5f);
    EXPECT_EQ(got.appeared, 1u);
    EXPECT_EQ(got.vanished, 300u);
    ASSERT_EQ(got.count, kMaxChangeCells);
    EXPECT_EQ(static_cast<ChangeKind>(got.cells[0].kind), ChangeKind::kAppeared);
    EXPECT_EQ(got.cells[0].x_m, 0.25f);
    const ChangeCellRecord& last = got.cells[kMaxChangeCells - 1];
    EXPECT_EQ(static_cast<ChangeKind>(last.kind), ChangeKind::kVanished);
    EXPECT_EQ(last.x_m, static_cast<float>(kMaxChangeCells - 1) + 0.25f);
    EXPECT_EQ(last.y_m, -2.5f);
    EXPECT_EQ(last.z_m, 1.75f);
    EXPECT_EQ(last.points, kMaxChangeCells - 1);
    EXPECT_FALSE(reader.readChanges(cursor, got));

    // A new scan: an empty report of the new epoch.
    m.writer->newScan();
    ASSERT_TRUE(reader.readChanges(cursor, got));
    EXPECT_EQ(got.epoch, m.writer->epoch());
    EXPECT_EQ(got.count, 0u);
    EXPECT_EQ(got.appeared + got.vanished, 0u);

    // A writer re-attached to the region (a restarted pipeline): its first report is read even
    // though the cursor's counter may equal the new one.
    r.count = 1;
    r.cells[0].x_m = 42.0f;
    m.writer->setChanges(r);
    ASSERT_TRUE(reader.readChanges(cursor, got));
    const ChangesCursor before = cursor;
    m.writer.reset();
    auto again = LiveMapWriter::attach(m.region, smallWriter("", 100));
    ASSERT_TRUE(again.isOk());
    ASSERT_TRUE(reader.readChanges(cursor, got));
    EXPECT_NE(cursor.nonce, before.nonce);
    EXPECT_EQ(got.count, 0u);
}

// The scans a UI offers to continue: as the writer lists them, at most kMaxListedScans.
TEST(LiveMap, ScanListRoundTrip) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(100));
    LiveMapReader reader(m.region);
    ASSERT_TRUE(reader.readScanList().has_value());
    EXPECT_EQ(reader.readScanList()->count, 0u);
    ScanList l;
    l.count = kMaxListedScans + 3;
    l.total = kMaxListedScans + 3;
    for (std::size_t i = 0; i < kMaxListedScans; ++i) {
        setText(l.scans[i].name,
                "scan-2026112" + std::to_string(i % 10) + "-1000" + std::to_string(i % 10));
        l.scans[i].modified_unix_s = 1'790'000'000 + static_cast<std::int64_t>(i);
        l.scans[i].journal_bytes = 1000 * i;
    }
    l.scans[0].current = 1;
    m.writer->setScanList(l);
    const auto got = reader.readScanList();
    ASSERT_TRUE(got.has_value());
    ASSERT_EQ(got->count, kMaxListedScans);
    EXPECT_EQ(got->total, kMaxListedScans + 3);
    EXPECT_EQ(getText(got->scans[3].name), "scan-20261123-10003");
    EXPECT_EQ(got->scans[3].modified_unix_s, 1'790'000'003);
    EXPECT_EQ(got->scans[3].journal_bytes, 3000u);
    EXPECT_EQ(got->scans[0].current, 1);
    EXPECT_EQ(got->scans[1].current, 0);
}

TEST(LiveMap, TrackIsDecimatedByDistance) {
    WriterOptions o;
    o.map_capacity_points = 1;
    o.track_min_step_m = 0.1;
    o.track_max_interval_s = 100;
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(o));
    for (int i = 0; i < 200; ++i) {  // 1 cm steps at 200 Hz: 2 m
        PoseRecord p;
        p.t_ns = i * 5 * kNsPerMs;
        p.position_m[0] = 0.01 * i;
        m.writer->publishPose(p);
    }
    LiveMapReader reader(m.region);
    MapCursor cursor;
    MapDelta delta;
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_GE(delta.track.size(), 19u);
    EXPECT_LE(delta.track.size(), 21u);
    EXPECT_NEAR(delta.track.back().x_m, 1.9f, 0.11f);
}

TEST(LiveMap, CommandsRoundTripInOrder) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(1));
    LiveMapReader ui1(m.region);
    LiveMapReader ui2(m.region);
    auto a = ui1.sendCommand(CommandType::kStartScan);
    auto b = ui2.sendCommand(CommandType::kExport, "/media/usb0");
    ASSERT_TRUE(a.isOk() && b.isOk());
    EXPECT_LT(*a, *b);
    auto ra = ui1.commandResult(*a);
    ASSERT_TRUE(ra.isOk());
    EXPECT_EQ(static_cast<CommandState>(ra->state), CommandState::kPending);

    auto c1 = m.writer->pollCommand();
    ASSERT_TRUE(c1.has_value());
    EXPECT_EQ(c1->seq, *a);
    EXPECT_EQ(c1->type, CommandType::kStartScan);
    auto c2 = m.writer->pollCommand();
    ASSERT_TRUE(c2.has_value());
    EXPECT_EQ(c2->type, CommandType::kExport);
    EXPECT_EQ(c2->argument, "/media/usb0");
    EXPECT_FALSE(m.writer->pollCommand().has_value());  // each command is taken once

    m.writer->ack(c2->seq, CommandState::kInProgress, "writing scan.ply", 0.25f);
    auto rb = ui2.commandResult(*b);
    ASSERT_TRUE(rb.isOk());
    EXPECT_EQ(static_cast<CommandState>(rb->state), CommandState::kInProgress);
    EXPECT_FLOAT_EQ(rb->progress, 0.25f);
    m.writer->ack(c2->seq, CommandState::kDone, "safe to remove");
    rb = ui2.commandResult(*b);
    ASSERT_TRUE(rb.isOk());
    EXPECT_EQ(static_cast<CommandState>(rb->state), CommandState::kDone);
    EXPECT_EQ(getText(rb->message), "safe to remove");
    m.writer->ack(c1->seq, CommandState::kRejected, "already scanning");
    EXPECT_EQ(static_cast<CommandState>(ui1.commandResult(*a)->state), CommandState::kRejected);
}

TEST(LiveMap, AnswerNotYetReadSurvivesOtherUisTraffic) {
    // A UI that looks at its answer only at its next frame must still find it, even when another
    // UI sent more commands than there are slots in the meantime.
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(1));
    LiveMapReader slow(m.region);
    LiveMapReader busy(m.region);
    const auto answerAll = [&] {
        while (auto c = m.writer->pollCommand())
            m.writer->ack(c->seq, CommandState::kDone, "ack " + c->argument);
    };
    auto mine = slow.sendCommand(CommandType::kExport, "/media/slow");
    ASSERT_TRUE(mine.isOk());
    answerAll();
    for (std::size_t i = 0; i < 3 * kCommandSlots; ++i) {
        auto seq = busy.sendCommand(CommandType::kStopScan, std::to_string(i));
        ASSERT_TRUE(seq.isOk()) << seq.status().message();
        answerAll();
        auto r = busy.commandResult(*seq);
        ASSERT_TRUE(r.isOk()) << r.status().message();
        EXPECT_EQ(getText(r->message), "ack " + std::to_string(i));
    }
    auto r = slow.commandResult(*mine);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(static_cast<CommandState>(r->state), CommandState::kDone);
    EXPECT_EQ(getText(r->message), "ack /media/slow");
}

TEST(LiveMap, EverySlotAwaitingAnAnswerMakesSendFailClearly) {
    // A pipeline that takes no commands: the 17th request finds no free slot and says why,
    // instead of silently overwriting an earlier request.
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(1));
    LiveMapReader ui(m.region);
    for (std::size_t i = 0; i < kCommandSlots; ++i)
        ASSERT_TRUE(ui.sendCommand(CommandType::kStopScan).isOk());
    auto extra = ui.sendCommand(CommandType::kStopScan);
    ASSERT_FALSE(extra.isOk());
    EXPECT_EQ(extra.status().code(), StatusCode::kTimeout);
    EXPECT_NE(extra.status().message().find("every command slot is busy"), std::string::npos);
    std::size_t taken = 0;
    while (m.writer->pollCommand()) ++taken;
    EXPECT_EQ(taken, kCommandSlots);  // none of the 16 was overwritten
}

TEST(LiveMap, CommandSlotHeldByCrashedUiIsSkipped) {
    InProcessMap m;
    ASSERT_NO_FATAL_FAILURE(m.start(1));
    auto* h = reinterpret_cast<RegionHeader*>(m.region->data());
    // A UI died between claiming slot 1 and finishing its request: the lock stays odd forever.
    h->next_command_seq = 0;
    h->commands[1].request_lock = 1;
    LiveMapReader ui(m.region);
    auto seq = ui.sendCommand(CommandType::kStopScan);
    ASSERT_TRUE(seq.isOk());
    EXPECT_EQ(*seq, 2u);  // slot 1 skipped
    auto cmd = m.writer->pollCommand();
    ASSERT_TRUE(cmd.has_value());
    EXPECT_EQ(cmd->type, CommandType::kStopScan);
}

TEST(LiveMap, ReaderFollowsWriterRestart) {
    const std::string name = uniqueRegionName("restart");
    LiveMapReader reader(fastReader(name));
    MapCursor cursor;
    MapDelta delta;
    std::uint64_t first_nonce = 0;
    {
        auto w1 = LiveMapWriter::create(smallWriter(name));
        ASSERT_TRUE(w1.isOk());
        ASSERT_TRUE((*w1)->appendPoints(pointsFrom(0, 10)).isOk());
        ASSERT_EQ(reader.poll(), Connection::kConnected);
        first_nonce = reader.writerNonce();
        ASSERT_TRUE(reader.readMap(cursor, delta));
        EXPECT_EQ(delta.points.size(), 10u);
        auto seq = reader.sendCommand(CommandType::kStartScan);
        ASSERT_TRUE(seq.isOk());
    }
    // The writer went away cleanly: the reader says so and keeps the last map readable.
    EXPECT_EQ(reader.poll(), Connection::kClosed);
    EXPECT_NE(reader.message().find("pipeline stopped"), std::string::npos);
    EXPECT_FALSE(reader.sendCommand(CommandType::kStopScan).isOk());

    auto w2 = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(w2.isOk());
    ASSERT_TRUE((*w2)->appendPoints(pointsFrom(100, 4)).isOk());
    EXPECT_EQ(reader.poll(), Connection::kConnected);
    EXPECT_NE(reader.writerNonce(), first_nonce);
    ASSERT_TRUE(reader.readMap(cursor, delta));
    EXPECT_TRUE(delta.reset);
    ASSERT_EQ(delta.points.size(), 4u);
    EXPECT_EQ(delta.points[0].x_m, 100.0f);
    // The new writer did not inherit the old writer's command.
    EXPECT_FALSE((*w2)->pollCommand().has_value());
}

TEST(LiveMap, WriterReplacedWithoutClosingIsFollowed) {
    // A crashed writer never marks the region closed; its successor replaces the object.
    const std::string name = uniqueRegionName("crash");
    WriterOptions o = smallWriter(name);
    o.unlink_on_close = false;
    auto w1 = LiveMapWriter::create(o);
    ASSERT_TRUE(w1.isOk());
    LiveMapReader reader(fastReader(name));
    ASSERT_EQ(reader.poll(), Connection::kConnected);
    const auto nonce1 = reader.writerNonce();
    auto w2 = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(w2.isOk());
    EXPECT_EQ(reader.poll(), Connection::kConnected);
    EXPECT_EQ(reader.writerNonce(), (*w2)->nonce());
    EXPECT_NE(reader.writerNonce(), nonce1);
}

TEST(LiveMap, SilentWriterIsReportedStale) {
    const std::string name = uniqueRegionName("stale");
    auto w = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(w.isOk());
    ReaderOptions ro = fastReader(name);
    ro.stale_after_ns = 30 * kNsPerMs;
    LiveMapReader reader(ro);
    EXPECT_EQ(reader.poll(), Connection::kConnected);
    std::this_thread::sleep_for(std::chrono::milliseconds(60));
    EXPECT_EQ(reader.poll(), Connection::kStale);
    EXPECT_NE(reader.message().find("not responding"), std::string::npos);
    (*w)->heartbeat();
    EXPECT_EQ(reader.poll(), Connection::kConnected);
}

TEST(LiveMap, OtherLayoutVersionIsRejectedWithReason) {
    const std::string name = uniqueRegionName("version");
    auto w = LiveMapWriter::create(smallWriter(name));
    ASSERT_TRUE(w.isOk());
    auto raw = SharedRegion::open(name);
    ASSERT_TRUE(raw.isOk());
    reinterpret_cast<RegionHeader*>((*raw)->data())->version = kLayoutVersion + 1;
    LiveMapReader reader(fastReader(name));
    EXPECT_EQ(reader.poll(), Connection::kIncompatible);
    EXPECT_NE(reader.message().find("layout version " + std::to_string(kLayoutVersion + 1)),
              std::string::npos)
        << reader.message();
}

}  // namespace
}  // namespace handscan::shm

namespace handscan::shm {
namespace {

TEST(DisplayVoxelFilter, KeepsTheFirstPointOfEachNewVoxel) {
    DisplayVoxelFilter f(0.1f);
    const std::vector<DisplayPoint> a = {
        {0.01f, 0.01f, 0.01f, 1, 0, 0, 0},
        {0.05f, 0.09f, 0.02f, 2, 0, 0, 0},  // same voxel as the first
        {0.15f, 0.0f, 0.0f, 3, 0, 0, 0},
        {-0.05f, 0.0f, 0.0f, 4, 0, 0, 0},  // negative side: another voxel
        {std::nanf(""), 0.0f, 0.0f, 5, 0, 0, 0}};
    const auto fresh = f.add(a);
    ASSERT_EQ(fresh.size(), 3u);
    EXPECT_EQ(fresh[0].r, 1);
    EXPECT_EQ(fresh[1].r, 3);
    EXPECT_EQ(fresh[2].r, 4);
    // A later sweep over the same surfaces adds only what is new.
    const std::vector<DisplayPoint> b = {{0.02f, 0.03f, 0.04f, 6, 0, 0, 0},
                                         {0.35f, 0.0f, 0.0f, 7, 0, 0, 0}};
    const auto more = f.add(b);
    ASSERT_EQ(more.size(), 1u);
    EXPECT_EQ(more[0].r, 7);
    EXPECT_EQ(f.voxelCount(), 4u);
    f.clear();
    EXPECT_EQ(f.add(b).size(), 2u);
}

TEST(LiveMap, AnIntegratedPoseCarriesTheScanAndCameraColumns) {
    PoseEstimate p;
    p.source = PoseSource::kIntegrated;
    p.solved_dof_mask = 0x3F & ~0x20;         // the laser: a corridor's axis (z translation) open
    p.visual_solved_dof_mask = 0x3F & ~0x04;  // the camera: yaw open
    const PoseRecord r = toPoseRecord(p);
    EXPECT_EQ(r.scan_dof_mask, 0x1F);
    EXPECT_EQ(r.vio_dof_mask, 0x3B);
    p.source = PoseSource::kImuPrediction;  // before the first match: nothing solved
    EXPECT_EQ(toPoseRecord(p).vio_dof_mask, 0);
}

}  // namespace
}  // namespace handscan::shm
