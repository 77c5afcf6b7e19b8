#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "handscan/report/map_images.hpp"
#include "handscan/report/map_raster.hpp"
#include "handscan/report/report_html.hpp"
#include "handscan/report/scan_facts.hpp"

namespace handscan::report {
namespace {

journal::MapPoint point(double t, float x, float y, float z, std::uint8_t r = 0) {
    return {t, x, y, z, r, r, r, 0};
}

// The grid starts at 1 cm and doubles until a point 300 m away fits; nothing is lost on the way
// and the nearest point (highest, from above) wins each merged cell.
TEST(MapRaster, GrowsToCoverEveryPointKeepingTheHighest) {
    MapRaster top(View::kTop);
    const std::vector<journal::MapPoint> pts = {point(0, 0, 0, 1), point(0, 0.001f, 0, 5),
                                                point(0, 300, -20, 0)};
    top.add(pts);
    EXPECT_GE(top.cell() * MapRaster::kCells, 300.0);
    EXPECT_LE(top.cell() * MapRaster::kCells, 1200.0);
    int set = 0;
    float highest = 0;
    for (int j = 0; j < MapRaster::kCells; ++j) {
        for (int i = 0; i < MapRaster::kCells; ++i) {
            if (!top.at(i, j).set) continue;
            ++set;
            highest = std::max(highest, top.at(i, j).height);
        }
    }
    EXPECT_EQ(set, 2);  // the two points at the origin share a cell by now
    EXPECT_EQ(highest, 5.0f);
}

TEST(MapImages, RendersPng) {
    MapRaster side(View::kSide);
    std::vector<journal::MapPoint> pts;
    for (int i = 0; i < 1000; ++i) pts.push_back(point(i, i * 0.01f, 0, (i % 100) * 0.02f, 200));
    side.add(pts);
    const std::vector<journal::TrajectoryPose> tr = {{0, 0, 0, 1}, {1, 5, 0, 1}};
    auto img = renderMap(side, Colouring::kHeight, tr, "side");
    ASSERT_TRUE(img.isOk()) << img.status().message();
    ASSERT_GT(img->png.size(), 100u);
    EXPECT_EQ(std::string(img->png.begin() + 1, img->png.begin() + 4), "PNG");
    EXPECT_GT(img->width, 100);
}

// A 10 m x 10 m square walked back to 0.2 m from its start, 1 pose per second; the laser silent
// from 12 to 15 s; stats.json degenerate for two sweeps at 20 and 21 s.
TEST(ScanFacts, DistanceLoopGapDropoutsAndDegenerateIntervals) {
    std::vector<journal::TrajectoryPose> tr;
    for (int k = 0; k <= 40; ++k) {
        const double s = k * 1.0;  // metres along the square
        double x = 0, y = 0;
        if (s <= 10)
            x = s;
        else if (s <= 20)
            x = 10, y = s - 10;
        else if (s <= 30)
            x = 30 - s, y = 10;
        else
            x = 0, y = 40 - s;
        if (k == 40) x = 0.2;
        tr.push_back({100.0 + k, x, y, 0, 0, 0, 0, 1});
    }
    ScanFactsBuilder b;
    std::vector<journal::MapPoint> pts;
    for (int i = 0; i < 4000; ++i) {
        const double t = 100.0 + i * 0.01;
        if (t >= 112.0 && t < 115.0) continue;
        pts.push_back(point(t, 0, 0, 0, i < 2000 ? 0 : 50));
    }
    b.add(pts);
    const std::string stats =
        R"({"per_sweep": [{"t_start_s": 119.0, "degenerate_directions": 0},
                          {"t_start_s": 120.0, "degenerate_directions": 1},
                          {"t_start_s": 121.0, "degenerate_directions": 2},
                          {"t_start_s": 122.0, "degenerate_directions": 0}]})";
    const ScanFacts f = b.finish(tr, stats);
    EXPECT_DOUBLE_EQ(f.duration_s, 40.0);
    EXPECT_NEAR(f.distance_m, 39.0 + std::sqrt(1.04), 1e-9);  // the last leg ends 0.2 m off
    ASSERT_TRUE(f.loop_gap_m.has_value());
    EXPECT_NEAR(*f.loop_gap_m, 0.2, 1e-9);
    EXPECT_EQ(f.points, pts.size());
    EXPECT_EQ(f.coloured, 2000u);
    ASSERT_EQ(f.laser_dropouts.size(), 1u);
    EXPECT_DOUBLE_EQ(f.laser_dropouts[0].from_s, 12.0);
    EXPECT_DOUBLE_EQ(f.laser_dropouts[0].to_s, 15.0);
    EXPECT_TRUE(f.pose_dropouts.empty());
    ASSERT_EQ(f.degenerate.size(), 1u);
    EXPECT_DOUBLE_EQ(f.degenerate[0].from_s, 20.0);
    EXPECT_DOUBLE_EQ(f.degenerate[0].to_s, 22.0);
    EXPECT_EQ(f.degenerate[0].directions, 2);
    ASSERT_EQ(f.bins.size(), 40u);
    EXPECT_EQ(f.bins[0].points, 100u);
    EXPECT_EQ(f.bins[13].points, 0u);
    EXPECT_EQ(f.bins[5].poses, 1u);
}

