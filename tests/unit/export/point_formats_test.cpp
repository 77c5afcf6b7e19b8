#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>

#include "export_test_support.hpp"
#include "handscan/core/json.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

template <typename T>
T at(const std::vector<std::uint8_t>& b, std::size_t off) {
    T v;
    std::memcpy(&v, b.data() + off, sizeof v);
    return v;
}

TEST_F(ExportTest, PlyHeaderAndRecords) {
    const std::string journal = makeJournal(10);
    auto r = exportScan(journal, dir_.string(), {{"ply"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const auto bytes = readFile((dir_ / "out" / "cloud.ply").string());
    const std::string text(bytes.begin(), bytes.end());
    const std::size_t end = text.find("end_header\n");
    ASSERT_NE(end, std::string::npos);
    EXPECT_NE(text.find("format binary_little_endian 1.0\n"), std::string::npos);
    EXPECT_NE(text.find("element vertex 10\n"), std::string::npos);
    EXPECT_NE(text.find("property ushort intensity\nproperty double time\n"), std::string::npos);
    const std::size_t body = end + 11;
    ASSERT_EQ(bytes.size(), body + 10 * 25);
    // Point 3: x = 3, colour (3, 6, 9), intensity 3, time 3.
    const std::size_t p3 = body + 3 * 25;
    EXPECT_EQ(at<float>(bytes, p3), 3.0f);
    EXPECT_EQ(at<float>(bytes, p3 + 8), -1.0f);
    EXPECT_EQ(bytes[p3 + 13], 6);
    EXPECT_EQ(at<std::uint16_t>(bytes, p3 + 15), 3);
    EXPECT_EQ(at<double>(bytes, p3 + 17), 3.0);
    EXPECT_EQ(r->points, 10u);
}

TEST_F(ExportTest, CountsThePointsTheCameraColoured) {
    // Points 0, 256 and 512 carry their laser grey (never seen by the camera), the rest colours
    // (i, 2i, 3i) mod 256.
    const std::string journal = makeJournal(600);
    auto r = exportScan(journal, dir_.string(), {{"ply"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->points, 600u);
    EXPECT_EQ(r->coloured_points, 597u);
    const auto json = readFile((dir_ / "out" / "scan.json").string());
    EXPECT_NE(std::string(json.begin(), json.end()).find("\"coloured_points\": 597"),
              std::string::npos);
}

TEST_F(ExportTest, LasHeaderFields) {
    const std::string journal = makeJournal(100);
    auto r = exportScan(journal, dir_.string(), {{"las"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const auto b = readFile((dir_ / "out" / "cloud.las").string());
    ASSERT_EQ(b.size(), 375u + 100u * 36u);
    EXPECT_EQ(std::string(b.begin(), b.begin() + 4), "LASF");
    EXPECT_EQ(b[24], 1);                         // version major
    EXPECT_EQ(b[25], 4);                         // version minor
    EXPECT_EQ(at<std::uint16_t>(b, 94), 375);    // header size
    EXPECT_EQ(at<std::uint32_t>(b, 96), 375u);   // offset to points
    EXPECT_EQ(b[104], 7);                        // point data record format
    EXPECT_EQ(at<std::uint16_t>(b, 105), 36);    // record length
    EXPECT_EQ(at<std::uint32_t>(b, 107), 0u);    // legacy count must be 0 for format 7
    EXPECT_EQ(at<double>(b, 131), 1e-4);         // x scale
    EXPECT_EQ(at<double>(b, 179), 99.0);         // max x
    EXPECT_EQ(at<double>(b, 187), 0.0);          // min x
    EXPECT_EQ(at<std::uint64_t>(b, 247), 100u);  // number of point records
    EXPECT_EQ(at<std::uint64_t>(b, 255), 100u);  // points by return [1]
    // Point 5: X = (5 - offset) / scale, RGB scaled to 16 bit, GPS time = 5.
    const std::size_t p5 = 375 + 5 * 36;
    const double x_offset = at<double>(b, 155);
    EXPECT_EQ(at<std::int32_t>(b, p5), static_cast<std::int32_t>((5.0 - x_offset) / 1e-4 + 0.5));
    EXPECT_EQ(b[p5 + 14], 0x11);  // return 1 of 1
    EXPECT_EQ(at<double>(b, p5 + 22), 5.0);
    EXPECT_EQ(at<std::uint16_t>(b, p5 + 30), 5 * 257);
    EXPECT_EQ(at<std::uint16_t>(b, p5 + 34), 15 * 257);
}

TEST_F(ExportTest, VoxelFilterKeepsOnePointPerVoxelAtTheCentroid) {
    const std::string path = (dir_ / "j.hsj").string();
    {
        auto w = journal::JournalWriter::create(path, "{}");
        ASSERT_TRUE(w.isOk());
        std::vector<journal::MapPoint> pts;
        // Two points in voxel [0, 0.1) and one in [0.5, 0.6) along x.
        pts.push_back({1.0, 0.02f, 0.01f, 0.01f, 100, 0, 0, 10});
        pts.push_back({3.0, 0.06f, 0.01f, 0.01f, 200, 0, 0, 30});
        pts.push_back({5.0, 0.55f, 0.01f, 0.01f, 50, 50, 50, 5});
        ASSERT_TRUE((*w)->appendPoints(pts).isOk());
        ASSERT_TRUE((*w)->finish().isOk());
    }
    auto r = exportScan(path, dir_.string(), {{"ply"}, 0.1, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->points, 2u);
    EXPECT_EQ(r->journal_points, 3u);
    EXPECT_NEAR(r->bounds.min[0], 0.04, 1e-6);  // centroid of 0.02 and 0.06
    EXPECT_NEAR(r->bounds.max[0], 0.55, 1e-6);
}

TEST_F(ExportTest, TrajectoryAndMetadataFiles) {
    const std::string journal = makeJournal(5);
    auto r = exportScan(journal, dir_.string(), {{"ply", "las"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_EQ(r->files.size(), 6u);
    const auto tum = readFile((dir_ / "out" / "trajectory.tum").string());
    EXPECT_EQ(std::string(tum.begin(), tum.end()),
              "0.000000000 0.000000000 0.000000000 0.000000000 0.000000000 0.000000000 0.000000000 "
              "1.000000000\n");
    const auto json = readFile((dir_ / "out" / "scan.json").string());
    const std::string js(json.begin(), json.end());
    const Json doc = Json::parse(js, nullptr, false);
    ASSERT_TRUE(doc.is_object()) << js;
    EXPECT_EQ(doc["scan"], Json({{"device", "test"}})) << js;  // the journal's metadata, as JSON
    EXPECT_EQ(doc["journal"]["points"], 5) << js;
    EXPECT_EQ(doc["export"]["points"], 5) << js;
}

TEST_F(ExportTest, EmptyScanExportsValidEmptyFiles) {
    const std::string journal = makeJournal(0);
    auto r = exportScan(journal, dir_.string(), {{"ply", "las"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->points, 0u);
    const auto las = readFile((dir_ / "out" / "cloud.las").string());
    ASSERT_EQ(las.size(), 375u);
    EXPECT_EQ(at<std::uint64_t>(las, 247), 0u);
}

TEST_F(ExportTest, UnknownFormatRejected) {
    const std::string journal = makeJournal(1);
    auto r = exportScan(journal, dir_.string(), {{"ply", "xyz"}, 0.0, "out", {}, {}, true, ""});
    ASSERT_FALSE(r.isOk());
    EXPECT_EQ(r.status().message(), "export: unknown format 'xyz' (expected ply, las, e57)");
    EXPECT_FALSE(fs::exists(dir_ / "out" / "cloud.ply"));
}

TEST_F(ExportTest, ScanJsonListsTheFormatsWritten) {
    const std::string journal = makeJournal(3);
    ExportOptions defaults;  // every format
    defaults.scan_name = "out";
    ASSERT_TRUE(exportScan(journal, dir_.string(), defaults).isOk());
    const auto json = readFile((dir_ / "out" / "scan.json").string());
    const std::string text(json.begin(), json.end());
    const Json doc = Json::parse(text, nullptr, false);
    ASSERT_TRUE(doc.is_object()) << text;
    EXPECT_EQ(doc["export"]["formats"], Json({"ply", "las", "e57"})) << text;
    EXPECT_EQ(text.find("unavailable"), std::string::npos) << text;
}

// The UI's and the CLI's progress bar: fractions only grow, from 0 to exactly 1 with "done", and
// name each stage; every format is written in one pass, then each file is verified.
TEST_F(ExportTest, ProgressGrowsThroughTheStagesToDone) {
    const std::string journal = (dir_ / "three_chunks.hsj").string();
    {
        auto w = journal::JournalWriter::create(journal, "{}");
        ASSERT_TRUE(w.isOk());
        for (int chunk = 0; chunk < 3; ++chunk) {
            std::vector<journal::MapPoint> pts(100'000);  // 2.5 + 3.6 MB of output per chunk
            for (std::size_t i = 0; i < pts.size(); ++i)
                pts[i] = {chunk + i * 1e-6, i * 1e-4f, chunk * 1.f, 0.f, 1, 2, 3, 4};
            ASSERT_TRUE((*w)->appendPoints(pts).isOk());
            ASSERT_TRUE((*w)->flush().isOk());
        }
        ASSERT_TRUE((*w)->finish().isOk());
    }
    std::vector<std::pair<double, std::string>> seen;
    ExportOptions opt{{"ply", "las", "ply"}, 0.0, "out", {}, {}, true, ""};
    opt.progress = [&](double f, const std::string& stage) { seen.emplace_back(f, stage); };
    auto r = exportScan(journal, dir_.string(), opt);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    ASSERT_GE(seen.size(), 6u);
    EXPECT_EQ(seen.front(), (std::pair<double, std::string>{0.0, "reading journal"}));
    EXPECT_EQ(seen.back(), (std::pair<double, std::string>{1.0, "done"}));
    std::vector<std::string> stages;
    for (std::size_t i = 0; i < seen.size(); ++i) {
        if (i > 0) {
            EXPECT_GE(seen[i].first, seen[i - 1].first) << seen[i].second;
        }
        if (stages.empty() || stages.back() != seen[i].second) stages.push_back(seen[i].second);
    }
    EXPECT_EQ(stages, (std::vector<std::string>{"reading journal", "writing cloud.ply, cloud.las",
                                                "verifying cloud.ply", "verifying cloud.las",
                                                "writing trajectory and metadata",
                                                "writing report.html", "done"}));
    // One update per journal chunk while writing.
    EXPECT_EQ(
        std::count_if(seen.begin(), seen.end(),
                      [](const auto& s) { return s.second == "writing cloud.ply, cloud.las"; }),
        3);
    EXPECT_EQ(r->files.size(), 6u);  // the repeated "ply" is written once

    seen.clear();
    opt.voxel_m = 2.0;
    ASSERT_TRUE(exportScan(journal, dir_.string(), opt).isOk());
    EXPECT_EQ(seen.front().second, "thinning");
    EXPECT_TRUE(std::any_of(seen.begin(), seen.end(), [](const auto& s) {
        return s.second == "thinning" && s.first == 0.3;
    }));
    EXPECT_EQ(seen.back().first, 1.0);
}

}  // namespace
}  // namespace handscan::exporter::testing
