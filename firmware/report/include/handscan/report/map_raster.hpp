// A map view rasterised while the points stream past once (no second pass, no cloud in memory):
// a 1024 x 1024 grid of cells that keeps, per cell, the point nearest the viewer and its colour.
// The grid starts at 1 cm cells around the first point and doubles its cell size (merging 2 x 2
// cells) whenever a point falls outside, so it always covers everything seen at the finest
// resolution that fits: a 10 m room at 1-2 cm, a 1 km walk at 1 m.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "handscan/journal/map_point.hpp"

namespace handscan::report {

enum class View {
    kTop,   // looking down: horizontal x right, y up; keeps the highest point
    kSide,  // looking along +y: x right, z up; keeps the point with the smallest y
};

struct RasterCell {
    float depth = 0;   // z (top) or -y (side): larger is nearer the viewer
    float height = 0;  // z of the kept point
    std::uint8_t r = 0, g = 0, b = 0;
    bool set = false;
};

class MapRaster {
public:
    static constexpr int kCells = 1024;
    // `max_z`: points above it are left out (the top view of an indoor walk would otherwise show
    // the ceiling; the export passes the highest trajectory point + 1 m).
    explicit MapRaster(View view, float max_z = std::numeric_limits<float>::infinity())
        : view_(view), max_z_(max_z) {}
    void add(std::span<const journal::MapPoint> points);
    // Grid geometry: cell (i, j) covers [u0 + i c, u0 + (i + 1) c) x [v0 + j c, ...).
    double cell() const { return cell_; }
    double u0() const { return u0_; }
    double v0() const { return v0_; }
    View view() const { return view_; }
    bool empty() const { return cells_.empty(); }
    const RasterCell& at(int i, int j) const {
        return cells_[static_cast<std::size_t>(j) * kCells + i];
    }
    // The view's horizontal / vertical coordinate of a world point.
    double u(double x, double /*y*/) const { return x; }
    double v(double y, double z) const { return view_ == View::kTop ? y : z; }

private:
    void start(double u, double v);
    void grow(double u, double v);  // until (u, v) is inside

    View view_;
    float max_z_;
    std::vector<RasterCell> cells_;
    double cell_ = 0.01, u0_ = 0, v0_ = 0;
};

}  // namespace handscan::report
