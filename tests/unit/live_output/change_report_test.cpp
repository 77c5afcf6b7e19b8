// A continued scan's change report on its way to the touch screen: every cell counted, the
// clearest ones carried when there are more than the region holds; published once per match the
// localizer used (not per call, not per sweep), read back by a UI's reader as the localizer has
// it, and emptied by a new scan.
#include "handscan/live_output/change_report.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "handscan/live_output/live_publisher.hpp"
#include "handscan/shm/live_map_reader.hpp"
#include "synthetic_room.hpp"
#include "test_names.hpp"

namespace handscan::live_output {
namespace {

using localize::test::pose;

TEST(ChangeReportTest, CountsEveryCellAndCarriesTheLargestWhenThereAreMore) {
    std::vector<localize::ChangeCell> cells;
    const std::size_t n = shm::kMaxChangeCells + 44;
    for (std::size_t i = 0; i < n; ++i) {
        localize::ChangeCell c;
        c.centre = Eigen::Vector3d(0.25 + 0.5 * static_cast<double>(i), -1.25, 0.75);
        c.kind = i % 3 == 0 ? localize::ChangeKind::kVanished : localize::ChangeKind::kAppeared;
        c.points = 3 + (i * 37) % n;  // every count once, in no order
        cells.push_back(c);
    }
    const shm::ChangeReport r = toChangeReport(cells, 0.5);
    EXPECT_EQ(r.cell_m, 0.5f);
    EXPECT_EQ(r.vanished, (n + 2) / 3);
    EXPECT_EQ(r.appeared + r.vanished, n);
    ASSERT_EQ(r.count, shm::kMaxChangeCells);
    // The largest ones, largest first; each with its own place and kind.
    for (std::size_t k = 0; k < r.count; ++k) {
        const shm::ChangeCellRecord& c = r.cells[k];
        EXPECT_EQ(c.points, 3 + n - 1 - k) << k;
        const auto i = static_cast<std::size_t>(std::lround((c.x_m - 0.25) / 0.5));
        ASSERT_LT(i, n);
        EXPECT_EQ(c.points, cells[i].points);
        EXPECT_EQ(c.y_m, -1.25f);
        EXPECT_EQ(c.z_m, 0.75f);
        EXPECT_EQ(static_cast<shm::ChangeKind>(c.kind),
                  i % 3 == 0 ? shm::ChangeKind::kVanished : shm::ChangeKind::kAppeared);
    }
}

// The localizer test's room with its cabinet moved (localizer_test.cpp): locked from a hint,
// then a tracking match that sees the cabinet's new place and its old one.
class PublishedChanges : public ::testing::Test {
protected:
    void SetUp() override {
        shm::WriterOptions o;
        o.name = shm::testing::uniqueRegionName("changes");
        o.map_capacity_points = 100;
        auto p = LivePublisher::create(o, std::filesystem::temp_directory_path().string());
        ASSERT_TRUE(p.isOk()) << p.status().message();
        publisher_ = std::move(*p);
        reader_ = std::make_unique<shm::LiveMapReader>(publisherRegion(o.name));
        ASSERT_EQ(reader_->poll(), shm::Connection::kConnected) << reader_->message();
        ASSERT_TRUE(reader_->readChanges(cursor_, report_));  // the empty report of a new scan
        ASSERT_EQ(report_.count, 0u);
    }
    static shm::ReaderOptions publisherRegion(const std::string& name) {
        shm::ReaderOptions r;
        r.name = name;
        r.recheck_interval_ns = 0;
        return r;
    }
    void feed(localize::Localizer& l, int n, const Eigen::Isometry3d& T_true,
              const Eigen::Isometry3d& T_odom) {
        const auto f =
            std::make_shared<const scan::FeatureCloud>(localize::test::sweepAt(T_true, moved_));
        for (int i = 0; i < n; ++i, t_ += kNsPerSec / 2) {
            l.addSweep(t_, T_odom, f);
            publisher_->changes(l);  // as the daemon does at each status (10 Hz)
        }
    }
    std::unique_ptr<LivePublisher> publisher_;
    std::unique_ptr<shm::LiveMapReader> reader_;
    shm::ChangesCursor cursor_;
    shm::ChangeReport report_;
    TimeNs t_ = 1000 * kNsPerSec;
    const Eigen::Vector3d moved_{-0.6, -0.5, 0.0};  // the cabinet, 0.78 m
};

TEST_F(PublishedChanges, OncePerUsedMatchAsTheLocalizerHasThemAndEmptiedByANewScan) {
    localize::LocalizerConfig c;
    c.apply = localize::MatchApply::kAtNextSweep;
    auto prior = std::make_shared<const localize::PriorMap>(
        localize::test::roomWorld(0.2, 0.0, Eigen::Vector3d::Zero(),
                                  {{2.5, 2.0, 1.3}, {7.5, 2.0, 1.3}, {3.5, 5.5, 1.3}}),
        pose(5, 3.5, 1.3, 0));
    localize::Localizer l(c, prior, pose(7.3, 3.6, 1.3, -5));
    const Eigen::Isometry3d truth = pose(6.5, 3.0, 1.3, -20);
    feed(l, 4, truth, Eigen::Isometry3d::Identity());
    EXPECT_FALSE(reader_->readChanges(cursor_, report_)) << "published before any match was used";
    feed(l, 2, truth, Eigen::Isometry3d::Identity());
    ASSERT_TRUE(l.locked());
    ASSERT_TRUE(reader_->readChanges(cursor_, report_));  // the lock's report
    const Eigen::Isometry3d east = pose(9.4, 3.5, 1.3, 60);
    feed(l, 4, east, truth.inverse() * east);
    ASSERT_EQ(l.stats().updates, 1u);
    ASSERT_TRUE(reader_->readChanges(cursor_, report_));  // the tracking match's
    EXPECT_FALSE(reader_->readChanges(cursor_, report_)) << "published again without a new match";

    const std::vector<localize::ChangeCell> expected = l.changes();
    std::size_t appeared = 0;
    for (const localize::ChangeCell& e : expected)
        appeared += e.kind == localize::ChangeKind::kAppeared ? 1 : 0;
    ASSERT_GE(appeared, 1u);  // the cabinet's new place and its old one
    ASSERT_GE(expected.size() - appeared, 1u);
    EXPECT_EQ(report_.appeared, appeared);
    EXPECT_EQ(report_.vanished, expected.size() - appeared);
    ASSERT_EQ(report_.count, expected.size());
    EXPECT_EQ(report_.cell_m, static_cast<float>(c.change_cell_m));
    for (const localize::ChangeCell& e : expected) {
        bool found = false;
        for (std::uint32_t k = 0; k < report_.count; ++k) {
            const shm::ChangeCellRecord& g = report_.cells[k];
            found =
                found || ((Eigen::Vector3d(g.x_m, g.y_m, g.z_m) - e.centre).norm() < 1e-5 &&
                          g.points == e.points &&
                          (static_cast<shm::ChangeKind>(g.kind) == shm::ChangeKind::kAppeared) ==
                              (e.kind == localize::ChangeKind::kAppeared));
        }
        EXPECT_TRUE(found) << "cell at " << e.centre.transpose() << " not published";
    }

    publisher_->newScan();
    ASSERT_TRUE(reader_->readChanges(cursor_, report_));
    EXPECT_EQ(report_.count, 0u);
    EXPECT_EQ(report_.appeared + report_.vanished, 0u);
}

}  // namespace
}  // namespace handscan::live_output
