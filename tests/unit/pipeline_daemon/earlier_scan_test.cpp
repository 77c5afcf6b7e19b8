// "Continue scan" on the daemon's side: the command's argument (scan=, pose=, errors naming the
// token), which scan can be continued (one with a journal; the newest), and a continued
// scan's journal naming the scan it continues (ScanSession::continueFrom).
#include "handscan/pipeline_daemon/earlier_scan.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "handscan/core/json.hpp"
#include "handscan/journal/journal_reader.hpp"
#include "handscan/pipeline_daemon/scan_session.hpp"
#include "handscan/prior_map/feature_map_file.hpp"
#include "handscan/shm/text_field.hpp"

namespace handscan::pipeline_daemon {
namespace {

namespace fs = std::filesystem;

TEST(ContinueArgument, ScanAndPoseInAnyOrderOrNeither) {
    auto none = parseContinueArgument("");
    ASSERT_TRUE(none.isOk());
    EXPECT_TRUE(none->scan.empty());
    EXPECT_FALSE(none->initial_pose);
    auto both =
        parseContinueArgument("pose=1,2,1.3,0,0,0.7071068,0.7071068 scan=scan-20261125-010203");
    ASSERT_TRUE(both.isOk()) << both.status().message();
    EXPECT_EQ(both->scan, "scan-20261125-010203");
    ASSERT_TRUE(both->initial_pose);
    EXPECT_TRUE(both->initial_pose->translation().isApprox(Eigen::Vector3d(1, 2, 1.3)));
    const Eigen::Vector3d x = both->initial_pose->linear().col(0);
    EXPECT_NEAR(std::atan2(x.y(), x.x()), M_PI / 2, 1e-6);
}

TEST(ContinueArgument, ErrorsNameWhatIsWrong) {
    auto bad_pose = parseContinueArgument("pose=1,2,3");
    ASSERT_FALSE(bad_pose.isOk());
    EXPECT_NE(bad_pose.status().message().find("7 numbers"), std::string::npos);
    auto escape = parseContinueArgument("scan=../etc");
    ASSERT_FALSE(escape.isOk());
    EXPECT_NE(escape.status().message().find("directory name"), std::string::npos);
    auto unknown = parseContinueArgument("heading=90");
    ASSERT_FALSE(unknown.isOk());
    EXPECT_NE(unknown.status().message().find("'heading=90'"), std::string::npos);
}

TEST(EarlierScan, TheNewestScanWithAJournalIsContinuedAndNamedInTheNewJournal) {
    const fs::path root =
        fs::temp_directory_path() / ("handscan-earlier-" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root / "scan-20261125-010000");
    fs::create_directories(root / "scan-20261125-020000");  // no feature map: still continuable
    fs::create_directories(root / "scan-20261125-030000");  // newest, but no journal
    for (const char* d : {"scan-20261125-010000", "scan-20261125-020000"})
        std::ofstream(root / d / "journal.hsj") << "x";
    std::ofstream(root / "scan-20261125-010000" / prior_map::kFeatureMapFile) << "x";
    auto newest = newestContinuableScan(root.string());
    ASSERT_TRUE(newest.isOk()) << newest.status().message();
    EXPECT_EQ(fs::path(*newest).filename(), "scan-20261125-020000");
    EXPECT_FALSE(canContinue((root / "scan-20261125-030000").string()));
    EXPECT_FALSE(newestContinuableScan((root / "nothing").string()).isOk());

    const fs::path journals = root / "journals";
    ScanSession session(journals.string(), {}, jsonText({{"source", "test"}}));
    auto started = session.continueFrom(*newest);
    ASSERT_TRUE(started.isOk()) << started.status().message();
    EXPECT_NE(started->find("continuing scan-20261125-020000"), std::string::npos) << *started;
    EXPECT_TRUE(session.scanning());
    EXPECT_FALSE(session.continueFrom(*newest).isOk());  // not while scanning
    const std::string path = session.journalPath();
    ASSERT_TRUE(session.finish().isOk());
    auto j = journal::JournalReader::open(path);
    ASSERT_TRUE(j.isOk()) << j.status().message();
    const Json meta = Json::parse(j->summary().metadata_json);
    EXPECT_EQ(meta["prior_map"], *newest);
    EXPECT_EQ(meta["source"], "test");
    fs::remove_all(root);
}

// The touch screen's list of scans to continue: newest first, with their journal's size; the
// daemon's stopped scan marked, its running scan left out; those without a journal left out.
TEST(EarlierScan, ScansToContinueAreListedNewestFirstTheStoppedOneMarked) {
    const fs::path root =
        fs::temp_directory_path() / ("handscan-listed-" + std::to_string(::getpid()));
    fs::remove_all(root);
    for (const char* d : {"scan-20261125-010000", "scan-20261125-020000", "scan-20261125-030000",
                          "scan-20261125-040000"})
        fs::create_directories(root / d);
    std::ofstream(root / "scan-20261125-010000" / "journal.hsj") << "12345";
    std::ofstream(root / "scan-20261125-020000" / "journal.hsj") << "123";
    std::ofstream(root / "scan-20261125-040000" / "journal.hsj") << "1234567";
    // scan-...-030000 has no journal.
    const std::string stopped = (root / "scan-20261125-020000").string();
    shm::ScanList l = continuableScans(root.string(), stopped, /*own_scanning=*/false);
    ASSERT_EQ(l.count, 3u);
    EXPECT_EQ(l.total, 3u);
    EXPECT_EQ(shm::getText(l.scans[0].name), "scan-20261125-040000");
    EXPECT_EQ(shm::getText(l.scans[1].name), "scan-20261125-020000");
    EXPECT_EQ(shm::getText(l.scans[2].name), "scan-20261125-010000");
    EXPECT_EQ(l.scans[0].journal_bytes, 7u);
    EXPECT_EQ(l.scans[2].journal_bytes, 5u);
    EXPECT_GT(l.scans[0].modified_unix_s, 1'700'000'000);
    EXPECT_EQ(l.scans[0].current, 0);
    EXPECT_EQ(l.scans[1].current, 1);
    // While that scan is being made it is not an earlier one.
    l = continuableScans(root.string(), stopped, /*own_scanning=*/true);
    ASSERT_EQ(l.count, 2u);
    EXPECT_EQ(shm::getText(l.scans[1].name), "scan-20261125-010000");
    // More than the list holds: the newest, all counted.
    for (int i = 0; i < static_cast<int>(shm::kMaxListedScans); ++i) {
        const fs::path d = root / ("scan-20261124-" + std::to_string(100000 + i));
        fs::create_directories(d);
        std::ofstream(d / "journal.hsj") << "x";
    }
    l = continuableScans(root.string(), "", false);
    EXPECT_EQ(l.count, shm::kMaxListedScans);
    EXPECT_EQ(l.total, shm::kMaxListedScans + 3);
    EXPECT_EQ(shm::getText(l.scans[0].name), "scan-20261125-040000");
    fs::remove_all(root);
}

}  // namespace
}  // namespace handscan::pipeline_daemon
