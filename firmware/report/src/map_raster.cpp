#include "handscan/report/map_raster.hpp"

#include <cmath>

namespace handscan::report {

void MapRaster::start(double u, double v) {
    cells_.assign(static_cast<std::size_t>(kCells) * kCells, RasterCell{});
    u0_ = u - kCells / 2 * cell_;
    v0_ = v - kCells / 2 * cell_;
}

void MapRaster::grow(double u, double v) {
    while (true) {
        const double span = kCells * cell_;
        const bool below_u = u < u0_, below_v = v < v0_;
        const bool inside = !below_u && !below_v && u < u0_ + span && v < v0_ + span;
        if (inside) return;
        // The old grid becomes one quadrant of a grid twice as coarse, on the side away from
        // the point; every 2 x 2 block of old cells merges into one, the nearest point winning.
        const int shift_i = below_u ? kCells / 2 : 0, shift_j = below_v ? kCells / 2 : 0;
        std::vector<RasterCell> merged(cells_.size());
        for (int j = 0; j < kCells; ++j) {
            for (int i = 0; i < kCells; ++i) {
                const RasterCell& c = cells_[static_cast<std::size_t>(j) * kCells + i];
                if (!c.set) continue;
                RasterCell& m =
                    merged[static_cast<std::size_t>(j / 2 + shift_j) * kCells + i / 2 + shift_i];
                if (!m.set || c.depth > m.depth) m = c;
            }
        }
        cells_.swap(merged);
        if (below_u) u0_ -= span;
        if (below_v) v0_ -= span;
        cell_ *= 2;
    }
}

void MapRaster::add(std::span<const journal::MapPoint> points) {
    for (const journal::MapPoint& p : points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !(p.z <= max_z_)) continue;
        const double u = p.x, v = view_ == View::kTop ? p.y : p.z;
        const float depth = view_ == View::kTop ? p.z : -p.y;
        if (cells_.empty()) start(u, v);
        auto i = static_cast<long>(std::floor((u - u0_) / cell_));
        auto j = static_cast<long>(std::floor((v - v0_) / cell_));
        if (i < 0 || j < 0 || i >= kCells || j >= kCells) {
            grow(u, v);
            i = static_cast<long>(std::floor((u - u0_) / cell_));
            j = static_cast<long>(std::floor((v - v0_) / cell_));
            if (i < 0 || j < 0 || i >= kCells || j >= kCells) continue;  // rounding at the edge
        }
        RasterCell& c = cells_[static_cast<std::size_t>(j) * kCells + static_cast<std::size_t>(i)];
        if (!c.set || depth > c.depth) c = {depth, p.z, p.r, p.g, p.b, true};
    }
}

}  // namespace handscan::report
