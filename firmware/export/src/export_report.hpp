// Gathers the scan report (handscan::report) while the export streams its points: the facts from
// every journal point, the map views from the exported ones (at most ~2 M of them: a 1024-cell
// raster gains nothing from more, and the export keeps its speed).
#pragma once

#include <span>
#include <string>
#include <utility>
#include <vector>

#include "handscan/journal/journal_reader.hpp"
#include "handscan/report/map_images.hpp"
#include "handscan/report/map_raster.hpp"
#include "handscan/report/scan_facts.hpp"

namespace handscan::exporter {

class ExportReportBuilder {
public:
    ExportReportBuilder(std::uint64_t exported_points,
                        const std::vector<journal::TrajectoryPose>& trajectory);
    void journalPoints(std::span<const journal::MapPoint> points) { facts_.add(points); }
    void exportedPoints(std::span<const journal::MapPoint> points);
    // The map views report.html shows (caption, PNG): from above by height and by RGB, from the
    // side by height and by RGB.
    std::vector<std::pair<std::string, report::MapImage>> images(
        const journal::JournalSummary& js) const;
    // report.html's text; `files` are the export's other files, `stats_json` a replay's stats
    // (used for the timeline when the journal holds no per-sweep records).
    std::string html(const journal::JournalSummary& js, const std::string& scan_name,
                     std::uint64_t exported, double voxel_m, const std::vector<std::string>& files,
                     const std::string& stats_json) const;

private:
    report::ScanFactsBuilder facts_;
    report::MapRaster top_, side_{report::View::kSide};
    std::size_t stride_ = 1;
    std::size_t phase_ = 0;  // index of the next point to raster within the stride
    std::vector<journal::MapPoint> sampled_;
};

}  // namespace handscan::exporter
