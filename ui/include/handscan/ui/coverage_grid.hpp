// Top-down point density for the coverage view: a 2D grid of per-cell point counts over the
// scanned area, coloured so that empty cells (gaps the operator should walk to) stand out black
// against the scanned floor. Pure CPU code; the UI uploads the image as a texture.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

#include "handscan/shm/layout.hpp"

namespace handscan::ui {

struct CoverageImage {
    int width = 0, height = 0;       // cells
    float min_x_m = 0, max_y_m = 0;  // world position of the top-left corner (row 0 = north edge)
    float cell_m = 0;
    std::vector<std::uint8_t> rgba;  // width * height * 4
    std::vector<std::uint32_t> counts;
};

class CoverageGrid {
public:
    explicit CoverageGrid(float cell_m = 0.25f, int max_cells_per_side = 1024);
    // Counts points at or below max_z_m (the UI passes the device height minus 0.5 m, so that
    // ceilings do not hide gaps in the floor).
    void add(std::span<const shm::DisplayPoint> points,
             float max_z_m = std::numeric_limits<float>::infinity());
    void clear();
    std::size_t occupiedCells() const { return cells_.size(); }
    std::uint32_t countAt(float x_m, float y_m) const;
    CoverageImage render() const;

private:
    static std::int64_t key(std::int32_t ix, std::int32_t iy) {
        return (static_cast<std::int64_t>(ix) << 32) ^ static_cast<std::uint32_t>(iy);
    }
    float cell_m_;
    int max_side_;
    std::unordered_map<std::int64_t, std::uint32_t> cells_;
    std::int32_t min_ix_ = 0, max_ix_ = -1, min_iy_ = 0, max_iy_ = -1;
};

}  // namespace handscan::ui
