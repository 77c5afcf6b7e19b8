// The report's module timeline and device rates from the journal's own per-sweep records (what a
// scan journaled by the daemon carries), the "unavailable" note for a journal without them (and
// no stats.json), and a damaged statistics chunk: named with where in the report and the
// export's notes, every point still exported.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "export_test_support.hpp"
#include "handscan/export/exporter.hpp"
#include "handscan/journal/journal_format.hpp"
#include "handscan/journal/journal_writer.hpp"

namespace handscan::exporter::testing {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

// A 20 s scan, one sweep a second: z (tz, bit 5) degenerate from 8 to 11 s, tracking lost at
// 14-15 s ("poor_fit"), the IMU silent in the sweep at 17 s. 1000 points a sweep. Returns each
// statistics chunk's offset.
std::vector<std::uint64_t> writeScan(const std::string& path) {
    std::vector<std::uint64_t> stats_at;
    auto w = journal::JournalWriter::create(path, "{}");
    EXPECT_TRUE(w.isOk());
    for (int k = 0; k < 20; ++k) {
        const double t = 50.0 + k;
        for (int i = 0; i < 5; ++i)
            EXPECT_TRUE((*w)->appendPose({t + 0.2 * i, 0.1 * k, 0, 0, 0, 0, 0, 1}).isOk());
        journal::SweepRecord r;
        r.t_start_s = t;
        r.index = static_cast<std::uint64_t>(k);
        r.solved_mask = k >= 8 && k < 11 ? 0x1F : 0x3F;
        r.tracking =
            k == 14 || k == 15 ? journal::SweepTracking::kLost : journal::SweepTracking::kOk;
        if (k == 14 || k == 15) r.tracking_reason = "poor_fit";
        r.devices = {1.0, 40, k == 17 ? 0u : 200u, 100, 0, 0};
        EXPECT_TRUE((*w)->appendSweep(r).isOk());
        std::vector<journal::MapPoint> pts;
        for (int i = 0; i < 1000; ++i)
            pts.push_back({t + i * 1e-3, float(i % 50), float(i / 50), 0.5f, 9, 9, 9, 100});
        EXPECT_TRUE((*w)->appendPoints(pts).isOk());
        stats_at.push_back(fs::file_size(path) + journal::kChunkHeaderBytes +
                           5 * journal::kPoseRecordBytes);
        EXPECT_TRUE((*w)->flush().isOk());
    }
    EXPECT_TRUE((*w)->finish().isOk());
    return stats_at;
}

// Total seconds of `lane` drawn in `colour` (the timeline's data-from / data-to).
double laneSeconds(const std::string& html, const std::string& lane, const std::string& colour) {
    const std::regex rect("fill=\"" + colour + "\" data-lane=\"" + lane +
                          "\" data-from=\"([0-9.]+)\" data-to=\"([0-9.]+)\"");
    double sum = 0;
    for (auto it = std::sregex_iterator(html.begin(), html.end(), rect);
         it != std::sregex_iterator(); ++it)
        sum += std::stod((*it)[2]) - std::stod((*it)[1]);
    return sum;
}

TEST_F(ExportTest, ReportTimelineAndDeviceRatesFromTheJournal) {
    const std::string journal = (dir_ / "journal.hsj").string();
    writeScan(journal);
    ExportOptions opt{{"ply"}, 0.0, "scan", {}, {}, true, ""};
    fs::create_directories(dir_ / "out");
    auto r = exportScan(journal, (dir_ / "out").string(), opt);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const std::string html = readText(fs::path(r->directory) / "report.html");
    EXPECT_NE(html.find("From the journal (20 sweeps)"), std::string::npos);
    EXPECT_EQ(html.find("timeline unavailable"), std::string::npos);
    // tz held by the IMU for the three degenerate sweeps, solved by the matcher the other 17.
    EXPECT_NEAR(laneSeconds(html, "tz", "#f59628"), 3.0, 1e-6);
    EXPECT_NEAR(laneSeconds(html, "tz", "#3c78eb"), 17.0, 1e-6);
    EXPECT_NEAR(laneSeconds(html, "rx", "#3c78eb"), 20.0, 1e-6);
    EXPECT_NE(html.find("<td>14.0 s</td><td>16.0 s</td><td>2.0 s</td><td>poor_fit</td>"),
              std::string::npos);
    // Device rates: the laser at 40 scans/s throughout, the IMU's dropout at 17-18 s.
    EXPECT_NE(html.find("<tr data-device=\"laser\"><td>laser</td><td>40.0 scans/s</td><td>40.0 "
                        "scans/s</td><td>0</td></tr>"),
              std::string::npos);
    EXPECT_NE(html.find("<tr data-device=\"IMU\"><td>IMU</td><td>190.0 samples/s</td><td>0.0 "
                        "samples/s</td><td>1</td></tr>"),
              std::string::npos);
    EXPECT_NE(html.find("<td>17.0 s</td><td>18.0 s</td><td>1.0 s</td><td>IMU</td>"),
              std::string::npos);
    EXPECT_EQ(html.find("data-device=\"colour camera\""), std::string::npos);  // none fitted
}

TEST_F(ExportTest, ReportSaysTheTimelineIsUnavailableForAnOldJournal) {
    const std::string journal = makeJournal(1000);  // points and a pose, no sweep records
    ExportOptions opt{{"ply"}, 0.0, "scan", {}, {}, true, ""};
    fs::create_directories(dir_ / "out");
    auto r = exportScan(journal, (dir_ / "out").string(), opt);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    const std::string html = readText(fs::path(r->directory) / "report.html");
    EXPECT_NE(html.find("timeline unavailable"), std::string::npos);
    EXPECT_EQ(html.find("data-lane="), std::string::npos);  // no empty chart drawn
    EXPECT_EQ(html.find("Devices: samples per second"), std::string::npos);
}

TEST_F(ExportTest, ACorruptStatisticsChunkIsReportedAndTheRestExports) {
    const std::string journal = (dir_ / "journal.hsj").string();
    const auto stats_at = writeScan(journal);
    {
        std::fstream f(journal, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(static_cast<std::streamoff>(stats_at[9] + journal::kChunkHeaderBytes + 30));
        f.put('\x7f');
    }
    ExportOptions opt{{"ply"}, 0.0, "scan", {}, {}, true, ""};
    fs::create_directories(dir_ / "out");
    auto r = exportScan(journal, (dir_ / "out").string(), opt);
    ASSERT_TRUE(r.isOk()) << r.status().message();
    EXPECT_EQ(r->points, 20000u);
    const std::string where = "chunk 29 at byte " + std::to_string(stats_at[9]);
    ASSERT_EQ(r->notes.size(), 1u);
    EXPECT_NE(r->notes[0].find(where), std::string::npos) << r->notes[0];
    const std::string html = readText(fs::path(r->directory) / "report.html");
    EXPECT_NE(html.find("Per-sweep statistics left out: " + where), std::string::npos);
    EXPECT_NE(html.find("From the journal (19 sweeps)"), std::string::npos);
}

}  // namespace
}  // namespace handscan::exporter::testing
