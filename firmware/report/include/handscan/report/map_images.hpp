// PNG images of a MapRaster: coloured by height (turbo colour map between the 2nd and 98th
// percentile of the cells' heights, with its legend) or by the points' RGB (grey where no camera
// frame coloured them), the trajectory drawn over it (start circle, end square) and a scale bar.
// The export's report.html and `handscan eval --plot` both show these.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "handscan/core/status.hpp"
#include "handscan/journal/map_point.hpp"
#include "handscan/report/map_raster.hpp"

namespace handscan::report {

enum class Colouring { kHeight, kRgb };

struct MapImage {
    std::vector<std::uint8_t> png;
    int width = 0, height = 0;
};

Result<MapImage> renderMap(const MapRaster& raster, Colouring colouring,
                           std::span<const journal::TrajectoryPose> trajectory,
                           const std::string& title, int max_px = 900);

Status writePng(const std::string& path, const MapImage& image);

}  // namespace handscan::report
