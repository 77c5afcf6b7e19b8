#include "export_report.hpp"

#include <algorithm>
#include <limits>

#include "handscan/report/map_images.hpp"
#include "handscan/report/report_html.hpp"

#ifndef HANDSCAN_VERSION
#define HANDSCAN_VERSION "0.0.0"
#endif

namespace handscan::exporter {

namespace {
constexpr std::uint64_t kRasterPoints = 2'000'000;
constexpr float kAboveHeadM = 1.0f;  // the top view leaves out what is higher above the walker

float ceilingCut(const std::vector<journal::TrajectoryPose>& trajectory) {
    if (trajectory.empty()) return std::numeric_limits<float>::infinity();
    double top = trajectory.front().z;
    for (const auto& p : trajectory) top = std::max(top, p.z);
    return static_cast<float>(top) + kAboveHeadM;
}

}  // namespace

ExportReportBuilder::ExportReportBuilder(std::uint64_t exported_points,
                                         const std::vector<journal::TrajectoryPose>& trajectory)
    : top_(report::View::kTop, ceilingCut(trajectory)),
      stride_(
          static_cast<std::size_t>(std::max<std::uint64_t>(1, exported_points / kRasterPoints))) {}

void ExportReportBuilder::exportedPoints(std::span<const journal::MapPoint> points) {
    if (stride_ == 1) {
        top_.add(points);
        side_.add(points);
        return;
    }
    sampled_.clear();
    for (; phase_ < points.size(); phase_ += stride_) sampled_.push_back(points[phase_]);
    phase_ -= points.size();
    top_.add(sampled_);
    side_.add(sampled_);
}

std::string ExportReportBuilder::html(const journal::JournalSummary& js,
                                      const std::string& scan_name, std::uint64_t exported,
                                      double voxel_m, const std::vector<std::string>& files,
                                      const std::string& stats_json) const {
    report::ReportInputs in;
    in.scan_name = scan_name;
    in.software = std::string("handscan ") + HANDSCAN_VERSION;
    in.journal_damage = js.damage;
    in.sweep_damage = js.sweep_damage;
    in.exported_points = exported;
    in.voxel_m = voxel_m;
    in.facts = facts_.finish(js.trajectory, js.sweeps, stats_json);
    in.files = files;
    in.images = images(js);
    return report::reportHtml(in);
}

std::vector<std::pair<std::string, report::MapImage>> ExportReportBuilder::images(
    const journal::JournalSummary& js) const {
    std::vector<std::pair<std::string, report::MapImage>> out;
    const struct {
        const report::MapRaster& raster;
        report::Colouring colouring;
        const char* caption;
    } views[] = {
        {top_, report::Colouring::kHeight, "from above, by height (cut 1 m over the walk)"},
        {top_, report::Colouring::kRgb, "from above, camera colours (same cut)"},
        {side_, report::Colouring::kHeight, "from the side (along +y), by height"},
        {side_, report::Colouring::kRgb, "from the side (along +y), camera colours"},
    };
    for (const auto& v : views) {
        auto image = report::renderMap(v.raster, v.colouring, js.trajectory, v.caption);
        if (image.isOk()) out.emplace_back(v.caption, std::move(*image));
    }
    return out;
}

}  // namespace handscan::exporter
