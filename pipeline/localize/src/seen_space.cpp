#include "handscan/localize/seen_space.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace handscan::localize {
namespace {

// The 26 directions to a cell's neighbours, unit length.
const std::array<Eigen::Vector3d, 26>& directions() {
    static const std::array<Eigen::Vector3d, 26> dirs = [] {
        std::array<Eigen::Vector3d, 26> d;
        int n = 0;
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x)
                    if (x != 0 || y != 0 || z != 0) d[n++] = Eigen::Vector3d(x, y, z).normalized();
        return d;
    }();
    return dirs;
}

std::uint8_t directionOf(const Eigen::Vector3d& u) {
    const auto& dirs = directions();
    std::size_t best = 0;
    for (std::size_t i = 1; i < dirs.size(); ++i)
        if (dirs[i].dot(u) > dirs[best].dot(u)) best = i;
    return static_cast<std::uint8_t>(best);
}

}  // namespace

SeenSpace::SeenSpace(const Eigen::AlignedBox3d& box, const SeenSpaceConfig& config)
    : box_(box),
      cell_(config.cell_m),
      short_m_(config.short_m),
      into_cos_(std::cos(config.into_deg * std::numbers::pi / 180.0)) {
    if (box.isEmpty()) return;
    const Eigen::Vector3d size = box.sizes();
    auto cellsAt = [&](double c) { return (size / c).array().ceil().max(1.0).prod(); };
    // A box too large for the finest cell gets coarser cells rather than gigabytes.
    while (cellsAt(cell_) > static_cast<double>(config.max_cells)) cell_ *= 1.25;
    dims_ = (size / cell_).array().ceil().max(1.0).cast<int>();
    short_m_ = std::max(short_m_, 3.0 * cell_);
    masks_.assign(static_cast<std::size_t>(dims_.prod()), 0);
}

bool SeenSpace::indexOf(const Eigen::Vector3d& p, std::uint32_t& index) const {
    if (masks_.empty()) return false;
    const Eigen::Vector3d f = ((p - box_.min()) / cell_).array().floor();
    // Compared as doubles first: a far (or non-finite) point must not reach the int conversion.
    if (!(f.array() >= 0.0).all() || !(f.array() < dims_.cast<double>().array()).all())
        return false;
    const Eigen::Vector3i i = f.cast<int>();
    index = static_cast<std::uint32_t>((i.z() * dims_.y() + i.y()) * dims_.x() + i.x());
    return true;
}

void SeenSpace::cellsAlong(const Eigen::Vector3d& origin, const Eigen::Vector3d& end,
                           std::vector<Crossing>& cells) const {
    const double length = (end - origin).norm() - short_m_;
    if (!std::isfinite(length) || length <= 0.0 || masks_.empty()) return;
    const Eigen::Vector3d u = (end - origin).normalized();
    const std::uint8_t dir = directionOf(u);
    // Samples a third of a cell apart: a cell is missed only where the segment clips its corner,
    // which claims less seen space, never more.
    const double step = cell_ / 3.0;
    const auto n = static_cast<int>(std::ceil(length / step));
    std::uint32_t prev = 0;
    bool any = false;
    for (int k = 0; k <= n; ++k) {
        std::uint32_t idx = 0;
        if (!indexOf(origin + std::min(k * step, length) * u, idx) || (any && idx == prev))
            continue;
        prev = idx;
        any = true;
        cells.push_back({idx, dir});
    }
}

void SeenSpace::add(const std::vector<Crossing>& cells) {
    for (const Crossing& c : cells)
        if (c.cell < masks_.size()) masks_[c.cell] |= std::uint32_t{1} << c.direction;
}

void SeenSpace::clear() { std::fill(masks_.begin(), masks_.end(), 0u); }

bool SeenSpace::seenThrough(const Eigen::Vector3d& p, const Eigen::Vector3d& n) const {
    std::uint32_t idx = 0;
    if (!indexOf(p, idx) || masks_[idx] == 0) return false;
    const auto& dirs = directions();
    for (std::size_t i = 0; i < dirs.size(); ++i)
        if ((masks_[idx] >> i & 1u) != 0 && dirs[i].dot(-n) >= into_cos_) return true;
    return false;
}

bool SeenSpace::crossed(const Eigen::Vector3d& p) const {
    std::uint32_t idx = 0;
    return indexOf(p, idx) && masks_[idx] != 0;
}

std::size_t SeenSpace::cellsCrossed() const {
    return static_cast<std::size_t>(
        std::count_if(masks_.begin(), masks_.end(), [](std::uint32_t m) { return m != 0; }));
}

}  // namespace handscan::localize
