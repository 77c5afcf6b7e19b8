// report.html: one self-contained page (images as data: URIs, charts as inline SVG, no script,
// no network) that opens offline in any browser: the map from above and from the side coloured
// by height and by RGB with the trajectory, the scan's figures, the sensors' health over time,
// the degenerate intervals and the loop-closure gap.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "handscan/report/map_images.hpp"
#include "handscan/report/scan_facts.hpp"

namespace handscan::report {

struct ReportInputs {
    std::string scan_name;
    std::string software;        // "handscan 0.1.0"
    std::string journal_damage;  // non-empty when the journal was recovered after a crash
    // Per-sweep statistics the journal could not read (each with where): left out of the timeline.
    std::vector<std::string> sweep_damage;
    std::uint64_t exported_points = 0;
    double voxel_m = 0.0;
    ScanFacts facts;
    std::vector<std::pair<std::string, MapImage>> images;  // caption, image
    std::vector<std::string> files;                        // the export's other files
};

std::string reportHtml(const ReportInputs& in);

std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace handscan::report
