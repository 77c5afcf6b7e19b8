#include "handscan/ui/coverage_grid.hpp"

#include <algorithm>
#include <cmath>

namespace handscan::ui {

CoverageGrid::CoverageGrid(float cell_m, int max_cells_per_side)
    : cell_m_(cell_m), max_side_(max_cells_per_side) {}

void CoverageGrid::clear() {
    cells_.clear();
    min_ix_ = min_iy_ = 0;
    max_ix_ = max_iy_ = -1;
}

void CoverageGrid::add(std::span<const shm::DisplayPoint> points, float max_z_m) {
    for (const shm::DisplayPoint& p : points) {
        if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !(p.z_m <= max_z_m)) continue;
        const auto ix = static_cast<std::int32_t>(std::floor(p.x_m / cell_m_));
        const auto iy = static_cast<std::int32_t>(std::floor(p.y_m / cell_m_));
        if (cells_.empty()) {
            min_ix_ = max_ix_ = ix;
            min_iy_ = max_iy_ = iy;
        }
        ++cells_[key(ix, iy)];
        min_ix_ = std::min(min_ix_, ix);
        max_ix_ = std::max(max_ix_, ix);
        min_iy_ = std::min(min_iy_, iy);
        max_iy_ = std::max(max_iy_, iy);
    }
}

std::uint32_t CoverageGrid::countAt(float x_m, float y_m) const {
    const auto it = cells_.find(key(static_cast<std::int32_t>(std::floor(x_m / cell_m_)),
                                    static_cast<std::int32_t>(std::floor(y_m / cell_m_))));
    return it == cells_.end() ? 0 : it->second;
}

CoverageImage CoverageGrid::render() const {
    CoverageImage img;
    img.cell_m = cell_m_;
    if (cells_.empty()) return img;
    // One pixel per cell, centred on the scanned area and clipped to max_side_ cells.
    const std::int32_t full_w = max_ix_ - min_ix_ + 1, full_h = max_iy_ - min_iy_ + 1;
    const std::int32_t w = std::min(full_w, max_side_);
    const std::int32_t h = std::min(full_h, max_side_);
    const auto centre = [](std::int32_t a, std::int32_t b) {
        return static_cast<std::int32_t>(std::floor((a + b) / 2.0));
    };
    const std::int32_t x0 = w == full_w ? min_ix_ : centre(min_ix_, max_ix_) - w / 2;
    const std::int32_t ytop = h == full_h ? max_iy_ : centre(min_iy_, max_iy_) + h / 2;
    img.width = w;
    img.height = h;
    img.min_x_m = static_cast<float>(x0) * cell_m_;
    img.max_y_m = static_cast<float>(ytop + 1) * cell_m_;
    img.rgba.assign(static_cast<std::size_t>(w) * h * 4, 0);
    img.counts.assign(static_cast<std::size_t>(w) * h, 0);
    std::uint32_t max_count = 1;
    for (const auto& [k, c] : cells_) max_count = std::max(max_count, c);
    const float log_max = std::log1p(static_cast<float>(max_count));
    for (std::int32_t row = 0; row < h; ++row) {
        for (std::int32_t col = 0; col < w; ++col) {
            const auto it = cells_.find(key(x0 + col, ytop - row));
            const std::size_t i = static_cast<std::size_t>(row) * w + col;
            std::uint8_t* px = &img.rgba[i * 4];
            px[3] = 255;
            if (it == cells_.end()) {
                px[0] = 20, px[1] = 0, px[2] = 0;  // a gap: almost black with a red tint
                continue;
            }
            img.counts[i] = it->second;
            // Log-scaled blue -> green -> yellow: sparse cells are visibly weaker than dense ones.
            const float t = std::log1p(static_cast<float>(it->second)) / log_max;
            px[0] = static_cast<std::uint8_t>(255 * std::clamp(2 * t - 1, 0.0f, 1.0f));
            px[1] = static_cast<std::uint8_t>(60 + 195 * std::clamp(2 * t, 0.0f, 1.0f));
            px[2] = static_cast<std::uint8_t>(255 * std::clamp(1 - 2 * t, 0.0f, 1.0f));
        }
    }
    return img;
}

}  // namespace handscan::ui
