// handscan merge: two journaled sessions in one frame as one PLY with a session property and
// one LAS with the session as point source ID; the overlap's point-to-plane consistency.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "handscan/core/json.hpp"
#include "handscan/journal/journal_writer.hpp"
#include "handscan/merge/overlap_consistency.hpp"
#include "handscan/merge/session_merge.hpp"

namespace handscan::merge {
namespace {

namespace fs = std::filesystem;

std::vector<std::uint8_t> readAll(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// A floor patch 4 x 4 m (one point per 2 cm) at height z, as one session's journal.
void writeSession(const fs::path& dir, float z, const std::string& prior) {
    fs::create_directories(dir);
    Json meta = {{"source", "test"}};
    if (!prior.empty()) meta["prior_map"] = prior;
    auto w = journal::JournalWriter::create((dir / "journal.hsj").string(), jsonText(meta));
    ASSERT_TRUE(w.isOk());
    std::vector<journal::MapPoint> pts;
    for (int i = 0; i < 200; ++i)
        for (int j = 0; j < 200; ++j)
            pts.push_back({1.0, 0.02f * i, 0.02f * j, z, 10, 20, 30, 100});
    ASSERT_TRUE((*w)->appendPoints(pts).isOk());
    ASSERT_TRUE((*w)->appendPose({1.0, 0, 0, 1.3, 0, 0, 0, 1}).isOk());
    ASSERT_TRUE((*w)->finish().isOk());
}

TEST(MergeTest, OneCloudWithASessionIdPerPointAndATrajectoryPerSession) {
    const fs::path dir = fs::temp_directory_path() / "handscan_merge_test";
    fs::remove_all(dir);
    writeSession(dir / "a", 0.0f, "");
    writeSession(dir / "b", 0.003f, (dir / "a").string());  // 3 mm off: measured below
    auto r = mergeSessions({(dir / "a").string(), (dir / "b").string()}, (dir / "m").string());
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->points, 80000u);
    ASSERT_EQ(r->sessions.size(), 2u);
    EXPECT_TRUE(r->sessions[1].in_frame);
    EXPECT_NEAR(r->sessions[1].against_first.median_m, 0.003, 5e-4);
    EXPECT_GT(r->sessions[1].against_first.overlap_points, 1000u);
    EXPECT_TRUE(fs::exists(dir / "m" / "trajectory_1.tum"));
    EXPECT_TRUE(fs::exists(dir / "m" / "trajectory_2.tum"));

    const auto ply = readAll(dir / "m" / "map.ply");
    const std::string text(ply.begin(), ply.end());
    const std::size_t end = text.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    EXPECT_NE(text.find("property ushort session\nend_header"), std::string::npos);
    const std::size_t record = 27, body = end + 11;
    ASSERT_EQ(ply.size(), body + 80000 * record);
    std::uint16_t first = 0, last = 0;
    std::memcpy(&first, &ply[body + 25], 2);
    std::memcpy(&last, &ply[body + 79999 * record + 25], 2);
    EXPECT_EQ(first, 1);
    EXPECT_EQ(last, 2);

    const auto las = readAll(dir / "m" / "map.las");
    std::uint32_t offset = 0;
    std::memcpy(&offset, &las[96], 4);  // offset to point data
    std::uint16_t source = 0;
    std::memcpy(&source, &las[offset + 79999 * 36 + 20], 2);
    EXPECT_EQ(source, 2);

    const Json sessions = Json::parse(std::string([&] {
        auto b = readAll(dir / "m" / "sessions.json");
        return std::string(b.begin(), b.end());
    }()));
    EXPECT_EQ(sessions["sessions"][1]["in_frame"], true);
    fs::remove_all(dir);
}

TEST(MergeTest, ASessionNotLocalizedOnAnEarlierOneIsFlagged) {
    const fs::path dir = fs::temp_directory_path() / "handscan_merge_test_flag";
    fs::remove_all(dir);
    writeSession(dir / "a", 0.0f, "");
    writeSession(dir / "b", 0.0f, "");
    auto r = mergeSessions({(dir / "a").string(), (dir / "b").string()}, (dir / "m").string());
    ASSERT_TRUE(r.isOk());
    EXPECT_FALSE(r->sessions[1].in_frame);
    EXPECT_FALSE(mergeSessions({(dir / "a").string()}, (dir / "m").string()).isOk());
    fs::remove_all(dir);
}

TEST(ConsistencyTest, NewGroundIsOutsideTheOverlap) {
    std::vector<Eigen::Vector3f> a, b;
    for (int i = 0; i < 100; ++i)
        for (int j = 0; j < 100; ++j) {
            a.emplace_back(0.02f * i, 0.02f * j, 0.0f);
            b.emplace_back(0.02f * i + 5.0f, 0.02f * j, 0.0f);  // 3 m away from all of a
        }
    const Consistency c = measureConsistency(a, b);
    EXPECT_GT(c.sampled, 0u);
    EXPECT_EQ(c.overlap_points, 0u);
}

}  // namespace
}  // namespace handscan::merge