TEST(ScanFacts, AnOpenWalkHasNoLoopGap) {
    const std::vector<journal::TrajectoryPose> tr = {{0, 0, 0, 0}, {10, 30, 0, 0}};
    const ScanFacts f = ScanFactsBuilder().finish(tr, "");
    EXPECT_FALSE(f.loop_gap_m.has_value());
    EXPECT_NE(f.loop_note.find("no closed loop"), std::string::npos);
    EXPECT_FALSE(f.have_sweep_stats);
    ASSERT_EQ(f.pose_dropouts.size(), 1u);  // 10 s without a pose
}

// stats.json's per-sweep masks, the tracking monitor's lost intervals and the VIO's bypassed
// stretches become the module timeline: tx degenerate at 20 s and solved by the VIO at 21 s.
TEST(ScanFacts, ModulesTrackingAndVioBypassOverTime) {
    const std::vector<journal::TrajectoryPose> tr = {{100, 0, 0, 0}, {130, 1, 0, 0}};
    const std::string stats = R"({
        "vio": {"first_frame_s": 101.0, "bypassed": [{"begin_s": 110.0, "end_s": 112.5},
                                                     {"begin_s": 125.0, "end_s": null}]},
        "tracking": {"lost_intervals": [{"begin_s": 115.0, "end_s": 117.0,
                                         "reason": "poor_fit"}]},
        "per_sweep": [
          {"t_start_s": 119.0, "degenerate_directions": 0, "solved_dof_mask": 63,
           "vio_solved_dof_mask": 0, "tracking": "ok"},
          {"t_start_s": 120.0, "degenerate_directions": 1, "solved_dof_mask": 55,
           "vio_solved_dof_mask": 0, "tracking": "rejected"},
          {"t_start_s": 121.0, "degenerate_directions": 1, "solved_dof_mask": 55,
           "vio_solved_dof_mask": 8, "tracking": "lost"}]})";
    const ScanFacts f = ScanFactsBuilder().finish(tr, stats);
    ASSERT_EQ(f.sweep_modules.size(), 3u);
    EXPECT_EQ(f.sweep_modules[1].scan_mask, 55);
    EXPECT_EQ(f.sweep_modules[1].tracking, 'r');
    EXPECT_EQ(f.sweep_modules[2].vio_mask, 8);
    EXPECT_EQ(f.sweep_modules[2].tracking, 'l');
    ASSERT_EQ(f.tracking_lost.size(), 1u);
    EXPECT_DOUBLE_EQ(f.tracking_lost[0].from_s, 15.0);
    EXPECT_EQ(f.tracking_lost[0].what, "poor_fit");
    ASSERT_TRUE(f.have_vio);
    EXPECT_DOUBLE_EQ(f.vio_from_s, 1.0);
    ASSERT_EQ(f.vio_bypassed.size(), 2u);
    EXPECT_DOUBLE_EQ(f.vio_bypassed[0].to_s, 12.5);
    EXPECT_DOUBLE_EQ(f.vio_bypassed[1].to_s, 30.0);  // still bypassed at the end
    ReportInputs in;
    in.facts = f;
    const std::string html = reportHtml(in);
    EXPECT_NE(html.find("Modules and directions over time"), std::string::npos);
    EXPECT_NE(html.find("<td>poor_fit</td>"), std::string::npos);
    // tx (lane 3) from 21 s to the end in the VIO's green, from 20 s in the IMU's orange.
    const auto lane_rect = [&](double t, const char* colour) {
        const double x = 80 + (900 - 80 - 10) * t / 30.0;
        char needle[96];
        std::snprintf(needle, sizeof needle, "<rect x=\"%g\" y=\"68\"", x);
        const auto at = html.find(needle);
        return at != std::string::npos && html.find(colour, at) < html.find("/>", at);
    };
    EXPECT_TRUE(lane_rect(20.0, "#f59628"));
    EXPECT_TRUE(lane_rect(21.0, "#46c85a"));
    EXPECT_FALSE(lane_rect(21.0, "#3c78eb"));
}

TEST(ReportHtml, SelfContained) {
    EXPECT_EQ(base64({'M', 'a', 'n'}), "TWFu");
    EXPECT_EQ(base64({'M', 'a'}), "TWE=");
    EXPECT_EQ(base64({'M'}), "TQ==");
    ReportInputs in;
    in.scan_name = "hall <2>";
    in.images.push_back({"top", MapImage{{1, 2, 3}, 10, 10}});
    const std::string html = reportHtml(in);
    EXPECT_NE(html.find("src=\"data:image/png;base64,AQID\""), std::string::npos);
    EXPECT_NE(html.find("hall &lt;2&gt;"), std::string::npos);
    EXPECT_EQ(html.find("<script"), std::string::npos);
    EXPECT_EQ(html.find("src=\"http"), std::string::npos);
}

}  // namespace
}  // namespace handscan::report
